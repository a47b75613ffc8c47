//! The API's computations: each takes a parsed request and returns the
//! library's record as JSON (a value, or a record of its own written
//! straight into the answer), or an [`ApiError`]. They are synchronous and
//! run on the blocking pool ([`crate::api`]); nothing here knows HTTP.

use std::collections::BTreeMap;

use fpc::design::{
    optimize, DesignBase, DesignOptions, Requirements, RequirementsError, VARIABLES,
};
use fpc::finger::{Finger, Fold, LoadPathSpec, LoadPoint, Solver, TargetProblem, VALIDITY_SAMPLES};
use fpc::gripper::{Gripper, SphereEnvelope};
use fpc::scene::{PartitionPlan, SceneFile, SceneSolution, SolutionRecord};
use fpc::studies::lift_curve;
use fpc::{Coefficients, Warning};
use serde::{Deserialize, Serialize};
use serde_json::{json, Value};

use crate::errors::ApiError;
use crate::limits::{
    count, scene_toml, MAX_DESIGN_STARTS, MAX_ENVELOPE_RADII, MAX_ENVELOPE_SAMPLES,
    MAX_LIFT_POINTS, MAX_PATH_FORCE_N, MAX_PATH_POINTS,
};

/// The name a scene sent to the API has in its record (`scene_name`).
const SCENE_NAME: &str = "page";

/// A scene: as JSON (`scene`, the keys of a scene file) or as the text of
/// a scene file (`toml`), one of the two.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SceneRequest {
    /// The scene's keys as JSON.
    #[serde(default)]
    pub scene: Option<SceneFile>,
    /// The scene file's text.
    #[serde(default)]
    pub toml: Option<String>,
}

/// `POST /api/lift-curve`: a gripper scene and the number of intervals.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LiftRequest {
    /// The scene's keys as JSON.
    #[serde(default)]
    pub scene: Option<SceneFile>,
    /// The scene file's text.
    #[serde(default)]
    pub toml: Option<String>,
    /// Intervals of the size sweep (the curve has one point more).
    #[serde(default = "default_lift_points")]
    pub points: usize,
}

fn default_lift_points() -> usize {
    40
}

/// `POST /api/envelope`: a gripper scene, the radii and the angles a fresh
/// search scans.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct EnvelopeRequest {
    /// The scene's keys as JSON.
    #[serde(default)]
    pub scene: Option<SceneFile>,
    /// The scene file's text.
    #[serde(default)]
    pub toml: Option<String>,
    /// Radii, equally spaced up to the gripper's largest sphere `r_max`.
    #[serde(default = "default_radii")]
    pub radii: usize,
    /// Grasping angles a fresh search scans.
    #[serde(default = "default_samples")]
    pub samples: usize,
}

fn default_radii() -> usize {
    24
}

fn default_samples() -> usize {
    24
}

/// `POST /api/load-path`: a finger scene, the direction of a growing tip
/// force and how far to follow it.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct LoadPathRequest {
    /// The scene's keys as JSON.
    #[serde(default)]
    pub scene: Option<SceneFile>,
    /// The scene file's text.
    #[serde(default)]
    pub toml: Option<String>,
    /// The force's direction (X, Z) in the finger frame (normalised).
    pub direction: [f64; 2],
    /// The largest force followed to (N).
    pub max_force_n: f64,
    /// The most points returned (the path stops there).
    #[serde(default = "default_path_points")]
    pub max_points: usize,
}

fn default_path_points() -> usize {
    400
}

/// The answer of `POST /api/load-path` ([`load_path`]), written straight
/// into the response: as a JSON value tree, each point took ten times its
/// size in memory.
#[derive(Debug, Serialize)]
pub struct LoadPathAnswer {
    direction: [f64; 2],
    max_force_n: f64,
    valid: bool,
    points: Vec<PathPoint>,
    folds: Vec<Fold>,
    termination: String,
    steps: usize,
}

/// A load path's point: its load, tip and stability, and its findings by
/// kind as `fpc` writes them on stderr ([`Warning::by_kind`]): each kind's
/// count and, in `warnings`, every finding of a kind with few, else the
/// worst. A finger past its limits has one finding per element and kind:
/// kept whole, 5000 points of 1000 elements took most of a gigabyte.
#[derive(Debug, Serialize)]
struct PathPoint {
    force_n: f64,
    tip_mm: [f64; 2],
    stable: bool,
    valid: bool,
    warnings: Vec<Warning>,
    warnings_by_kind: BTreeMap<&'static str, usize>,
}

impl PathPoint {
    fn new(p: &LoadPoint<'_>, warnings: &[Warning]) -> PathPoint {
        let kinds = Warning::by_kind(warnings);
        PathPoint {
            force_n: p.lambda,
            tip_mm: p.tip,
            stable: p.negative_eigenvalues == 0,
            valid: !warnings.iter().any(Warning::is_validity),
            warnings: kinds
                .iter()
                .flat_map(|k| k.kept.iter().map(|&w| w.clone()))
                .collect(),
            warnings_by_kind: kinds.iter().map(|k| (k.kind, k.count)).collect(),
        }
    }
}

/// `POST /api/design`: a requirements file and the optimiser's random
/// starts.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct DesignRequest {
    /// The requirements file's text (the keys of `fpc design`).
    pub toml: String,
    /// Random starts besides the centre and the corners.
    #[serde(default = "default_starts")]
    pub starts: usize,
    /// Optional: the finger to design from, a scene's TOML text (a
    /// calibrated scene, say), as `fpc design --scene` takes it.
    #[serde(default)]
    pub scene: Option<String>,
}

fn default_starts() -> usize {
    2
}

/// The scene file of a request holding `scene` or `toml`.
fn scene_file(scene: Option<SceneFile>, toml: Option<String>) -> Result<SceneFile, ApiError> {
    match (scene, toml) {
        (Some(s), None) => Ok(s),
        (None, Some(t)) => scene_toml("toml", &t),
        (Some(_), Some(_)) => Err(ApiError::bad(
            "scene",
            "give the scene as JSON (`scene`) or as TOML text (`toml`), not both",
        )),
        (None, None) => Err(ApiError::bad(
            "scene",
            "missing: give the scene as JSON (`scene`) or as TOML text (`toml`)",
        )),
    }
}

/// `POST /api/finger`: the finger of the scene (its `[gripper]` section,
/// if any, left out) solved at the scene's load: the record of `fpc solve`
/// (tip, end angle, mid-plane samples `points_mm`, validity, findings, and
/// a calibrated scene's 1-sigma `uncertainty`).
pub fn finger(req: SceneRequest) -> Result<Value, ApiError> {
    let mut file = scene_file(req.scene, req.toml)?;
    file.gripper = None;
    let scene = file.resolve()?;
    let solved = scene.solve()?;
    let u = scene.uncertainty(&solved)?;
    record(&SolutionRecord::new(SCENE_NAME, scene.file(), &solved).with_uncertainty(u.as_ref()))
}

/// `POST /api/grasp`: the gripper scene's grasp, the record of `fpc solve`
/// (`grasp` with the verdict and findings), with the fingers at rest
/// (`rest_points_gripper_mm`) added.
pub fn grasp(req: SceneRequest) -> Result<Value, ApiError> {
    let file = scene_file(req.scene, req.toml)?;
    if file.gripper.is_none() {
        return Err(ApiError::bad(
            "gripper",
            "missing: a grasp needs the scene's [gripper] section",
        ));
    }
    let scene = file.resolve()?;
    let solved = scene.solve()?;
    let u = scene.uncertainty(&solved)?;
    let mut v = record(
        &SolutionRecord::new(SCENE_NAME, scene.file(), &solved).with_uncertainty(u.as_ref()),
    )?;
    if let SceneSolution::Gripper { gripper, .. } = &solved {
        v["rest_points_gripper_mm"] = json!(gripper.rest_shape());
    }
    Ok(v)
}

/// The gripper of a gripper scene (its grasp left out), and the scene's
/// prestrain.
fn gripper_of(file: SceneFile) -> Result<(Gripper, f64), ApiError> {
    let mut file = file;
    match &mut file.gripper {
        Some(g) => g.grasp = None,
        None => {
            return Err(ApiError::bad(
                "gripper",
                "missing: a curve needs the scene's [gripper] section",
            ))
        }
    }
    let scene = file.resolve()?;
    let eps0 = scene.file().actuator.pemc.eps0.unwrap_or(f64::NAN);
    match scene.solve()? {
        SceneSolution::Gripper { gripper, .. } => Ok((*gripper, eps0)),
        SceneSolution::Finger(_) => Err(ApiError::bad(
            "gripper",
            "missing: a curve needs the scene's [gripper] section",
        )),
    }
}

/// `POST /api/lift-curve`: study 1's curve for the scene's gripper, the
/// largest lifting force per finger `f_v = mu F` against the grasping
/// size at grasping angle 0 and zero pressure, from `d_min` to `d_max`.
pub fn lift(req: LiftRequest) -> Result<Value, ApiError> {
    let points = count("points", req.points, 2, MAX_LIFT_POINTS)?;
    let (g, eps0) = gripper_of(scene_file(req.scene, req.toml)?)?;
    let c = lift_curve(&g, eps0, points);
    let pts: Vec<Value> = c
        .points
        .iter()
        .map(|p| {
            json!({
                "size_mm": p.size,
                "tip_gap_mm": p.tip_gap,
                "normal_force_n": p.normal,
                "lift_n": p.lift,
                "height_mm": p.height,
                "reversed": p.reversed,
                "valid": p.invalid.is_none(),
                "invalid": p.invalid,
                "warnings": p.warnings,
            })
        })
        .collect();
    Ok(json!({
        "eps0": c.eps0,
        "mounting_angle_deg": c.mounting_angle.to_degrees(),
        "overlap_mm": c.overlap,
        "palm_mm": c.palm,
        "l0_mm": c.l0,
        "d_min_mm": g.d_min(),
        "d_max_mm": c.d_max,
        "mu": g.mu(),
        "points": pts,
        "dropped": c.dropped,
        "stopped": c.stopped.as_ref().map(|s| json!({"at": s.at, "reason": s.reason})),
        "warnings": c.warnings,
    }))
}

/// `POST /api/envelope`: study 5's sphere envelope for the scene's
/// gripper, the largest lifting force per finger that holds a sphere
/// validly against its radius (the best grasping angle at each radius,
/// zero pressure), on `radii` radii up to `r_max`, with the gripper's
/// own warnings, as the lift curve has them, and the verdict and findings
/// of its finger at rest (outside the model there, no radius can be held
/// validly).
pub fn envelope(req: EnvelopeRequest) -> Result<Value, ApiError> {
    let radii = count("radii", req.radii, 2, MAX_ENVELOPE_RADII)?;
    let samples = count("samples", req.samples, 4, MAX_ENVELOPE_SAMPLES)?;
    let (g, _) = gripper_of(scene_file(req.scene, req.toml)?)?;
    let r_max = g.r_max();
    let mut follower = SphereEnvelope::new(&g, 0.0, samples);
    let mut rows = Vec::with_capacity(radii);
    for i in 1..=radii {
        let r = r_max * i as f64 / radii as f64;
        let best = follower.at(r)?;
        rows.push(json!({ "radius_mm": r, "best": best }));
    }
    Ok(json!({
        "r_max_mm": r_max,
        "pressure_kpa": 0.0,
        "mu": g.mu(),
        "points": rows,
        "counts": follower.counts(),
        "warnings": g.warnings(),
        "rest_valid": !g.reference().warnings.iter().any(Warning::is_validity),
        "rest_warnings": g.reference().warnings,
    }))
}

/// `POST /api/load-path`: the finger of the scene at its load, a tip force
/// along `direction` added and raised from 0 to `max_force_n` by
/// pseudo-arclength continuation, through folds (where the finger snaps
/// under load control), which are located and reported. Every point
/// carries its validity (`valid`, `warnings`: what a solve at that load
/// reports), and the path is `valid` when every point is.
pub fn load_path(req: LoadPathRequest) -> Result<LoadPathAnswer, ApiError> {
    let max_points = count("max_points", req.max_points, 10, MAX_PATH_POINTS)?;
    let [dx, dz] = req.direction;
    let norm = dx.hypot(dz);
    if !(norm.is_finite() && norm > 0.0) {
        return Err(ApiError::bad(
            "direction",
            "direction: must be a finite, non-zero (X, Z) vector",
        ));
    }
    let max_force = req.max_force_n;
    if !(max_force > 0.0 && max_force <= MAX_PATH_FORCE_N) {
        return Err(ApiError::bad(
            "max_force_n",
            format!("max_force_n = {max_force}: must lie in (0, {MAX_PATH_FORCE_N}] N"),
        ));
    }
    let mut file = scene_file(req.scene, req.toml)?;
    file.gripper = None;
    let scene = file.resolve()?;
    let PartitionPlan::Fixed(part) = &scene.partition else {
        return Err(ApiError::bad(
            "partition.elements",
            "a load path needs a fixed partition (a number of elements)",
        ));
    };
    let finger = Finger::with_model(scene.model, &scene.actuator, part, true);
    let opts = fpc::SolveOptions {
        stability: true,
        ..scene.options
    };
    let start = finger.solve(&scene.load, &opts)?;
    let direction = [dx / norm, dz / norm];
    let spec = LoadPathSpec {
        problem: TargetProblem {
            base: scene.load,
            direction,
            weights: [1.0, 0.0],
            target: 0.0,
        },
        lambda0: 0.0,
        increasing: true,
        lambda_end: Some(max_force),
        lambda_scale: 1.0,
        events: true,
    };
    let mut points = Vec::new();
    let mut refused = None;
    let per = finger.unknowns_per_element();
    let path = Solver::new(&finger).follow_load(&spec, &start.coefficients, &opts, &mut |p| {
        // the findings a solve at this load reports: the same verdict
        let findings = Coefficients::new(per, p.coefficients.to_vec())
            .and_then(|k| finger.validity(&k, VALIDITY_SAMPLES));
        match findings {
            Ok(warnings) => points.push(PathPoint::new(p, &warnings)),
            Err(e) => refused = Some(e),
        }
        refused.is_none() && points.len() < max_points
    })?;
    if let Some(e) = refused {
        return Err(e.into());
    }
    Ok(LoadPathAnswer {
        direction,
        max_force_n: max_force,
        valid: points.iter().all(|p| p.valid),
        points,
        folds: path.folds,
        termination: format!("{:?}", path.termination),
        steps: path.steps,
    })
}

/// `POST /api/design`: `fpc design` on the requirements, the keys of its
/// `design.json` (without the provenance).
pub fn design(req: DesignRequest) -> Result<Value, ApiError> {
    let starts = count("starts", req.starts, 0, MAX_DESIGN_STARTS)?;
    let mut r = Requirements::parse(&req.toml).map_err(|e| match &e {
        RequirementsError::Syntax(s) => ApiError::bad("toml", s.to_string()),
        // the message starts with where the text writes the value, as a
        // syntax error's does
        RequirementsError::Input(i) => {
            let mut err = ApiError::from(i.clone());
            if let Some((line, col)) = e.position(&req.toml) {
                err.message = format!("{line}:{col}: {}", err.message);
            }
            err
        }
    })?;
    if let Some(text) = &req.scene {
        let file = scene_toml("scene", text)?;
        let base = file.resolve()?;
        r = r.with_base(DesignBase::from_scene(&base, "the request's scene"));
    }
    let opts = DesignOptions {
        random_starts: starts,
        ..DesignOptions::default()
    };
    let d = optimize(&r, &opts)?;
    let b = r.bounds();
    let varied: Vec<&str> = VARIABLES
        .iter()
        .zip(b)
        .filter(|(_, b)| b[1] > b[0])
        .map(|(n, _)| *n)
        .collect();
    Ok(json!({
        "feasible": d.feasible,
        "design": {
            "eps0": d.best.design[0],
            "mounting_angle_deg": d.best.design[1],
            "overlap_mm": d.best.design[2],
            "varied": varied,
        },
        "worst_margin": d.best.worst,
        "limiting": d.best.worst_margin(),
        "margins": d.best.margins,
        "sensitivities": d.sensitivities,
        "evaluations": d.evaluations,
        "starts": d.starts,
        "failure": d.failure,
        "scenes": d.reproductions,
        "notes": r.notes(),
    }))
}

fn record(r: &impl serde::Serialize) -> Result<Value, ApiError> {
    serde_json::to_value(r).map_err(|e| ApiError::internal(format!("cannot write the record: {e}")))
}

//! The record of a solved scene: what `fpc solve` writes to
//! `solution.json` and the Python module's `solve_scene` returns, built
//! once here so the two cannot drift apart.

use serde::Serialize;

use super::fields::{degrees, warning_text};
use super::schema::SceneFile;
use super::solve::{GraspOutcome, SceneSolution};
use super::uncertainty::Uncertainty;
use crate::coefficients::Coefficients;
use crate::error::Warning;
use crate::finger::{Solution, SolveReport};
use crate::gripper::{Gripper, Invalid, Verdict};
use crate::plan::RefinementRecord;

/// What `fpc solve` writes to `solution.json` (without its provenance) and
/// `fpc.solve_scene` returns: the finger's equilibrium under the keys of
/// `fpc finger --json`, the run's keys, every finding typed, and in a
/// gripper scene the gripper and its grasp. Built by
/// [`SolutionRecord::new`]; serialize it (serde) for the JSON.
#[derive(Serialize)]
pub struct SolutionRecord<'a> {
    /// The scene file's name without its extension.
    scene_name: &'a str,
    /// `finger`, `gripper` (no grasp asked) or `grasp`.
    kind: &'static str,
    /// The number of elements used.
    elements: usize,
    /// With `tip_tol_mm`: the estimated error (mm) of `refinement`'s tip
    /// (the extrapolated one when extrapolated); null otherwise.
    tip_error_estimate_mm: Option<f64>,
    /// With `tip_tol_mm`: the levels solved and the best tip, under the
    /// keys of `fpc finger --json`'s `refinement`; the solution's keys
    /// below are the finest level's.
    #[serde(skip_serializing_if = "Option::is_none")]
    refinement: Option<&'a RefinementRecord>,
    /// The finger's equilibrium: the grasp's, or the gripper's rest state.
    #[serde(flatten)]
    solution: SolutionKeys<'a>,
    /// The one verdict: for a grasp, the grasp's (`grasp.valid`); for a
    /// finger or a gripper without a grasp, no finding puts the answer
    /// outside the model ([`Warning::is_validity`]).
    validity: bool,
    /// Every warning once ([`SceneSolution::warnings`]), as
    /// `{kind, message, element?, value?, limit?}`.
    warnings: Vec<Warning>,
    /// The same warnings as text naming the scene's keys (as on stderr).
    warning_messages: Vec<String>,
    /// The scene with every default written out.
    scene: &'a SceneFile,
    /// A gripper scene's keys (absent in a finger scene).
    #[serde(flatten)]
    gripper: Option<GripperKeys<'a>>,
    /// 1-sigma uncertainties from the scene's `[calibration]` covariance
    /// (absent without one): [`SolutionRecord::with_uncertainty`].
    #[serde(skip_serializing_if = "Option::is_none")]
    uncertainty: Option<&'a Uncertainty>,
}

/// The keys of a [`Solution`] but its `warnings` (the scene's
/// [`SolutionRecord`]'s `warnings` hold them with the gripper's and the
/// grasp's). A test keeps the two key lists in step.
#[derive(Serialize)]
pub(crate) struct SolutionKeys<'a> {
    /// Tip (X, Z) in the finger frame (mm).
    tip_mm: &'a [f64; 2],
    /// Tip tangent angle from the X axis (rad).
    end_angle_rad: f64,
    /// Least-squares circle radius (mm); null when straight or not sampled.
    radius_mm: Option<f64>,
    /// Total potential energy (N mm).
    energy_nmm: f64,
    /// Negative Hessian eigenvalues; null when not computed.
    negative_eigenvalues: Option<usize>,
    /// `negative_eigenvalues == 0`; null when not computed.
    stable: Option<bool>,
    /// The element unknowns, one array per element.
    coefficients: &'a Coefficients,
    /// Mid-plane samples, root to tip, in the finger frame (mm).
    points_mm: &'a [[f64; 2]],
    /// Undeformed element lengths, root to tip (mm).
    element_lengths_mm: &'a [f64],
    /// How the solve went.
    report: &'a SolveReport,
}

impl<'a> SolutionKeys<'a> {
    pub(crate) fn of(s: &'a Solution) -> SolutionKeys<'a> {
        SolutionKeys {
            tip_mm: &s.tip,
            end_angle_rad: s.end_angle,
            radius_mm: s.radius,
            energy_nmm: s.energy,
            negative_eigenvalues: s.negative_eigenvalues,
            stable: s.stable,
            coefficients: &s.coefficients,
            points_mm: &s.points,
            element_lengths_mm: &s.element_lengths,
            report: &s.report,
        }
    }
}

/// The keys only a gripper scene has.
#[derive(Serialize)]
struct GripperKeys<'a> {
    /// The design and the geometry its rest state fixes.
    gripper: GripperJson<'a>,
    /// The grasp; null when none was asked.
    grasp: Option<GraspJson<'a>>,
    /// `points_mm` in the gripper frame (mm; Zg down).
    points_gripper_mm: Vec<[f64; 2]>,
}

/// The gripper: the library's keys (`params`, `model`, `elements`,
/// `l0_mm`, `palm_mm`, `overlap_mm`, `d_min_mm`, `d_max_mm`, `r_max_mm`,
/// `tip_is_innermost`, `rest_tip_gripper_mm`, `warnings`) and three of its
/// design's at the top.
#[derive(Serialize)]
pub struct GripperJson<'a> {
    /// The mounting angle `a` (deg).
    mounting_angle_deg: f64,
    /// Friction coefficient between object and tip.
    mu: f64,
    /// Number of fingers.
    fingers: usize,
    #[serde(flatten)]
    gripper: &'a Gripper,
}

/// A solved grasp, per finger.
#[derive(Serialize)]
pub struct GraspJson<'a> {
    /// `cuboid`, `size` or `sphere`.
    kind: &'static str,
    /// Channel pressure (kPa).
    pressure_kpa: f64,
    /// Grasping angle `b` (deg).
    beta_deg: f64,
    /// Normal force `F` on the finger (N).
    normal_force_n: f64,
    /// Friction `f` on the finger (N).
    friction_n: f64,
    /// The friction cone's limit `mu F` (N).
    friction_limit_n: f64,
    /// Lifting force `f_v` (N).
    lift_n: f64,
    /// Grasping size `d` (mm).
    size_mm: f64,
    /// Gap between the tips (mm).
    tip_gap_mm: f64,
    /// Finger height `h`, the tip's Zg (mm).
    height_mm: f64,
    /// Tip in the gripper frame (mm).
    tip_gripper_mm: [f64; 2],
    /// The contact load on the tip, (Fx, Fz) in the finger frame (N).
    tip_load_finger_n: [f64; 2],
    /// The one verdict: the rules hold, the finger is inside the model, the
    /// grasp is stable and on the loading path (`verdict` has the parts).
    valid: bool,
    /// The first reason it is not valid, `{kind, message}`; null when valid.
    invalid: Option<Invalid>,
    /// The verdict's parts: `rules` (the first rule broken or null),
    /// `findings` (the finger's validity findings), `stability`
    /// (`{kind: stable | unstable | unknown | not_judged}`) and `path`
    /// (`{from, steps}`: how the equilibrium was reached from rest).
    verdict: &'a Verdict,
    /// A sphere's radius (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    sphere_radius_mm: Option<f64>,
    /// A sphere's centre in the gripper frame (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    sphere_center_gripper_mm: Option<[f64; 2]>,
}

impl<'a> SolutionRecord<'a> {
    /// The record of `solved`, the solution of the scene `file` named
    /// `stem` (the file's name without its extension).
    pub fn new(
        stem: &'a str,
        file: &'a SceneFile,
        solved: &'a SceneSolution,
    ) -> SolutionRecord<'a> {
        let warnings = solved.warnings();
        let (kind, tip_error_estimate_mm, refinement, gripper) = match solved {
            SceneSolution::Finger(s) => (
                "finger",
                s.estimated_tip_error_mm(),
                s.refinement.as_ref(),
                None,
            ),
            SceneSolution::Gripper { gripper, grasp } => (
                if grasp.is_some() { "grasp" } else { "gripper" },
                None,
                None,
                Some(GripperKeys {
                    gripper: GripperJson::of(gripper),
                    grasp: grasp.as_deref().map(|o| GraspJson::of(gripper, o)),
                    points_gripper_mm: solved
                        .solution()
                        .points
                        .iter()
                        .map(|&p| gripper.to_gripper(p))
                        .collect(),
                }),
            ),
        };
        SolutionRecord {
            scene_name: stem,
            kind,
            elements: solved.elements(),
            tip_error_estimate_mm,
            refinement,
            solution: SolutionKeys::of(solved.solution()),
            validity: is_valid(solved, &warnings),
            warning_messages: warnings.iter().map(warning_text).collect(),
            warnings,
            scene: file,
            gripper,
            uncertainty: None,
        }
    }

    /// The record with the solution's uncertainties
    /// ([`Scene::uncertainty`](crate::scene::Scene::uncertainty)) under
    /// `uncertainty`; `None` leaves the record as it was.
    pub fn with_uncertainty(mut self, u: Option<&'a Uncertainty>) -> SolutionRecord<'a> {
        self.uncertainty = u;
        self
    }
}

/// The one verdict: a grasp's own, else no validity finding.
fn is_valid(solved: &SceneSolution, warnings: &[Warning]) -> bool {
    match solved {
        SceneSolution::Gripper { grasp: Some(g), .. } => g.is_valid(),
        _ => !warnings.iter().any(Warning::is_validity),
    }
}

impl<'a> GripperJson<'a> {
    /// The keys of `gripper`.
    pub fn of(gripper: &'a Gripper) -> GripperJson<'a> {
        GripperJson {
            mounting_angle_deg: degrees(gripper.mounting_angle()),
            mu: gripper.mu(),
            fingers: gripper.params().fingers,
            gripper,
        }
    }
}

impl<'a> GraspJson<'a> {
    /// The keys of the grasp `o` of `gripper`.
    pub fn of(gripper: &Gripper, o: &'a GraspOutcome) -> GraspJson<'a> {
        let g = &o.grasp;
        GraspJson {
            kind: o.spec.name(),
            pressure_kpa: g.pressure_kpa,
            beta_deg: degrees(g.beta),
            normal_force_n: g.normal,
            friction_n: g.friction,
            friction_limit_n: gripper.mu() * g.normal,
            lift_n: g.lift,
            size_mm: g.size,
            tip_gap_mm: g.tip_gap,
            height_mm: g.height,
            tip_gripper_mm: g.tip,
            tip_load_finger_n: [g.load.fx, g.load.fz],
            valid: o.is_valid(),
            invalid: o.invalid(),
            verdict: &g.verdict,
            sphere_radius_mm: o.sphere.as_ref().map(|s| s.radius),
            sphere_center_gripper_mm: o.sphere.as_ref().map(|s| s.center),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn keys(v: serde_json::Value) -> Vec<String> {
        let mut k: Vec<String> = v.as_object().unwrap().keys().cloned().collect();
        k.sort();
        k
    }

    #[test]
    fn the_solution_keys_are_the_solutions() {
        // every key of the library's Solution but `warnings`, which the
        // record holds for the whole scene
        let sol = crate::Scene::from_toml("").unwrap().solve().unwrap();
        let mut ours = keys(serde_json::to_value(SolutionKeys::of(sol.solution())).unwrap());
        ours.push("warnings".into());
        ours.sort();
        assert_eq!(ours, keys(serde_json::to_value(sol.solution()).unwrap()));
    }
}

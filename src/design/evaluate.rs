//! A design's margins: every requirement as normalised margins, each
//! grasp solved through the ordinary gripper path (module docs of
//! [`crate::design`]).

use serde::Serialize;

use crate::actuator::Actuator;
use crate::error::Warning;
use crate::finger::{Load, SolveOptions};
use crate::gripper::{EnvelopeSeed, Gripper, Object, SphereEnvelope};
use crate::scene::{
    CalibrationSection, Elements, GraspKind as SceneGrasp, GraspSection, GripperSection, SceneFile,
};
use crate::sensitivity::GraspKind;

use super::best_grasp::{BestGradient, Turn};
use super::requirements::{ObjectRequirement, OpenRequirement, Requirements};
use super::variables::{actuator, design_gradient, gripper, MarginGradient, DESIGN_PARAMS};

/// Widths sampled per cuboid requirement.
pub const CUBOID_SAMPLES: usize = 5;

/// Radii sampled per sphere requirement.
pub const SPHERE_SAMPLES: usize = 3;

/// Grasping angles scanned per sphere radius (then refined by Brent).
const SPHERE_ANGLE_SAMPLES: usize = 8;

/// The margin of a requirement a design cannot even be built for (the
/// overlap beyond the finger's reach, an angle outside (0, 180), fingers
/// that do not fit around the palm): below -1, the margin of a grasp
/// that holds nothing, and below every margin of a gripper that can be
/// built (see `beyond_minus_one`), so that a gripper that can be built
/// always ranks above one that cannot, and a least-violating design is
/// one to build.
pub const UNBUILDABLE_MARGIN: f64 = -2.0;

/// A margin of a gripper that can be built, and the factor its gradient
/// takes: as it is at -1 and above; below, a requirement missed by more
/// than itself (a normal force three times its limit, a lift against the
/// weight, a required opening wider than the gripper's closed gap), it is
/// compressed into (-2, -1) as `-2 + 1 / (-m)`: monotone, with value and
/// slope continuous at -1, so the search ranks the designs as before, but
/// never at or below [`UNBUILDABLE_MARGIN`] (a margin normalised by a
/// small limit can be far below -2; the requirements' bounds keep it
/// above -1e10, far from the -1e15 where the compression would round to
/// -2).
fn beyond_minus_one(m: f64) -> (f64, f64) {
    if m >= -1.0 || m.is_nan() {
        return (m, 1.0);
    }
    let r = 1.0 / -m;
    (-2.0 + r, r * r)
}

/// One requirement's margin at a design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Margin {
    /// Which requirement: `object[0] cuboid d = 60 mm: lift`, `open`, ...
    pub requirement: String,
    /// The normalised margin (>= 0: met).
    pub margin: f64,
    /// The quantity and its limit, in words.
    pub detail: String,
    /// The sampled width or radius (mm), for an object's margin.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub at_mm: Option<f64>,
    /// The grasping angle of a sphere grasp (degrees).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub beta_deg: Option<f64>,
    /// The quantity the margin measures (a lift or a normal force in N, an
    /// opening in mm), where there is one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub value: Option<f64>,
    /// The normal force of the grasp behind an object's margin (N).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub normal_n: Option<f64>,
    /// Whether the grasp behind an object's margin is valid (the one
    /// verdict); an invalid grasp holds nothing.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub valid: Option<bool>,
    /// The notes of the solution behind the margin that do not make it
    /// invalid ([`Warning::is_validity`] false: an element bent backwards outside strict mode,
    /// the actuator's notes), in words: every sample's, not only the
    /// hardest one's, so that a claim is never read without them.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub notes: Vec<String>,
}

/// The findings of `warnings` that do not make an answer invalid
/// ([`Warning::is_validity`]), in words: what a margin and a reproduced
/// scene carry beside their verdict.
pub(crate) fn notes(warnings: &[Warning]) -> Vec<String> {
    warnings
        .iter()
        .filter(|w| !w.is_validity())
        .map(|w| w.to_string())
        .collect()
}

/// All margins of a design.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Evaluation {
    /// The design `(eps0, mounting angle deg, overlap mm)`.
    pub design: [f64; 3],
    /// Every margin.
    pub margins: Vec<Margin>,
    /// The smallest margin (the design meets every requirement when it is
    /// at least 0).
    pub worst: f64,
}

impl Evaluation {
    /// True when every requirement is met.
    pub fn feasible(&self) -> bool {
        self.worst >= 0.0
    }

    /// The requirement with the smallest margin.
    pub fn worst_margin(&self) -> Option<&Margin> {
        self.margins
            .iter()
            .min_by(|a, b| a.margin.total_cmp(&b.margin))
    }

    /// Object `i`'s smallest lift margin: the hardest sample, whose grasp
    /// its scene file reproduces ([`Evaluation::scenes`]).
    pub fn hardest_lift(&self, i: usize) -> Option<&Margin> {
        self.hardest_where(i, |m| m.requirement.ends_with("lift"))
    }

    /// The smallest margin of any kind of object `i` (fits, lift, gentle).
    pub fn hardest(&self, i: usize) -> Option<&Margin> {
        self.hardest_where(i, |_| true)
    }

    fn hardest_where(&self, i: usize, keep: impl Fn(&Margin) -> bool) -> Option<&Margin> {
        let prefix = format!("object[{i}] ");
        self.margins
            .iter()
            .filter(|m| m.requirement.starts_with(&prefix) && keep(m))
            .min_by(|a, b| a.margin.total_cmp(&b.margin))
    }

    /// One scene file per object (a file name and its TOML text) that `fpc
    /// solve` runs to reproduce this design's grasp of it at its hardest
    /// sample (the width or radius with the smallest lift margin).
    pub fn scenes(&self, req: &Requirements) -> Vec<(String, String)> {
        let x = self.design;
        // the base scene's model, actuator and calibration (its partition,
        // load and solver settings are not a gripper scene's), else the
        // paper's actuator
        let mut file = match &req.base {
            Some(b) => SceneFile {
                model: b.file.model.clone(),
                actuator: b.file.actuator.clone(),
                calibration: b.file.calibration.clone().and_then(for_gripper),
                ..SceneFile::default()
            },
            None => SceneFile::default(),
        };
        file.actuator.pemc.eps0 = Some(x[0]);
        file.partition.elements = Some(Elements::Count(req.elements));
        let from = req
            .base
            .as_ref()
            .map(|b| format!(" from {}", b.source))
            .unwrap_or_default();
        let head = format!(
            "# generated by fpc design{from}: eps0 = {}, mounting angle = {} deg, overlap = {} mm\n\n",
            x[0], x[1], x[2]
        );
        let mut out = Vec::new();
        for (i, o) in req.objects.iter().enumerate() {
            let m = self.hardest_lift(i);
            let (name, grasp) = match o {
                ObjectRequirement::Cuboid { size_mm, .. } => (
                    format!("object{i}_cuboid.toml"),
                    GraspSection {
                        kind: Some(SceneGrasp::Size),
                        d_mm: Some(m.and_then(|m| m.at_mm).unwrap_or(size_mm[1])),
                        beta_deg: Some(0.0),
                        pressure_kpa: Some(0.0),
                        ..GraspSection::default()
                    },
                ),
                ObjectRequirement::Sphere {
                    radius_mm, lift_n, ..
                } => (
                    format!("object{i}_sphere.toml"),
                    GraspSection {
                        kind: Some(SceneGrasp::Sphere),
                        r_mm: Some(m.and_then(|m| m.at_mm).unwrap_or(radius_mm[1])),
                        // the claimed grasp lifts its best f_v (friction at
                        // its limit); the required lift if none was found
                        lift_n: Some(m.and_then(|m| m.value).unwrap_or(*lift_n)),
                        beta_deg: Some(m.and_then(|m| m.beta_deg).unwrap_or(20.0)),
                        pressure_kpa: Some(0.0),
                        ..GraspSection::default()
                    },
                ),
            };
            file.gripper = Some(GripperSection {
                mounting_angle_deg: Some(x[1]),
                overlap_mm: Some(x[2]),
                palm_mm: None,
                fingers: Some(req.fingers),
                mu: Some(req.mu),
                strict: Some(req.strict),
                grasp: Some(grasp),
            });
            // the scene types serialise to TOML without fail; were one not
            // to, the reproduction reports the unreadable scene
            let body = file
                .to_toml()
                .unwrap_or_else(|e| format!("# the scene could not be written: {e}\n"));
            out.push((name, format!("{head}{body}")));
        }
        out
    }
}

/// A `[calibration]` table as a gripper scene takes it: without
/// `load.kappa` (grasps are solved at kappa's default), whose row and
/// column are dropped from the covariance (the remaining keys' marginal
/// covariance); `None` when no key is left.
fn for_gripper(mut c: CalibrationSection) -> Option<CalibrationSection> {
    let kappa = crate::sensitivity::Param::Kappa.name();
    let keep: Vec<usize> = (0..c.parameters.len())
        .filter(|&i| c.parameters[i] != kappa)
        .collect();
    if keep.is_empty() {
        return None;
    }
    let pick = |v: &[f64]| keep.iter().filter_map(|&i| v.get(i).copied()).collect();
    c.standard_errors = c.standard_errors.as_deref().map(pick);
    c.covariance = c.covariance.as_ref().map(|m| {
        keep.iter()
            .filter_map(|&i| m.get(i).map(|row| pick(row)))
            .collect()
    });
    c.parameters = keep.iter().map(|&i| c.parameters[i].clone()).collect();
    Some(c)
}

/// The sample points `[a, b]` split into `n` (both ends; one point if equal).
fn samples(range: [f64; 2], n: usize) -> Vec<f64> {
    if range[0] == range[1] || n < 2 {
        return vec![range[0]];
    }
    (0..n)
        .map(|i| range[0] + (range[1] - range[0]) * i as f64 / (n - 1) as f64)
        .collect()
}

/// The margins of every requirement at design `x`. A design that cannot
/// be built gets [`UNBUILDABLE_MARGIN`] for every requirement; a grasp
/// that cannot be solved counts as not held.
pub fn evaluate(req: &Requirements, x: [f64; 3]) -> Evaluation {
    evaluate_inner(req, x, false, None).0
}

/// Where each sphere requirement's best grasping angle lay at its first
/// radius in the last design evaluated along a search, by object index:
/// the next trial's envelope starts from there
/// ([`SphereEnvelope::seeded`]) instead of searching the angle afresh.
#[derive(Debug, Clone, Default)]
pub(crate) struct Seeds(Vec<Option<EnvelopeSeed>>);

impl Seeds {
    fn get(&self, object: usize) -> Option<EnvelopeSeed> {
        self.0.get(object).copied().flatten()
    }

    /// Objects whose last optimum was followed from its seed, not
    /// searched afresh.
    #[cfg(test)]
    pub(crate) fn followed(&self) -> usize {
        self.0.iter().flatten().filter(|s| s.followed()).count()
    }

    fn set(&mut self, object: usize, seed: Option<EnvelopeSeed>) {
        if self.0.len() <= object {
            self.0.resize(object + 1, None);
        }
        self.0[object] = seed;
    }
}

/// [`evaluate`] (with every margin's gradient if `gradients`), each
/// sphere's envelope started from `seeds` and leaving its own there. The
/// margins are those of the same ordinary grasps: a seed only predicts
/// the angle, which is corrected and verified as any followed radius is
/// (a fresh search where that fails); but the optimum so followed is the
/// seed's local one, so a search reports its final design from a fresh
/// [`evaluate`].
pub(crate) fn evaluate_seeded(
    req: &Requirements,
    x: [f64; 3],
    gradients: bool,
    seeds: &mut Seeds,
) -> (Evaluation, Vec<MarginGradient>) {
    evaluate_inner(req, x, gradients, Some(seeds))
}

/// [`evaluate`] with every margin's [`MarginGradient`], in the same order.
pub(crate) fn evaluate_with_gradients(
    req: &Requirements,
    x: [f64; 3],
) -> (Evaluation, Vec<MarginGradient>) {
    evaluate_inner(req, x, true, None)
}

/// What the margin functions collect: the margins, and, when asked for,
/// their gradients (the actuator the gripper was built from).
struct Collect<'a> {
    margins: Vec<Margin>,
    grads: Vec<MarginGradient>,
    actuator: Option<&'a Actuator>,
}

impl Collect<'_> {
    /// A margin with its gradient, compressed below -1
    /// ([`beyond_minus_one`]).
    fn push(&mut self, mut m: Margin, g: impl FnOnce(&Actuator) -> Option<MarginGradient>) {
        let slope;
        (m.margin, slope) = beyond_minus_one(m.margin);
        let grad = self.actuator.and_then(g).unwrap_or([None; 3]);
        self.margins.push(m);
        self.grads.push(scaled(grad, slope));
    }

    /// A margin with no answer behind it (an unbuildable gripper, a grasp
    /// or an opening that failed): `margin` and `detail` say why; no value,
    /// no verdict, no notes, and a zero gradient, as a constant margin's.
    fn failed(
        &mut self,
        requirement: String,
        margin: f64,
        detail: String,
        at_mm: Option<f64>,
        beta_deg: Option<f64>,
    ) {
        let m = Margin {
            requirement,
            margin,
            detail,
            at_mm,
            beta_deg,
            value: None,
            normal_n: None,
            valid: None,
            notes: Vec::new(),
        };
        // as given, not compressed: -1 (nothing held) or UNBUILDABLE_MARGIN
        let grad = self.actuator.map_or([None; 3], |_| [Some(0.0); 3]);
        self.margins.push(m);
        self.grads.push(grad);
    }
}

fn evaluate_inner(
    req: &Requirements,
    x: [f64; 3],
    gradients: bool,
    mut seeds: Option<&mut Seeds>,
) -> (Evaluation, Vec<MarginGradient>) {
    let act = actuator(req, x[0]).ok();
    let mut c = Collect {
        margins: Vec::new(),
        grads: Vec::new(),
        actuator: if gradients { act.as_ref() } else { None },
    };
    match gripper(req, x) {
        Err(e) => c.failed(
            "buildable".into(),
            UNBUILDABLE_MARGIN,
            e.to_string(),
            None,
            None,
        ),
        Ok(g) => {
            for (i, o) in req.objects.iter().enumerate() {
                match o {
                    ObjectRequirement::Cuboid {
                        size_mm,
                        lift_n,
                        max_normal_n,
                    } => cuboid_margins(&g, i, *size_mm, *lift_n, *max_normal_n, &mut c),
                    ObjectRequirement::Sphere {
                        radius_mm,
                        lift_n,
                        max_normal_n,
                    } => {
                        let seed = seeds.as_ref().and_then(|s| s.get(i));
                        let sphere = SphereRequirement {
                            index: i,
                            radius: *radius_mm,
                            lift: *lift_n,
                            max_normal: *max_normal_n,
                        };
                        let left = sphere_margins(&g, (req, x), &sphere, seed, &mut c);
                        if let Some(s) = seeds.as_deref_mut() {
                            s.set(i, left);
                        }
                    }
                }
            }
            if let Some(open) = &req.open {
                open_margin(&g, open, req.base.as_ref().map(|b| b.kappa), &mut c);
            }
        }
    }
    let worst = c
        .margins
        .iter()
        .map(|m| m.margin)
        .fold(f64::INFINITY, f64::min);
    (
        Evaluation {
            design: x,
            margins: c.margins,
            worst,
        },
        c.grads,
    )
}

fn cuboid_margins(
    g: &Gripper,
    i: usize,
    size: [f64; 2],
    lift: f64,
    max_normal: Option<f64>,
    out: &mut Collect<'_>,
) {
    let mut warm = None;
    for d in samples(size, CUBOID_SAMPLES) {
        let name = |what: &str| format!("object[{i}] cuboid d = {d:.1} mm: {what}");
        let d_max = g.d_max();
        if d > d_max {
            out.push(
                Margin {
                    requirement: name("fits"),
                    margin: (d_max - d) / d,
                    detail: format!("d_max = {d_max:.2} mm"),
                    at_mm: Some(d),
                    beta_deg: None,
                    value: Some(d_max),
                    normal_n: None,
                    valid: None,
                    notes: Vec::new(),
                },
                |act| {
                    let rows = g.geometry_sensitivities(act, &DESIGN_PARAMS).ok()?;
                    Some(design_gradient(
                        [rows[0].d_max, rows[1].d_max, rows[2].d_max],
                        1.0 / d,
                    ))
                },
            );
            continue;
        }
        match g.size_grasp(0.0, d, 0.0, Object::Face, warm.as_ref(), false) {
            Ok(gr) => {
                let held = gr.lift;
                let mut m = (held - lift) / lift;
                let mut detail = format!("f_v = {held:.4} N for {lift} N (F = {:.4} N)", gr.normal);
                let mut clamped = false;
                if let Some(inv) = gr.invalid() {
                    // an invalid grasp holds nothing, whatever its force
                    clamped = m > -0.1;
                    m = m.min(-0.1);
                    detail = format!("{detail}; invalid: {inv}");
                }
                let sens = |act: &Actuator| {
                    g.grasp_sensitivities(act, &gr, GraspKind::Size { d }, &DESIGN_PARAMS)
                        .ok()
                };
                out.push(
                    Margin {
                        requirement: name("lift"),
                        margin: m,
                        detail,
                        at_mm: Some(d),
                        beta_deg: Some(0.0),
                        value: Some(held),
                        normal_n: Some(gr.normal),
                        valid: Some(gr.is_valid()),
                        notes: notes(&gr.warnings),
                    },
                    |act| {
                        if clamped {
                            return Some([Some(0.0); 3]);
                        }
                        let s = sens(act)?;
                        let r = &s.rows;
                        Some(design_gradient(
                            [r[0].lift, r[1].lift, r[2].lift],
                            1.0 / lift,
                        ))
                    },
                );
                if let Some(fmax) = max_normal {
                    out.push(
                        gentle_margin(name("gentle"), fmax, gr.normal, (d, 0.0), &gr.warnings),
                        |act| {
                            let s = sens(act)?;
                            let r = &s.rows;
                            Some(design_gradient(
                                [r[0].normal, r[1].normal, r[2].normal],
                                -1.0 / fmax,
                            ))
                        },
                    );
                }
                warm = Some(gr);
            }
            Err(e) => {
                out.failed(
                    name("lift"),
                    -1.0,
                    format!("no grasp: {e}"),
                    Some(d),
                    Some(0.0),
                );
                warm = None;
            }
        }
    }
}

/// One sphere requirement of [`sphere_margins`].
struct SphereRequirement {
    /// The object's index.
    index: usize,
    /// The radii that must be held (mm).
    radius: [f64; 2],
    /// Lifting force per finger (N).
    lift: f64,
    /// Largest normal force (N), if limited.
    max_normal: Option<f64>,
}

/// The sphere requirement's margins; its first radius predicted from
/// `seed` if given. Returns the seed it leaves: its optimum at the first
/// radius. `design` is the requirements and the design `g` was built from
/// (for the gradients at the turn of closing from rest, [`Turn`]).
fn sphere_margins(
    g: &Gripper,
    design: (&Requirements, [f64; 3]),
    sphere: &SphereRequirement,
    seed: Option<EnvelopeSeed>,
    out: &mut Collect<'_>,
) -> Option<EnvelopeSeed> {
    let SphereRequirement {
        index: i,
        radius,
        lift,
        max_normal,
    } = *sphere;
    // the radii after the first continued from those before
    let mut follower = SphereEnvelope::new(g, 0.0, SPHERE_ANGLE_SAMPLES).seeded(seed);
    let radii = samples(radius, SPHERE_SAMPLES);
    // the turn of closing from rest and its rate, shared by the radii
    let turn = Turn::new(g, design);
    for &r in &radii {
        let name = |what: &str| format!("object[{i}] sphere r = {r:.1} mm: {what}");
        match follower.at(r) {
            Ok(Some(best)) => {
                let grads = std::cell::OnceCell::new();
                let grads =
                    |act: &Actuator| *grads.get_or_init(|| BestGradient::at(g, act, &best, &turn));
                out.push(
                    Margin {
                        requirement: name("lift"),
                        margin: (best.lift - lift) / lift,
                        detail: format!(
                            "best f_v = {:.4} N at b = {:.2} deg for {lift} N",
                            best.lift,
                            best.beta.to_degrees()
                        ),
                        at_mm: Some(r),
                        beta_deg: Some(best.beta.to_degrees()),
                        value: Some(best.lift),
                        normal_n: Some(best.normal),
                        valid: Some(true),
                        notes: notes(&best.warnings),
                    },
                    |act| grads(act).map(|b| scaled(b.lift, 1.0 / lift)),
                );
                if let Some(fmax) = max_normal {
                    out.push(
                        gentle_margin(
                            name("gentle"),
                            fmax,
                            best.normal,
                            (r, best.beta.to_degrees()),
                            &best.warnings,
                        ),
                        |act| grads(act).map(|b| scaled(b.normal, -1.0 / fmax)),
                    );
                }
            }
            Ok(None) => out.failed(
                name("lift"),
                -1.0,
                "no valid grasp at any angle".into(),
                Some(r),
                None,
            ),
            Err(e) => out.failed(name("lift"), -1.0, format!("no grasp: {e}"), Some(r), None),
        }
    }
    radii.first().and_then(|&r| follower.seed_at(r))
}

/// A gradient over the design variables, each component scaled by `factor`.
fn scaled(g: MarginGradient, factor: f64) -> MarginGradient {
    g.map(|v| v.map(|v| v * factor).filter(|v| v.is_finite()))
}

/// The margin of a normal force `normal` against its limit `fmax` (N), at
/// size or radius and grasping angle `(at_mm, beta_deg)`, of a grasp with
/// findings `warnings`.
fn gentle_margin(
    requirement: String,
    fmax: f64,
    normal: f64,
    (at_mm, beta_deg): (f64, f64),
    warnings: &[Warning],
) -> Margin {
    Margin {
        requirement,
        margin: (fmax - normal) / fmax,
        detail: format!("F = {normal:.4} N, at most {fmax} N"),
        at_mm: Some(at_mm),
        beta_deg: Some(beta_deg),
        value: Some(normal),
        normal_n: None,
        valid: None,
        notes: notes(warnings),
    }
}

/// `kappa`: the base scene's pressure factor (default: the paper's).
fn open_margin(g: &Gripper, open: &OpenRequirement, kappa: Option<f64>, out: &mut Collect<'_>) {
    let mut load = Load::unloaded().with_pressure_kpa(open.pressure_kpa);
    if let Some(k) = kappa {
        load.kappa = k;
    }
    let opts = SolveOptions::default().tip_only();
    match g.finger().solve(&load, &opts) {
        Ok(sol) => {
            let size = g.size_of(sol.tip);
            let mut margin = (size - open.size_mm) / open.size_mm;
            let mut detail = format!(
                "opens to d = {size:.2} mm at {} kPa, {} mm needed",
                open.pressure_kpa, open.size_mm
            );
            // an opening outside the model is not one
            let outside = sol.warnings.iter().find(|w| w.is_validity());
            let clamped = outside.is_some() && margin > -0.1;
            if let Some(w) = outside {
                margin = margin.min(-0.1);
                detail = format!("{detail}; outside the model: {w}");
            }
            out.push(
                Margin {
                    requirement: "open".into(),
                    margin,
                    detail,
                    at_mm: None,
                    beta_deg: None,
                    value: Some(size),
                    normal_n: None,
                    valid: None,
                    notes: notes(&sol.warnings),
                },
                |act| {
                    if clamped {
                        return Some([Some(0.0); 3]);
                    }
                    let r = g
                        .size_sensitivities(act, &sol, &load, &DESIGN_PARAMS)
                        .ok()?;
                    Some(design_gradient(
                        [r[0].size, r[1].size, r[2].size],
                        1.0 / open.size_mm,
                    ))
                },
            );
        }
        Err(e) => out.failed(
            "open".into(),
            -1.0,
            format!("no solution at {} kPa: {e}", open.pressure_kpa),
            None,
            None,
        ),
    }
}

#[cfg(test)]
mod tests {
    use super::{beyond_minus_one, UNBUILDABLE_MARGIN};

    #[test]
    fn margins_below_minus_one_stay_above_an_unbuildable_gripper_s() {
        // unchanged at -1 and above
        for m in [-1.0, -0.5, 0.0, 3.0] {
            assert_eq!(beyond_minus_one(m), (m, 1.0));
        }
        // a normal force three times its limit: -2 before, -1.5 now
        assert_eq!(beyond_minus_one(-2.0), (-1.5, 0.25));
        // value and slope continuous at -1
        let (v, slope) = beyond_minus_one(-1.0 - 1e-9);
        assert!((v + 1.0 + 1e-9).abs() < 1e-15 && (slope - 1.0).abs() < 1e-8);
        // monotone, and above the unbuildable margin down to a margin
        // normalised by the smallest force against a large one
        let mut last = -1.0;
        for k in 1..=10 {
            let (v, slope) = beyond_minus_one(-(10f64.powi(k)));
            assert!(v < last && v > UNBUILDABLE_MARGIN, "{k}: {v}");
            assert!(slope > 0.0 && slope.is_finite());
            last = v;
        }
        // nothing infinite comes out, and NaN is not hidden
        assert_eq!(
            beyond_minus_one(f64::NEG_INFINITY),
            (UNBUILDABLE_MARGIN, 0.0)
        );
        assert!(beyond_minus_one(f64::NAN).0.is_nan());
    }
}

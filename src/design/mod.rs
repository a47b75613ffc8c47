//! Inverse design: from the objects a gripper must hold to the design to
//! build (`fpc design`).
//!
//! A design is a point `x = (eps0, mounting angle in degrees, overlap in
//! mm)`; the requirements ([`Requirements`]) say which of them vary and
//! within which bounds. Each requirement becomes normalised margins, 0 at
//! the limit and positive when met ([`evaluate`]):
//!
//! - a cuboid of widths `[d0, d1]` with lift `L` per finger: at `CUBOID_SAMPLES`
//!   widths across the range, the width must fit (`d <= d_max`, margin
//!   `(d_max - d) / d`), the grasp at full friction (`f = mu F`, angle 0)
//!   must be valid, and `(mu F - L) / L >= 0`; with `max_normal_n` also
//!   `(F_max - F) / F_max >= 0`;
//! - a sphere of radii `[r0, r1]` with lift `L`: at `SPHERE_SAMPLES` radii,
//!   the best valid grasping angle's lift ([`Gripper::max_sphere_lift`])
//!   gives `(f_v - L) / L`;
//! - opening: the unloaded finger at `pressure_kpa` gives a grasp size of
//!   at least `size_mm`: `(d(P) - size) / size`.
//!
//! The design with the largest worst-case margin is found by a multistart
//! projected gradient ascent on a smooth minimum of the margins
//! ([`optimize`]); [`grid_search`] is the brute-force check. Every grasp a
//! design claims is a forward solve through the ordinary gripper path, and
//! [`Designed::scenes`] writes one scene file per object that `fpc solve`
//! runs to reproduce it.

mod optimize;
mod reproduce;
mod requirements;

pub use optimize::{
    grid_search, optimize, DesignOptions, Designed, GridResult, MarginSensitivity, MAX_ASCENTS,
    MAX_ASCENT_ITERATIONS, MAX_GRID_POINTS, MAX_RANDOM_STARTS,
};
pub use reproduce::{reproduce, Reproduction, REPRODUCE_RTOL};
pub use requirements::{
    ObjectRequirement, OpenRequirement, Requirements, RequirementsError, Vary, DEFAULT_DESIGN,
    VARIABLES,
};

use serde::Serialize;

use crate::actuator::Actuator;
use crate::actuator::ActuatorParam;
use crate::finger::{Finger, Load, SolveOptions};
use crate::gripper::{Gripper, GripperParams, Object, PalmSpec};
use crate::partition::Partition;
use crate::sensitivity::{GraspKind, GripperParam};
use crate::solve_error::SolveError;

/// Widths sampled per cuboid requirement.
pub const CUBOID_SAMPLES: usize = 5;

/// Radii sampled per sphere requirement.
pub const SPHERE_SAMPLES: usize = 3;

/// Grasping angles scanned per sphere radius (then refined by Brent).
const SPHERE_ANGLE_SAMPLES: usize = 8;

/// The margin of a requirement a design cannot even be built for (the
/// overlap beyond the finger's reach, an angle outside (0, 180)).
pub const UNBUILDABLE_MARGIN: f64 = -1.0;

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
    /// its scene file reproduces ([`Designed::scenes`]).
    pub fn hardest_lift(&self, i: usize) -> Option<&Margin> {
        let prefix = format!("object[{i}] ");
        self.margins
            .iter()
            .filter(|m| m.requirement.starts_with(&prefix) && m.requirement.ends_with("lift"))
            .min_by(|a, b| a.margin.total_cmp(&b.margin))
    }
}

/// The gripper of a design.
pub fn gripper(req: &Requirements, x: [f64; 3]) -> Result<Gripper, SolveError> {
    let act = Actuator::paper(x[0])?;
    let part = Partition::equal(act.geometry().lx, req.elements)?;
    Gripper::new(
        Finger::new(&act, &part, true),
        GripperParams {
            mounting_angle: x[1].to_radians(),
            geometry: PalmSpec::Overlap(x[2]),
            fingers: req.fingers,
            mu: req.mu,
            strict: false,
        },
    )
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
    evaluate_inner(req, x, false).0
}

/// d margin / d (eps0, mounting angle in degrees, overlap in mm) of one
/// margin, from the exact sensitivities of the gripper's outputs
/// (`Gripper::geometry_sensitivities`, `grasp_sensitivities`,
/// `size_sensitivities`, `max_sphere_lift_sensitivities`); `None` where
/// they do not cover the margin (the caller falls back to central
/// differences for that variable).
pub(crate) type MarginGradient = [Option<f64>; 3];

/// [`evaluate`] with every margin's [`MarginGradient`], in the same order.
pub(crate) fn evaluate_with_gradients(
    req: &Requirements,
    x: [f64; 3],
) -> (Evaluation, Vec<MarginGradient>) {
    evaluate_inner(req, x, true)
}

/// The design variables as gripper parameters.
const DESIGN_PARAMS: [GripperParam; 3] = [
    GripperParam::Actuator(ActuatorParam::Eps0),
    GripperParam::MountingAngle,
    GripperParam::Overlap,
];

/// A gradient over [`DESIGN_PARAMS`] (per rad of the angle) as one over the
/// design variables (per degree), scaled by `factor`.
fn design_gradient(rows: [f64; 3], factor: f64) -> MarginGradient {
    let per = [1.0, std::f64::consts::PI / 180.0, 1.0];
    let mut g = [None; 3];
    for i in 0..3 {
        let v = rows[i] * per[i] * factor;
        g[i] = v.is_finite().then_some(v);
    }
    g
}

/// What the margin functions collect: the margins, and, when asked for,
/// their gradients (the actuator the gripper was built from).
struct Collect<'a> {
    margins: Vec<Margin>,
    grads: Vec<MarginGradient>,
    actuator: Option<&'a Actuator>,
}

impl Collect<'_> {
    fn push(&mut self, m: Margin, g: impl FnOnce(&Actuator) -> Option<MarginGradient>) {
        let grad = self.actuator.and_then(g).unwrap_or([None; 3]);
        self.margins.push(m);
        self.grads.push(grad);
    }
}

fn evaluate_inner(
    req: &Requirements,
    x: [f64; 3],
    gradients: bool,
) -> (Evaluation, Vec<MarginGradient>) {
    let act = Actuator::paper(x[0]).ok();
    let mut c = Collect {
        margins: Vec::new(),
        grads: Vec::new(),
        actuator: if gradients { act.as_ref() } else { None },
    };
    match gripper(req, x) {
        Err(e) => c.push(
            Margin {
                requirement: "buildable".into(),
                margin: UNBUILDABLE_MARGIN,
                detail: e.to_string(),
                at_mm: None,
                beta_deg: None,
                value: None,
                normal_n: None,
                valid: None,
            },
            |_| Some([Some(0.0); 3]),
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
                    } => sphere_margins(&g, i, *radius_mm, *lift_n, *max_normal_n, &mut c),
                }
            }
            if let Some(open) = &req.open {
                open_margin(&g, open, &mut c);
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
                        Margin {
                            requirement: name("gentle"),
                            margin: (fmax - gr.normal) / fmax,
                            detail: format!("F = {:.4} N, at most {fmax} N", gr.normal),
                            at_mm: Some(d),
                            beta_deg: Some(0.0),
                            value: Some(gr.normal),
                            normal_n: None,
                            valid: None,
                        },
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
                out.push(
                    Margin {
                        requirement: name("lift"),
                        margin: -1.0,
                        detail: format!("no grasp: {e}"),
                        at_mm: Some(d),
                        beta_deg: Some(0.0),
                        value: None,
                        normal_n: None,
                        valid: None,
                    },
                    |_| Some([Some(0.0); 3]),
                );
                warm = None;
            }
        }
    }
}

fn sphere_margins(
    g: &Gripper,
    i: usize,
    radius: [f64; 2],
    lift: f64,
    max_normal: Option<f64>,
    out: &mut Collect<'_>,
) {
    for r in samples(radius, SPHERE_SAMPLES) {
        let name = |what: &str| format!("object[{i}] sphere r = {r:.1} mm: {what}");
        match g.max_sphere_lift(0.0, r, SPHERE_ANGLE_SAMPLES) {
            Ok(Some(best)) => {
                let sens = |act: &Actuator| {
                    g.max_sphere_lift_sensitivities(act, 0.0, &best, &DESIGN_PARAMS)
                        .ok()
                };
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
                    },
                    |act| {
                        let s = sens(act)?;
                        let w = &s.rows;
                        Some(design_gradient(
                            [w[0].lift, w[1].lift, w[2].lift],
                            1.0 / lift,
                        ))
                    },
                );
                if let Some(fmax) = max_normal {
                    out.push(
                        Margin {
                            requirement: name("gentle"),
                            margin: (fmax - best.normal) / fmax,
                            detail: format!("F = {:.4} N, at most {fmax} N", best.normal),
                            at_mm: Some(r),
                            beta_deg: Some(best.beta.to_degrees()),
                            value: Some(best.normal),
                            normal_n: None,
                            valid: None,
                        },
                        |act| {
                            let s = sens(act)?;
                            let w = &s.rows;
                            Some(design_gradient(
                                [w[0].normal, w[1].normal, w[2].normal],
                                -1.0 / fmax,
                            ))
                        },
                    );
                }
            }
            Ok(None) => out.push(
                Margin {
                    requirement: name("lift"),
                    margin: -1.0,
                    detail: "no valid grasp at any angle".into(),
                    at_mm: Some(r),
                    beta_deg: None,
                    value: None,
                    normal_n: None,
                    valid: None,
                },
                |_| Some([Some(0.0); 3]),
            ),
            Err(e) => out.push(
                Margin {
                    requirement: name("lift"),
                    margin: -1.0,
                    detail: format!("no grasp: {e}"),
                    at_mm: Some(r),
                    beta_deg: None,
                    value: None,
                    normal_n: None,
                    valid: None,
                },
                |_| Some([Some(0.0); 3]),
            ),
        }
    }
}

fn open_margin(g: &Gripper, open: &OpenRequirement, out: &mut Collect<'_>) {
    let load = Load::unloaded().with_pressure_kpa(open.pressure_kpa);
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
        Err(e) => out.push(
            Margin {
                requirement: "open".into(),
                margin: -1.0,
                detail: format!("no solution at {} kPa: {e}", open.pressure_kpa),
                at_mm: None,
                beta_deg: None,
                value: None,
                normal_n: None,
                valid: None,
            },
            |_| Some([Some(0.0); 3]),
        ),
    }
}

//! The eight studies of the paper (docs/model.md section 6) as functions that
//! return plain rows.
//!
//! Every study takes the base actuator (the paper's by default; each study
//! sets the prestrain it needs) and [`StudyOptions`]. Sweeps warm-start each
//! point from the previous one; a sweep that fails stops cleanly at that
//! point and records where and why ([`SweepStop`]) instead of aborting the
//! study. Only a failure of a gripper's reference state (the unloaded
//! finger) is an error.

use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, PI};

use crate::actuator::Actuator;
use crate::blocks::Partition;
use crate::error::{finite, positive, require, InputError, SolveError, Warning};
use crate::finger::{Coefficients, Finger, Load, Solution, SolveOptions, Solver, TargetProblem};
use crate::fit::fit_circle;
use crate::gripper::{
    follow, grasping_angle_range, Grasp, Gripper, GripperParams, Invalid, PalmSpec, SphereLift,
    ViableAngles,
};

/// Prestrains of the paper's samples.
pub const PAPER_EPS0: [f64; 3] = [0.4, 0.25, 0.15];

/// Mounting angles of studies 1 and 2: pi/2, pi/2.5, pi/3.
pub const PAPER_ANGLES: [f64; 3] = [FRAC_PI_2, PI / 2.5, FRAC_PI_3];

/// Overlaps of study 2 (mm).
pub const PAPER_OVERLAPS: [f64; 3] = [0.0, 10.0, 20.0];

/// Pressures of study 8 (kPa).
pub const STUDY8_PRESSURES_KPA: [f64; 4] = [0.0, 27.6, 55.2, 82.7];

/// Resolution and shared settings of the studies.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StudyOptions {
    /// Elements per finger (the paper uses 8).
    pub elements: usize,
    /// Friction coefficient.
    pub mu: f64,
    /// Points per grasping-size sweep (studies 1, 2, 3, 5), at least 2.
    pub sweep_points: usize,
    /// Grasping angles scanned (studies 5 and 6), at least 4.
    pub angle_samples: usize,
    /// Pressures in study 7 (0 to 400 kPa inclusive), at least 2.
    pub pressure_points: usize,
    /// Strict mode: grasps that bend an element backwards are invalid and
    /// dropped, as the paper's analysis assumes.
    pub strict: bool,
}

impl Default for StudyOptions {
    fn default() -> StudyOptions {
        StudyOptions {
            elements: 8,
            mu: 0.6,
            sweep_points: 32,
            angle_samples: 24,
            pressure_points: 21,
            strict: false,
        }
    }
}

impl StudyOptions {
    /// Coarse sweeps (for tests and previews).
    pub fn coarse() -> StudyOptions {
        StudyOptions {
            sweep_points: 6,
            angle_samples: 8,
            pressure_points: 5,
            ..StudyOptions::default()
        }
    }

    /// Checks every field.
    pub fn validate(&self) -> Result<(), InputError> {
        let at_least = |field: &str, v: usize, min: usize| {
            require(v >= min, field, v as f64, format!("must be at least {min}"))
        };
        at_least("study.elements", self.elements, 1)?;
        positive("study.mu", self.mu)?;
        at_least("study.sweep_points", self.sweep_points, 2)?;
        at_least("study.angle_samples", self.angle_samples, 4)?;
        at_least("study.pressure_points", self.pressure_points, 2)?;
        Ok(())
    }

    fn finger(&self, actuator: &Actuator, eps0: f64) -> Result<Finger, InputError> {
        let act = actuator.with_eps0(eps0)?;
        let part = Partition::equal(act.geometry().lx, self.elements)?;
        Ok(Finger::new(&act, &part, true))
    }

    fn gripper(
        &self,
        actuator: &Actuator,
        eps0: f64,
        mounting_angle: f64,
        overlap: f64,
    ) -> Result<Gripper, SolveError> {
        Gripper::new(
            self.finger(actuator, eps0)?,
            GripperParams {
                mounting_angle,
                geometry: PalmSpec::Overlap(overlap),
                fingers: 3,
                mu: self.mu,
                strict: self.strict,
            },
        )
    }
}

/// Where and why a sweep stopped before its end.
#[derive(Debug, Clone, PartialEq)]
pub struct SweepStop {
    /// The sweep parameter that failed (grasping size in mm, or pressure in kPa).
    pub at: f64,
    /// The solver's message.
    pub reason: String,
}

// ------------------------------------------------------------ studies 1-3

/// One point of a lifting-force curve (grasping angle 0, `f = mu F`).
#[derive(Debug, Clone, PartialEq)]
pub struct LiftPoint {
    /// Grasping size `d` (mm).
    pub size: f64,
    /// Gap between the tips (mm).
    pub tip_gap: f64,
    /// Normal force `F` (N).
    pub normal: f64,
    /// Max lifting force `f_v = mu F` (N).
    pub lift: f64,
    /// Finger height `h` (mm).
    pub height: f64,
    /// An element is bent backwards (dropped in strict mode).
    pub reversed: bool,
    /// The grasp's validity findings.
    pub warnings: Vec<Warning>,
}

/// Max lifting force versus grasping size for one gripper.
#[derive(Debug, Clone, PartialEq)]
pub struct LiftCurve {
    /// Prestrain.
    pub eps0: f64,
    /// Mounting angle (rad).
    pub mounting_angle: f64,
    /// Overlap `g` (mm).
    pub overlap: f64,
    /// Palm diameter `l` (mm).
    pub palm: f64,
    /// Inward reach `l0` (mm).
    pub l0: f64,
    /// `d_max = l + 2 Lx cos a` (mm).
    pub d_max: f64,
    /// The unloaded finger's mid-plane in the gripper frame (mm).
    pub rest_shape: Vec<[f64; 2]>,
    /// The sweep from `max(0, l - 2 l0)` to `d_max` (in strict mode
    /// without the grasps that bend an element backwards).
    pub points: Vec<LiftPoint>,
    /// Grasps left out in strict mode.
    pub dropped: usize,
    /// Set when the sweep stopped before `d_max`.
    pub stopped: Option<SweepStop>,
    /// The gripper's design warnings.
    pub warnings: Vec<Warning>,
}

impl LiftCurve {
    /// The largest grasping size the sweep reached (mm).
    pub fn reached(&self) -> f64 {
        self.points.last().map_or(0.0, |p| p.size)
    }

    /// The max lifting force at grasping size `d`, interpolated linearly
    /// (`None` outside the swept range).
    pub fn max_lift(&self, d: f64) -> Option<f64> {
        let pts = &self.points;
        if pts.is_empty() || !d.is_finite() {
            return None;
        }
        if pts.len() == 1 {
            return (d == pts[0].size).then_some(pts[0].lift);
        }
        let i = pts
            .windows(2)
            .position(|w| d >= w[0].size && d <= w[1].size)?;
        let (p, q) = (&pts[i], &pts[i + 1]);
        let t = if q.size > p.size {
            (d - p.size) / (q.size - p.size)
        } else {
            0.0
        };
        Some(p.lift + t * (q.lift - p.lift))
    }
}

/// Sweeps the grasping size over `n + 1` points from `from` to `to`
/// (grasping angle `beta`, `f = mu F`), each solve warm-started from the
/// previous; stops at the first failure.
fn size_sweep(
    g: &Gripper,
    pressure_kpa: f64,
    beta: f64,
    from: f64,
    to: f64,
    n: usize,
    mut visit: impl FnMut(&Grasp),
) -> Option<SweepStop> {
    let mut warm: Option<Grasp> = None;
    for i in 0..=n {
        let d = from + (to - from) * i as f64 / n as f64;
        match g.grasp_load_for_size(pressure_kpa, d, beta, warm.as_ref()) {
            Ok(gr) => {
                visit(&gr);
                warm = Some(gr);
            }
            Err(e) => {
                return Some(SweepStop {
                    at: d,
                    reason: e.to_string(),
                })
            }
        }
    }
    None
}

fn lift_curve(g: &Gripper, eps0: f64, n: usize) -> LiftCurve {
    let mut points = Vec::with_capacity(n + 1);
    let mut dropped = 0;
    let stopped = size_sweep(g, 0.0, 0.0, g.d_min(), g.d_max(), n, |gr| {
        if matches!(gr.invalid, Some(Invalid::CurvatureReversal { .. })) {
            dropped += 1;
            return;
        }
        points.push(LiftPoint {
            size: gr.size,
            tip_gap: gr.tip_gap,
            normal: gr.normal,
            lift: gr.lift,
            height: gr.height,
            reversed: gr.is_reversed(),
            warnings: gr.warnings.clone(),
        })
    });
    LiftCurve {
        eps0,
        mounting_angle: g.mounting_angle(),
        overlap: g.overlap(),
        palm: g.palm(),
        l0: g.l0(),
        d_max: g.d_max(),
        rest_shape: g.rest_shape(),
        points,
        dropped,
        stopped,
        warnings: g.warnings().to_vec(),
    }
}

/// Study 1 (Sec. 4.1): prestrain x mounting angle, overlap 0, grasping
/// angle 0, `f = mu F`: one curve per (eps0 in [`PAPER_EPS0`], a in
/// [`PAPER_ANGLES`]), eps0-major.
pub fn study1_prestrain_angle(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<Vec<LiftCurve>, SolveError> {
    opts.validate()?;
    let mut out = Vec::new();
    for eps0 in PAPER_EPS0 {
        for a in PAPER_ANGLES {
            let g = opts.gripper(actuator, eps0, a, 0.0)?;
            out.push(lift_curve(&g, eps0, opts.sweep_points));
        }
    }
    Ok(out)
}

/// Study 2 (Sec. 4.2): overlap, eps0 = 0.25: one curve per (a in
/// [`PAPER_ANGLES`], g in [`PAPER_OVERLAPS`]), angle-major. Each curve's
/// `d_max` is `2 (l0 - g + Lx cos a)`.
pub fn study2_overlap(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<Vec<LiftCurve>, SolveError> {
    opts.validate()?;
    let mut out = Vec::new();
    for a in PAPER_ANGLES {
        for g in PAPER_OVERLAPS {
            let gr = opts.gripper(actuator, 0.25, a, g)?;
            out.push(lift_curve(&gr, 0.25, opts.sweep_points));
        }
    }
    Ok(out)
}

/// The gripper of the paper's Sec. 5: eps0 = 0.25, a = pi/3, g = 20 mm.
pub fn section5_gripper(actuator: &Actuator, opts: &StudyOptions) -> Result<Gripper, SolveError> {
    opts.validate()?;
    opts.gripper(actuator, 0.25, FRAC_PI_3, 20.0)
}

/// Study 3 result: the cuboid grasping region, under the max lifting force
/// versus grasping size curve.
#[derive(Debug, Clone, PartialEq)]
pub struct CuboidRegion {
    /// The boundary curve.
    pub curve: LiftCurve,
}

impl CuboidRegion {
    /// True when a cuboid of size `d` (mm) needing lifting force `lift`
    /// (N per finger) lies in the region: `d` within the swept sizes and
    /// `0 <= lift <= max f_v(d)`.
    pub fn contains(&self, d: f64, lift: f64) -> bool {
        d > 0.0 && lift >= 0.0 && self.curve.max_lift(d).is_some_and(|m| lift <= m)
    }
}

/// Study 3 (Sec. 5.1.1): the cuboid grasping region of the Sec. 5 gripper
/// (grasping angle 0).
pub fn study3_cuboid_region(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<CuboidRegion, SolveError> {
    let g = section5_gripper(actuator, opts)?;
    Ok(CuboidRegion {
        curve: lift_curve(&g, 0.25, opts.sweep_points),
    })
}

// ------------------------------------------------------------ study 4

/// One pressure of the force-control study.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceControlRow {
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Normal force `F` that holds the cuboid (N).
    pub normal: f64,
    /// Finger height `h` (mm).
    pub height: f64,
    /// Gap between the tips (mm).
    pub tip_gap: f64,
    /// True when `F >= 0` and `f <= mu F`.
    pub friction_ok: bool,
    /// True when the grasp breaks no rule (see [`crate::gripper::rules`]).
    pub valid: bool,
    /// An element is bent backwards.
    pub reversed: bool,
    /// The grasp's validity findings.
    pub warnings: Vec<Warning>,
}

/// Study 4 result.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceControl {
    /// Cuboid size (mm).
    pub size: f64,
    /// Friction per finger (N).
    pub friction: f64,
    /// One row per pressure, 0 to 100 kPa in steps of 10.
    pub rows: Vec<ForceControlRow>,
    /// Set when the pressure sweep stopped early.
    pub stopped: Option<SweepStop>,
}

/// Study 4 (Sec. 5.1.2): the Sec. 5 gripper holds a cuboid of d = 100 mm
/// with f = 0.3 N per finger; for each pressure, the normal force and the
/// finger height.
pub fn study4_force_control(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<ForceControl, SolveError> {
    let g = section5_gripper(actuator, opts)?;
    let (size, friction) = (100.0, 0.3);
    let mut rows = Vec::new();
    let mut stopped = None;
    let mut warm: Option<Grasp> = None;
    for i in 0..=10 {
        let p = 10.0 * i as f64;
        match g.force_control(p, size, friction, warm.as_ref()) {
            Ok(gr) => {
                rows.push(ForceControlRow {
                    pressure_kpa: p,
                    normal: gr.normal,
                    height: gr.height,
                    tip_gap: gr.tip_gap,
                    friction_ok: gr.friction_ok(g.mu()),
                    valid: gr.is_valid(),
                    reversed: gr.is_reversed(),
                    warnings: gr.warnings.clone(),
                });
                warm = Some(gr);
            }
            Err(e) => {
                stopped = Some(SweepStop {
                    at: p,
                    reason: e.to_string(),
                });
                break;
            }
        }
    }
    Ok(ForceControl {
        size,
        friction,
        rows,
        stopped,
    })
}

// ------------------------------------------------------------ study 5

/// A valid sphere grasp of the study-5 sweep (`f = mu F`).
#[derive(Debug, Clone, PartialEq)]
pub struct SpherePoint {
    /// Grasping angle (rad).
    pub beta: f64,
    /// Sphere radius (mm).
    pub radius: f64,
    /// Max lifting force `F (sin b + mu cos b)` (N).
    pub lift: f64,
    /// Normal force (N).
    pub normal: f64,
    /// Grasping size (mm).
    pub size: f64,
    /// An element is bent backwards (dropped in strict mode).
    pub reversed: bool,
    /// The grasp's validity findings.
    pub warnings: Vec<Warning>,
}

/// Study 5 result: the sphere grasping region.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereRegion {
    /// Every valid grasp of the sweeps.
    pub points: Vec<SpherePoint>,
    /// Number of invalid grasps dropped.
    pub dropped: usize,
    /// Max lifting force versus radius on a radius grid over the swept
    /// radii, each the best valid grasping angle ([`Gripper::max_sphere_lift`]).
    pub envelope: Vec<SphereLift>,
    /// The envelope's highest point, refined by golden-section search in
    /// the radius (`None`: no valid grasp).
    pub peak: Option<SphereLift>,
    /// Sweeps that stopped early: (grasping angle, where and why).
    pub stopped: Vec<(f64, SweepStop)>,
}

/// Study 5 (Sec. 5.2.1): the Sec. 5 gripper; grasping angles over
/// `[-arctan mu, pi/2)`, at each a sweep of the grasping size (so of `F`)
/// with `f = mu F`, `r = tip gap / (2 cos b)`; invalid grasps dropped. The
/// envelope is solved directly on a grid of `2 sweep_points` radii over the
/// swept ones: at each radius, the best valid grasping angle.
pub fn study5_sphere_region(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<SphereRegion, SolveError> {
    let g = section5_gripper(actuator, opts)?;
    let [lo, hi] = grasping_angle_range(g.mu());
    let n = opts.sweep_points;
    let mut points = Vec::new();
    let mut dropped = 0;
    let mut stopped = Vec::new();
    for j in 0..opts.angle_samples {
        let beta = lo + (hi - lo) * j as f64 / opts.angle_samples as f64;
        let d_max = g.d_max();
        let stop = size_sweep(&g, 0.0, beta, d_max / n as f64, d_max, n - 1, |gr| {
            let c = g.sphere_contact(&gr.solution, beta);
            if c.invalid.or(gr.invalid).is_none() {
                points.push(SpherePoint {
                    beta,
                    radius: c.radius,
                    lift: gr.lift,
                    normal: gr.normal,
                    size: gr.size,
                    reversed: gr.is_reversed(),
                    warnings: gr.warnings.clone(),
                });
            } else {
                dropped += 1;
            }
        });
        if let Some(s) = stop {
            stopped.push((beta, s));
        }
    }
    let (envelope, peak) = sphere_envelope(&g, &points, 2 * n, opts.angle_samples)?;
    Ok(SphereRegion {
        points,
        dropped,
        envelope,
        peak,
        stopped,
    })
}

/// The max-lift envelope on `m` radii spanning the valid sweep points,
/// and its peak refined by golden-section search around the best radius.
fn sphere_envelope(
    g: &Gripper,
    points: &[SpherePoint],
    m: usize,
    samples: usize,
) -> Result<(Vec<SphereLift>, Option<SphereLift>), SolveError> {
    let rmin = points
        .iter()
        .map(|p| p.radius)
        .fold(f64::INFINITY, f64::min);
    let rmax = points.iter().map(|p| p.radius).fold(0.0, f64::max);
    if !(rmin.is_finite() && rmax > rmin) {
        return Ok((Vec::new(), None));
    }
    let at = |r: f64| g.max_sphere_lift(0.0, r, samples);
    let radii: Vec<f64> = (0..m)
        .map(|i| rmin + (rmax - rmin) * i as f64 / (m - 1) as f64)
        .collect();
    let mut envelope = Vec::with_capacity(m);
    let mut best: Option<(usize, SphereLift)> = None;
    for &r in &radii {
        if let Some(e) = at(r)? {
            if best.is_none_or(|(_, b)| e.lift > b.lift) {
                best = Some((envelope.len(), e));
            }
            envelope.push(e);
        }
    }
    let Some((i, mut peak)) = best else {
        return Ok((envelope, None));
    };
    // golden section on the neighbours' bracket (a lift of None counts as -inf)
    let (mut a, mut b) = (
        envelope[i.saturating_sub(1)].radius,
        envelope[(i + 1).min(envelope.len() - 1)].radius,
    );
    let ratio = 0.5 * (5f64.sqrt() - 1.0);
    let lift = |e: &Option<SphereLift>| e.map_or(f64::NEG_INFINITY, |e| e.lift);
    let (mut x1, mut x2) = (b - ratio * (b - a), a + ratio * (b - a));
    let (mut e1, mut e2) = (at(x1)?, at(x2)?);
    for _ in 0..GOLDEN_STEPS {
        if lift(&e1) >= lift(&e2) {
            (b, x2, e2) = (x2, x1, e1);
            x1 = b - ratio * (b - a);
            e1 = at(x1)?;
        } else {
            (a, x1, e1) = (x1, x2, e2);
            x2 = a + ratio * (b - a);
            e2 = at(x2)?;
        }
    }
    for e in [e1, e2].into_iter().flatten() {
        if e.lift > peak.lift {
            peak = e;
        }
    }
    Ok((envelope, Some(peak)))
}

/// Golden-section steps refining the study-5 peak radius.
const GOLDEN_STEPS: usize = 12;

// ------------------------------------------------------------ study 6

/// Study 6 (Sec. 5.2.2): the grasping angles that hold a sphere of
/// r = 50 mm with f_v = 0.5 N per finger (Sec. 5 gripper).
pub fn study6_viable_angles(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<ViableAngles, SolveError> {
    let g = section5_gripper(actuator, opts)?;
    g.viable_angle_range(0.0, 50.0, 0.5, opts.angle_samples)
}

// ------------------------------------------------------------ study 7

/// One pressure of the curvature study.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvatureRow {
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Circle-fit radius of the mid-plane (mm; `None`: nearly straight).
    pub radius: Option<f64>,
    /// Signed curvature `1/radius` (1/mm): positive while the finger
    /// curls towards its prestressed side (-Z), negative once pressure has
    /// reversed the curl, 0 when straight.
    pub curvature: f64,
    /// Angle of the tip tangent (rad).
    pub end_angle: f64,
    /// Tip in the finger frame (mm).
    pub tip: [f64; 2],
    /// The finger's validity findings.
    pub warnings: Vec<Warning>,
}

impl CurvatureRow {
    /// True once the curl has reversed (past flat).
    pub fn reversed(&self) -> bool {
        self.curvature < 0.0
    }
}

/// Radius of curvature versus pressure for one prestrain.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvatureCurve {
    /// Prestrain.
    pub eps0: f64,
    /// One row per pressure.
    pub rows: Vec<CurvatureRow>,
    /// Set when the sweep stopped early.
    pub stopped: Option<SweepStop>,
}

/// Study 7 (Sec. 6.2): unloaded fingers of eps0 in {0.15, 0.25, 0.4},
/// pressure from 0 to 400 kPa, circle-fit radius with its side.
pub fn study7_curvature(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<Vec<CurvatureCurve>, SolveError> {
    opts.validate()?;
    let sopts = SolveOptions {
        stability: false,
        ..SolveOptions::default()
    };
    let mut out = Vec::new();
    for eps0 in [0.15, 0.25, 0.4] {
        let finger = opts.finger(actuator, eps0)?;
        let mut solver = Solver::new(&finger);
        let mut rows = Vec::new();
        let mut stopped = None;
        let mut guess: Option<Coefficients> = None;
        for i in 0..opts.pressure_points {
            let p = 400.0 * i as f64 / (opts.pressure_points - 1) as f64;
            let load = Load::unloaded().with_pressure_kpa(p);
            match solver.solve(&load, guess.as_ref(), &sopts) {
                Ok(sol) => {
                    rows.push(curvature_row(p, &sol));
                    guess = Some(sol.coefficients);
                }
                Err(e) => {
                    stopped = Some(SweepStop {
                        at: p,
                        reason: e.to_string(),
                    });
                    break;
                }
            }
        }
        out.push(CurvatureCurve {
            eps0,
            rows,
            stopped,
        });
    }
    Ok(out)
}

fn curvature_row(pressure_kpa: f64, sol: &Solution) -> CurvatureRow {
    // the side of the fitted circle's centre with respect to the root
    // tangent (the X axis): below it, the finger curls towards -Z
    let circle = fit_circle(&sol.points);
    let curvature = match circle {
        Some(c) if c.radius > 0.0 && c.center[1] != 0.0 => -c.center[1].signum() / c.radius,
        _ => 0.0,
    };
    CurvatureRow {
        pressure_kpa,
        radius: circle.map(|c| c.radius),
        curvature,
        end_angle: sol.end_angle,
        tip: sol.tip,
        warnings: sol.warnings.clone(),
    }
}

// ------------------------------------------------------------ study 8

/// An axis of the finger frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// Along the root tangent.
    X,
    /// Normal to it, towards the constraining layer.
    Z,
}

impl Axis {
    fn unit(self) -> [f64; 2] {
        match self {
            Axis::X => [1.0, 0.0],
            Axis::Z => [0.0, 1.0],
        }
    }
}

/// A tip force that moves the tip a given distance along an axis.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplacementForce {
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// The axis of force and displacement.
    pub axis: Axis,
    /// Displacement of the tip along the axis (mm).
    pub displacement: f64,
    /// The force along the axis (N).
    pub force: f64,
    /// The pressurised, unloaded tip (finger frame, mm).
    pub start_tip: [f64; 2],
    /// The loaded equilibrium.
    pub solution: Solution,
}

/// From the pressurised unloaded shape, the tip force along `axis` (finger
/// frame) that moves the tip `displacement` mm along that axis.
pub fn tip_force_for_displacement(
    finger: &Finger,
    pressure_kpa: f64,
    axis: Axis,
    displacement: f64,
) -> Result<DisplacementForce, SolveError> {
    finite("displacement.pressure_kpa", pressure_kpa)?;
    finite("displacement.distance", displacement)?;
    let base = Load::unloaded().with_pressure_kpa(pressure_kpa);
    let opts = SolveOptions::default();
    let mut solver = Solver::new(finger);
    let start = solver.solve(&base, None, &opts)?;
    let u = axis.unit();
    let at = |target: f64| TargetProblem {
        base,
        direction: u,
        weights: u,
        target,
    };
    let s0 = u[0] * start.tip[0] + u[1] * start.tip[1];
    let (solution, force) = follow(
        &mut solver,
        &start.coefficients,
        0.0,
        &at(s0),
        &at(s0 + displacement),
        &opts,
    )
    .map_err(|e| e.for_target("displacement.distance", displacement))?;
    Ok(DisplacementForce {
        pressure_kpa,
        axis,
        displacement,
        force,
        start_tip: start.tip,
        solution,
    })
}

/// One row of study 8.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplacementForceRow {
    /// Prestrain of the sample.
    pub eps0: f64,
    /// Axis of force and displacement.
    pub axis: Axis,
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Force for a 10 mm tip displacement (N); `None` when the solve failed.
    pub force: Option<f64>,
    /// The loaded finger's validity findings.
    pub warnings: Vec<Warning>,
}

/// Study 8 (Sec. 6.3): at 0, 27.6, 55.2, 82.7 kPa, the tip force that moves
/// the tip 10 mm: along +X for the eps0 = 0.4 sample, along +Z for the
/// eps0 = 0.15 sample.
pub fn study8_force_at_displacement(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<Vec<DisplacementForceRow>, SolveError> {
    opts.validate()?;
    let mut rows = Vec::new();
    for (eps0, axis) in [(0.4, Axis::X), (0.15, Axis::Z)] {
        let finger = opts.finger(actuator, eps0)?;
        for p in STUDY8_PRESSURES_KPA {
            let r = tip_force_for_displacement(&finger, p, axis, 10.0).ok();
            rows.push(DisplacementForceRow {
                eps0,
                axis,
                pressure_kpa: p,
                force: r.as_ref().map(|r| r.force),
                warnings: r.map(|r| r.solution.warnings).unwrap_or_default(),
            });
        }
    }
    Ok(rows)
}

// ------------------------------------------------------------ all

/// The eight studies' results.
#[derive(Debug, Clone, PartialEq)]
pub struct Studies {
    /// Prestrain x mounting angle ([`study1_prestrain_angle`]).
    pub study1: Vec<LiftCurve>,
    /// Overlap ([`study2_overlap`]).
    pub study2: Vec<LiftCurve>,
    /// Cuboid grasping region ([`study3_cuboid_region`]).
    pub study3: CuboidRegion,
    /// Force control by pressure ([`study4_force_control`]).
    pub study4: ForceControl,
    /// Sphere grasping region ([`study5_sphere_region`]).
    pub study5: SphereRegion,
    /// Viable grasping angles ([`study6_viable_angles`]).
    pub study6: ViableAngles,
    /// Curvature versus pressure ([`study7_curvature`]).
    pub study7: Vec<CurvatureCurve>,
    /// Force at a fixed displacement ([`study8_force_at_displacement`]).
    pub study8: Vec<DisplacementForceRow>,
}

/// Runs the eight studies.
pub fn run_all(actuator: &Actuator, opts: &StudyOptions) -> Result<Studies, SolveError> {
    Ok(Studies {
        study1: study1_prestrain_angle(actuator, opts)?,
        study2: study2_overlap(actuator, opts)?,
        study3: study3_cuboid_region(actuator, opts)?,
        study4: study4_force_control(actuator, opts)?,
        study5: study5_sphere_region(actuator, opts)?,
        study6: study6_viable_angles(actuator, opts)?,
        study7: study7_curvature(actuator, opts)?,
        study8: study8_force_at_displacement(actuator, opts)?,
    })
}

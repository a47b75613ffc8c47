//! Run time against error: how the tip position, the radius of curvature
//! and the grasp size converge with the number of elements N and the
//! Newton tolerance, against a converged reference.
//!
//! Scene (default actuator with ribs, eps0 = 0.25): the tip-loaded finger
//! (Fx = 0.939782 N, Fz = 0.521707 N, finger frame) for the tip and the
//! grasp size (the gripper of the paper's Sec. 5: a = pi/3, overlap 20 mm), and
//! the unloaded finger for the circle-fit radius. The reference is N = 256
//! at a relative residual of 1e-13; a Richardson extrapolation from N = 64,
//! 128 and 256 reports how far the reference itself may be from N -> oo.

use std::f64::consts::PI;
use std::time::Instant;

use fpc::{
    Actuator, Finger, Gripper, GripperParams, Load, PalmSpec, Partition, SolveError, SolveOptions,
    Solver,
};

/// One (N, tolerance) point.
#[derive(Debug, Clone, PartialEq)]
pub struct AccuracyRow {
    /// Number of equal elements.
    pub elements: usize,
    /// Relative residual tolerance of Newton.
    pub rtol: f64,
    /// Median time of the tip-loaded solve from the unloaded guess (us).
    pub time_us: f64,
    /// Distance of the tip from the reference tip (mm).
    pub tip_error_mm: f64,
    /// |radius - reference radius| of the unloaded finger (mm).
    pub radius_error_mm: f64,
    /// |grasp size - reference grasp size| (mm).
    pub grasp_error_mm: f64,
    /// True when no other row is both faster and more accurate at the tip.
    pub pareto: bool,
}

/// The converged reference and its own error estimate.
#[derive(Debug, Clone, PartialEq)]
pub struct Reference {
    /// Elements of the reference.
    pub elements: usize,
    /// Reference tip (mm).
    pub tip: [f64; 2],
    /// Reference radius (mm).
    pub radius: f64,
    /// Reference grasp size (mm).
    pub grasp_size: f64,
    /// Observed order of convergence of the tip from N = 64, 128, 256.
    pub observed_order: f64,
    /// Distance between the reference tip and its Richardson extrapolation (mm).
    pub richardson_gap_mm: f64,
}

/// The whole table with recommendations.
#[derive(Debug, Clone, PartialEq)]
pub struct AccuracyStudy {
    /// Every (N, tolerance) point.
    pub rows: Vec<AccuracyRow>,
    /// The reference.
    pub reference: Reference,
    /// Smallest N whose tip error is below 0.1 mm at the tightest tolerance.
    pub n_for_0_1_mm: Option<usize>,
    /// Smallest N whose tip error is below 0.01 mm at the tightest tolerance.
    pub n_for_0_01_mm: Option<usize>,
}

struct Measured {
    tip: [f64; 2],
    radius: f64,
    grasp: f64,
    time_us: f64,
}

fn measure(act: &Actuator, n: usize, rtol: f64, repeats: usize) -> Result<Measured, SolveError> {
    let part = Partition::equal(act.geometry().lx, n)?;
    let finger = Finger::new(act, &part, true);
    let opts = SolveOptions {
        rtol,
        ..SolveOptions::default()
    };
    let unloaded = finger.solve(&Load::unloaded(), &opts)?;
    let radius = unloaded.radius.unwrap_or(f64::INFINITY);
    let load = Load::unloaded().with_tip_force(0.939782, 0.521707);
    let tip_opts = opts.tip_only();
    let mut solver = Solver::new(&finger);
    let mut times = Vec::with_capacity(repeats);
    let mut tip = [0.0; 2];
    for _ in 0..repeats.max(1) {
        let t = Instant::now();
        let s = solver.solve(&load, Some(&unloaded.coefficients), &tip_opts)?;
        times.push(t.elapsed().as_secs_f64() * 1e6);
        tip = s.tip;
    }
    times.sort_by(f64::total_cmp);
    let params = GripperParams {
        mounting_angle: PI / 3.0,
        geometry: PalmSpec::Overlap(20.0),
        ..GripperParams::default()
    };
    let gripper = Gripper::new(finger.clone(), params)?;
    let grasp = gripper.size_of(tip);
    Ok(Measured {
        tip,
        radius,
        grasp,
        time_us: times[times.len() / 2],
    })
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Runs the study over `elements` x `rtols`; `progress` is called after each point.
pub fn accuracy_study(
    elements: &[usize],
    rtols: &[f64],
    mut progress: impl FnMut(usize, usize),
) -> Result<AccuracyStudy, SolveError> {
    let act = Actuator::paper(0.25)?;
    let r64 = measure(&act, 64, 1e-13, 1)?;
    let r128 = measure(&act, 128, 1e-13, 1)?;
    let r256 = measure(&act, 256, 1e-13, 1)?;
    let d1 = dist(r128.tip, r64.tip);
    let d2 = dist(r256.tip, r128.tip);
    let order = if d1 > 0.0 && d2 > 0.0 {
        (d1 / d2).log2()
    } else {
        f64::NAN
    };
    let gap = if order.is_finite() && order > 0.0 {
        d2 / (2f64.powf(order) - 1.0)
    } else {
        d2
    };
    let reference = Reference {
        elements: 256,
        tip: r256.tip,
        radius: r256.radius,
        grasp_size: r256.grasp,
        observed_order: if order.is_finite() { order } else { 0.0 },
        richardson_gap_mm: gap,
    };
    let total = elements.len() * rtols.len();
    let mut rows = Vec::with_capacity(total);
    for &n in elements {
        for &rtol in rtols {
            let repeats = if n <= 32 {
                25
            } else if n <= 64 {
                5
            } else {
                1
            };
            let m = measure(&act, n, rtol, repeats)?;
            rows.push(AccuracyRow {
                elements: n,
                rtol,
                time_us: m.time_us,
                tip_error_mm: dist(m.tip, reference.tip),
                radius_error_mm: (m.radius - reference.radius).abs(),
                grasp_error_mm: (m.grasp - reference.grasp_size).abs(),
                pareto: false,
            });
            progress(rows.len(), total);
        }
    }
    for i in 0..rows.len() {
        let (t, e) = (rows[i].time_us, rows[i].tip_error_mm);
        rows[i].pareto = !rows.iter().any(|r| {
            r.time_us <= t && r.tip_error_mm <= e && (r.time_us < t || r.tip_error_mm < e)
        });
    }
    let tightest = rtols.iter().copied().fold(f64::INFINITY, f64::min);
    let smallest_n = |limit: f64| {
        rows.iter()
            .filter(|r| r.rtol == tightest && r.tip_error_mm <= limit)
            .map(|r| r.elements)
            .min()
    };
    Ok(AccuracyStudy {
        n_for_0_1_mm: smallest_n(0.1),
        n_for_0_01_mm: smallest_n(0.01),
        rows,
        reference,
    })
}

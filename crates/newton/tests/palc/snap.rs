//! The 1-D snap-through `g = x^3 - x - lambda` and a pitchfork: folds,
//! step control, the natural end, a branch point.

use super::*;

// ------------------------------------------------------ 1-D snap-through

/// `E = x^4/4 - x^2/2 - lambda x`: `g = x^3 - x - lambda`, `H = 3 x^2 - 1`.
/// Optionally not evaluable beyond `x_max`.
pub(super) struct Snap {
    x_max: f64,
    refuse: bool,
}

impl Snap {
    pub(super) fn new() -> Snap {
        Snap {
            x_max: f64::INFINITY,
            refuse: false,
        }
    }
}

impl DensePathProblem for Snap {
    fn dim(&self) -> usize {
        1
    }
    fn eval(&mut self, x: &[f64], l: f64, g: &mut [f64], gl: &mut [f64], h: &mut [f64]) -> bool {
        let x = x[0];
        if x > self.x_max {
            if self.refuse {
                return false;
            }
            g[0] = f64::NAN;
            gl[0] = -1.0;
            h[0] = f64::NAN;
            return true;
        }
        g[0] = x * x * x - x - l;
        gl[0] = -1.0;
        h[0] = 3.0 * x * x - 1.0;
        true
    }
}

pub(super) fn lambda_fold() -> f64 {
    2.0 / (3.0 * 3f64.sqrt())
}

pub(super) fn x_fold() -> f64 {
    1.0 / 3f64.sqrt()
}

/// The equilibrium at `lambda = -1`: the real root of `x^3 - x + 1`.
pub(super) const X_START: f64 = -1.324_717_957_244_746;

#[test]
fn snap_through_passes_both_folds_and_the_unstable_middle() {
    for theta in [1.0, 0.3, 3.0] {
        let opts = PalcOptions {
            theta,
            ..Default::default()
        };
        let mut palc = Palc::new(1, opts).unwrap();
        let mut p = Dense::path(Snap::new());
        let b = palc.branch(
            &mut p,
            &[-1.3],
            -1.0,
            Direction::Increasing,
            Some(1.0),
            |_| Control::Continue,
        );
        let r = &b.report;
        assert_eq!(r.termination, PathTermination::ReachedTarget, "{r}");
        // the start was polished, the end lies on the target exactly
        assert!((b.points[0].x[0] - X_START).abs() < 1e-12);
        let last = b.last().unwrap();
        assert_eq!(last.lambda, 1.0);
        assert!((last.x[0] + X_START).abs() < 1e-12, "{}", last.x[0]);
        // every point an equilibrium; inertia = sign of H
        for pt in &b.points {
            let x = pt.x[0];
            assert!((x * x * x - x - pt.lambda).abs() <= 1e-10);
            let unstable = 3.0 * x * x - 1.0 < 0.0;
            assert_eq!(pt.inertia.negative, usize::from(unstable), "x = {x}");
            assert_eq!(pt.inertia.positive + pt.inertia.negative, 1);
        }
        // the branch runs through the unstable middle part
        let middle = b.points.iter().filter(|pt| !pt.is_stable()).count();
        assert!(middle >= 2, "theta = {theta}: {middle} unstable points");
        assert!(b.points.iter().any(|pt| pt.x[0].abs() < 0.3));
        // two folds, located to 1e-10, stability lost then regained
        let folds: Vec<_> = b.folds().collect();
        assert_eq!(b.events.len(), 2, "theta = {theta}: {:?}", b.events);
        assert_eq!(folds.len(), 2);
        let (lf, xf) = (lambda_fold(), x_fold());
        for (f, (l, x), (before, after)) in
            [(folds[0], (lf, -xf), (0, 1)), (folds[1], (-lf, xf), (1, 0))]
        {
            assert!(f.located);
            assert_eq!(f.kind, EventKind::Fold);
            assert!((f.lambda - l).abs() <= 1e-10, "theta = {theta}: {f:?}");
            assert!((f.x[0] - x).abs() <= 1e-10, "theta = {theta}: {f:?}");
            assert_eq!(
                (f.inertia_before.negative, f.inertia_after.negative),
                (before, after)
            );
            assert!(f.tangent_lambda.abs() < 1e-9);
            // between its neighbours
            let (a, c) = (&b.points[f.after_point], &b.points[f.after_point + 1]);
            assert!(a.arclength < f.arclength && f.arclength < c.arclength);
            assert!(a.tangent_lambda * c.tangent_lambda < 0.0);
        }
        // arclength increases, lambda's tangent sign pattern + - +
        assert!(b.points.windows(2).all(|w| w[1].arclength > w[0].arclength));
        assert!(r.factorizations >= r.evaluations && r.evaluations > 0);
        assert_eq!(r.steps + 1, b.points.len());
        assert_eq!(r.events, 2);
        assert!(r.locate_solves > 0);
    }
}

#[test]
fn snap_through_backwards_and_natural_end() {
    // from lambda = +1 downwards to -1: the same folds in reverse order
    let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
    let mut p = Dense::path(Snap::new());
    let b = palc.branch(
        &mut p,
        &[1.3],
        1.0,
        Direction::Decreasing,
        Some(-1.0),
        |_| Control::Continue,
    );
    assert_eq!(b.report.termination, PathTermination::ReachedTarget);
    assert_eq!(b.last().unwrap().lambda, -1.0);
    let folds: Vec<_> = b.folds().collect();
    assert_eq!(folds.len(), 2);
    assert!((folds[0].lambda + lambda_fold()).abs() <= 1e-10);
    assert!((folds[0].x[0] - x_fold()).abs() <= 1e-10);
    assert!((folds[1].lambda - lambda_fold()).abs() <= 1e-10);

    // a stop predicate: a geometric bound x <= 0 ends the branch in the
    // middle part, at the first point past it
    let b = palc.branch(
        &mut p,
        &[-1.3],
        -1.0,
        Direction::Increasing,
        Some(1.0),
        |pt| {
            if pt.x[0] > 0.0 {
                Control::Stop
            } else {
                Control::Continue
            }
        },
    );
    assert_eq!(b.report.termination, PathTermination::Stopped);
    let (last, before) = (b.last().unwrap(), &b.points[b.points.len() - 2]);
    assert!(last.x[0] > 0.0 && before.x[0] <= 0.0);
    assert_eq!(b.folds().count(), 1);
    assert_eq!(palc.last_point().unwrap().1, last.lambda);
    // stop at the start
    let b = palc.branch(&mut p, &[-1.3], -1.0, Direction::Increasing, None, |_| {
        Control::Stop
    });
    assert_eq!(b.report.termination, PathTermination::Stopped);
    assert_eq!((b.points.len(), b.report.steps), (1, 0));
}

#[test]
fn target_is_landed_on_exactly_whatever_the_steps() {
    for (initial, max, target) in [(0.05, 0.5, 0.9), (0.01, 0.01, 0.25), (0.3, 0.3, -0.37)] {
        let opts = PalcOptions {
            initial_step: initial,
            min_step: 1e-8,
            max_step: max,
            ..Default::default()
        };
        let mut palc = Palc::new(1, opts).unwrap();
        let mut p = Dense::path(Snap::new());
        let b = palc.branch(
            &mut p,
            &[-1.3],
            -1.0,
            Direction::Increasing,
            Some(target),
            |_| Control::Continue,
        );
        assert_eq!(b.report.termination, PathTermination::ReachedTarget);
        let last = b.last().unwrap();
        assert_eq!(last.lambda, target);
        assert_eq!(b.report.lambda, target);
        let x = last.x[0];
        assert!((x * x * x - x - target).abs() <= 1e-10);
        // the first crossing: before the first fold (lambda rises from -1)
        // if the target is below the fold's load, else after both folds
        if target < lambda_fold() {
            assert!(x < -x_fold(), "{x}");
            assert_eq!(b.folds().count(), 0);
        } else {
            assert!(x > x_fold(), "{x}");
            assert_eq!(b.folds().count(), 2);
        }
        assert!(b.points[..b.points.len() - 1]
            .iter()
            .all(|pt| pt.lambda < target));
    }
    // a target reached on the unstable middle part
    let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
    let mut p = Dense::path(Snap::new());
    let b = palc.branch(
        &mut p,
        &[0.0],
        0.0,
        Direction::Decreasing,
        Some(-0.1),
        |_| Control::Continue,
    );
    // from the unstable middle (x = 0, lambda = 0) downwards: lambda falls
    // at once and reaches -0.1 on the unstable part
    assert_eq!(b.report.termination, PathTermination::ReachedTarget);
    assert!(!b.last().unwrap().is_stable());
}

#[test]
fn step_limit_non_finite_and_failed_starts_are_reported() {
    let mut palc = Palc::new(
        1,
        PalcOptions {
            max_steps: 3,
            ..Default::default()
        },
    )
    .unwrap();
    let mut p = Dense::path(Snap::new());
    let b = palc.branch(
        &mut p,
        &[-1.3],
        -1.0,
        Direction::Increasing,
        Some(1.0),
        |_| Control::Continue,
    );
    assert_eq!(b.report.termination, PathTermination::MaxSteps);
    assert_eq!((b.report.steps, b.points.len()), (3, 4));

    // the problem cannot be evaluated beyond x = 0.9 (NaN, or refused):
    // the branch approaches the limit with ever shorter steps and ends
    // NonFinite; nothing non-finite is accepted
    for refuse in [false, true] {
        let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
        let mut p = Dense::path(Snap { x_max: 0.9, refuse });
        let b = palc.branch(
            &mut p,
            &[-1.3],
            -1.0,
            Direction::Increasing,
            Some(1.0),
            |_| Control::Continue,
        );
        assert_eq!(
            b.report.termination,
            PathTermination::NonFinite,
            "{}",
            b.report
        );
        assert!(b.report.rejected > 0);
        assert!(b
            .points
            .iter()
            .all(|pt| pt.x[0] <= 0.9 && pt.x[0].is_finite() && pt.lambda.is_finite()));
        let last = b.last().unwrap();
        assert!(last.x[0] > 0.9 - 1e-6, "ended at {}", last.x[0]);
        assert_eq!(b.folds().count(), 2);
        let (x, l) = palc.last_point().unwrap();
        assert_eq!((x[0], l), (last.x[0], last.lambda));
    }

    // a non-finite start
    let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
    let mut p = Dense::path(Snap::new());
    let b = palc.branch(
        &mut p,
        &[f64::NAN],
        -1.0,
        Direction::Increasing,
        None,
        |_| Control::Continue,
    );
    assert_eq!(b.report.termination, PathTermination::NonFinite);
    assert!(b.points.is_empty());
    assert!(palc.last_point().is_none());
    // a start too far for plain Newton within max_corrector_iterations
    let b = palc.branch(&mut p, &[1e6], -1.0, Direction::Increasing, None, |_| {
        Control::Continue
    });
    assert_eq!(b.report.termination, PathTermination::StartFailed);
    assert!(b.points.is_empty());
}

/// `g = x^3 - lambda x` (a pitchfork, no imperfection), plus a stiff
/// decoupled direction: along the trivial branch `x = 0` the inertia of
/// `H = diag(-lambda, 10)` changes at `lambda = 0` while `d lambda / ds`
/// stays 1, a possible bifurcation. The driver reports it and stays on
/// the trivial branch.
pub(super) struct Pitchfork;

impl DensePathProblem for Pitchfork {
    fn dim(&self) -> usize {
        2
    }
    fn eval(&mut self, x: &[f64], l: f64, g: &mut [f64], gl: &mut [f64], h: &mut [f64]) -> bool {
        g[0] = x[0].powi(3) - l * x[0];
        g[1] = 10.0 * x[1] - l;
        gl[0] = -x[0];
        gl[1] = -1.0;
        h.copy_from_slice(&[3.0 * x[0] * x[0] - l, 0.0, 0.0, 10.0]);
        true
    }
}

#[test]
fn a_branch_point_is_reported_as_a_possible_bifurcation() {
    let mut palc = Palc::new(2, PalcOptions::default()).unwrap();
    let mut p = Dense::path(Pitchfork);
    let b = palc.branch(
        &mut p,
        &[0.0, -0.1],
        -1.0,
        Direction::Increasing,
        Some(1.0),
        |_| Control::Continue,
    );
    assert_eq!(b.report.termination, PathTermination::ReachedTarget);
    assert_eq!(b.events.len(), 1, "{:?}", b.events);
    let e = &b.events[0];
    assert_eq!(e.kind, EventKind::PossibleBifurcation);
    assert!(e.located);
    assert!(e.lambda.abs() <= 1e-10, "{}", e.lambda);
    assert!(e.x[0].abs() <= 1e-10 && (e.x[1] - e.lambda / 10.0).abs() <= 1e-10);
    assert_eq!(
        (e.inertia_before.negative, e.inertia_after.negative),
        (0, 1)
    );
    assert!(e.tangent_lambda > 0.9);
    // no branch switching: x_0 = 0 all along
    assert!(b.points.iter().all(|pt| pt.x[0] == 0.0));
    assert_eq!(b.folds().count(), 0);

    // without event detection: nothing reported, the same points
    let mut palc = Palc::new(
        2,
        PalcOptions {
            detect_events: false,
            ..Default::default()
        },
    )
    .unwrap();
    let b2 = palc.branch(
        &mut p,
        &[0.0, -0.1],
        -1.0,
        Direction::Increasing,
        Some(1.0),
        |_| Control::Continue,
    );
    assert!(b2.events.is_empty() && b2.report.locate_solves == 0);
    assert_eq!(b2.points, b.points);
}

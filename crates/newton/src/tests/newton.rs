//! Tests of the Newton minimiser: convergence, safeguards, an independent
//! minimiser.

use super::*;

#[test]
fn newton_convex_quadratic_takes_one_step() {
    let mut rng = Lcg::new(42);
    for &n in &[1usize, 3, 10, 33] {
        let mut q = QuadQuartic::random(n, false, &mut rng);
        let mut newton = Newton::new(n, NewtonOptions::default());
        let mut x = vec![0.0; n];
        let r = newton.minimize(&mut Dense::new(&mut q), &mut x);
        assert!(r.converged(), "n = {n}: {r}");
        assert_eq!(r.iterations, 1, "n = {n}: {r}");
        assert_eq!(r.max_shift, 0.0);
        // the step's decrease is the quadratic model's, so where it lands
        // only the gradient is evaluated (chord steps, the default)
        assert_eq!((r.hessian_evals, r.gradient_evals), (1, 1));
        // Independent: an LU solve of A x = b.
        let xs = lu_solve(n, &q.a, &q.b);
        let d = max_abs_diff(&x, &xs);
        assert!(
            d < 1e-8 * (1.0 + norm_inf_of(&xs)),
            "n = {n}: differs by {d}"
        );
    }
}

#[test]
fn newton_rosenbrock_2_and_10() {
    for &n in &[2usize, 10] {
        let mut p = Dense::new(Rosenbrock { n });
        let careful = NewtonOptions {
            eager_full_steps: false,
            ..NewtonOptions::default()
        };
        let mut newton = Newton::new(n, careful);
        let mut x = rosenbrock_start(n);
        let r = newton.minimize(&mut p, &mut x);
        assert!(r.converged(), "n = {n}: {r}");
        assert!(r.residual_norm <= 1e-10);
        assert!(max_abs_diff(&x, &vec![1.0; n]) < 1e-9, "n = {n}: {x:?}");
        // Without eager full steps the Hessian is only evaluated at accepted points.
        assert_eq!(r.hessian_evals, r.iterations + 1);
        assert!(r.energy < 1e-18);
        // Eager full steps reach the same minimiser with fewer evaluations.
        let mut eager = Newton::new(n, NewtonOptions::default());
        let mut xe = rosenbrock_start(n);
        let re = eager.minimize(&mut p, &mut xe);
        assert!(re.converged(), "n = {n}: {re}");
        assert!(max_abs_diff(&xe, &vec![1.0; n]) < 1e-9, "n = {n}: {xe:?}");
        assert!(
            re.energy_evals + re.hessian_evals < r.energy_evals + r.hessian_evals,
            "n = {n}: eager {re:?} vs careful {r:?}"
        );
    }
}

/// Chord steps (the default) reach the minimiser Newton without them
/// reaches, to the tolerance, with no more Hessians, and they do save some
/// across random mildly quartic problems started from zero.
#[test]
fn chord_steps_save_hessians_and_keep_the_minimiser() {
    let mut rng = Lcg::new(7);
    let (mut with, mut without, mut chords) = (0, 0, 0);
    for &n in &[3usize, 10, 33] {
        for _ in 0..8 {
            let mut q = QuadQuartic::random(n, true, &mut rng);
            let no_chord = NewtonOptions {
                chord_steps: false,
                ..NewtonOptions::default()
            };
            let mut xa = vec![0.0; n];
            let ra =
                Newton::new(n, NewtonOptions::default()).minimize(&mut Dense::new(&mut q), &mut xa);
            let mut xb = vec![0.0; n];
            let rb = Newton::new(n, no_chord).minimize(&mut Dense::new(&mut q), &mut xb);
            assert!(ra.converged() && rb.converged(), "n = {n}: {ra} / {rb}");
            assert!(ra.residual_norm <= NewtonOptions::default().gtol);
            // the gradient the report gives is the one at the returned x
            let mut g = vec![0.0; n];
            q.gradient(&xa, &mut g);
            assert_eq!(norm_inf_of(&g), ra.residual_norm);
            let scale = 1.0 + xb.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            assert!(max_abs_diff(&xa, &xb) <= 1e-8 * scale, "n = {n}");
            assert!(ra.hessian_evals <= rb.hessian_evals, "n = {n}: {ra} / {rb}");
            // a chord step factorises nothing
            assert!(ra.factorizations <= ra.hessian_evals, "{ra}");
            // every other accepted step needed a factorisation of its own
            assert_eq!(rb.chord_steps, 0, "{rb}");
            assert!(ra.chord_steps <= ra.iterations, "{ra:?}");
            assert!(
                ra.factorizations >= ra.iterations - ra.chord_steps,
                "{ra:?}"
            );
            chords += ra.chord_steps;
            with += ra.hessian_evals;
            without += rb.hessian_evals;
        }
    }
    assert!(
        with < without,
        "chord steps saved no Hessian: {with} vs {without}"
    );
    assert!(chords > 0, "no chord step was counted");
}

/// A trusted start (nested iteration) evaluates the first full step with
/// its gradient: from close to the minimum that replaces the energy
/// evaluation; from far away the step is rejected and the solve goes on as
/// without it. The minimiser is the same either way.
#[test]
fn trusted_starts_skip_the_first_energy_and_keep_the_minimiser() {
    let mut rng = Lcg::new(11);
    for &n in &[4usize, 12] {
        let mut q = QuadQuartic::random(n, true, &mut rng);
        let mut x_ref = vec![0.0; n];
        let r =
            Newton::new(n, NewtonOptions::default()).minimize(&mut Dense::new(&mut q), &mut x_ref);
        assert!(r.converged());
        let trusted = NewtonOptions {
            trusted_start: true,
            ..NewtonOptions::default()
        };
        for (offset, near) in [(1e-3, true), (3.0, false)] {
            let start: Vec<f64> = x_ref
                .iter()
                .enumerate()
                .map(|(i, v)| v + offset * ((i as f64) + 1.0).sin())
                .collect();
            let mut xa = start.clone();
            let ra = Newton::new(n, trusted).minimize(&mut Dense::new(&mut q), &mut xa);
            let mut xb = start.clone();
            let rb =
                Newton::new(n, NewtonOptions::default()).minimize(&mut Dense::new(&mut q), &mut xb);
            assert!(ra.converged() && rb.converged(), "n = {n}: {ra} / {rb}");
            assert!(
                max_abs_diff(&xa, &x_ref) <= 1e-8 * (1.0 + norm_inf_of(&x_ref)),
                "n = {n}"
            );
            if near {
                assert_eq!(ra.energy_evals, 0, "n = {n}: {ra}");
                assert!(rb.energy_evals >= 1, "n = {n}: {rb}");
                assert!(ra.hessian_evals <= rb.hessian_evals, "n = {n}: {ra} / {rb}");
            }
        }
    }
}

#[test]
fn newton_matches_an_independent_quasi_newton_minimiser() {
    // argmin's L-BFGS never sees a Hessian
    for &n in &[2usize, 10] {
        let mut xn = rosenbrock_start(n);
        assert!(Newton::new(n, NewtonOptions::default())
            .minimize(&mut Dense::new(Rosenbrock { n }), &mut xn)
            .converged());
        let xb = lbfgs(&mut Rosenbrock { n }, &rosenbrock_start(n), 1e-9);
        assert!(max_abs_diff(&xn, &xb) < 1e-6, "n = {n}");
    }
    let mut rng = Lcg::new(77);
    for _ in 0..3 {
        let n = 8;
        let mut q = QuadQuartic::random(n, true, &mut rng);
        let mut xn = vec![0.0; n];
        assert!(Newton::new(n, NewtonOptions::default())
            .minimize(&mut Dense::new(&mut q), &mut xn)
            .converged());
        // (its line search meets round-off in the energy below 1e-8)
        let xb = lbfgs(&mut q, &vec![0.0; n], 1e-8);
        assert!(max_abs_diff(&xn, &xb) < 1e-6);
    }
}

#[test]
fn newton_indefinite_start_reaches_a_minimum_monotonically() {
    let n = 12;
    let mut p = DoubleWell {
        n,
        kappa: 0.1,
        tilt: 0.5,
        accepted: vec![],
    };
    let mut x: Vec<f64> = (0..n).map(|i| 0.1 * ((i as f64) * 0.7).sin()).collect();
    // The start Hessian is indefinite.
    let mut g = vec![0.0; n];
    let mut h = vec![0.0; n * n];
    p.hessian(&x, &mut g, &mut h);
    assert!(min_eigenvalue(n, &h) < -0.5);
    p.accepted.clear();

    // Hessians only at accepted points, so the problem's record is the path
    let careful = NewtonOptions {
        eager_full_steps: false,
        ..NewtonOptions::default()
    };
    let mut newton = Newton::new(n, careful);
    let mut dp = Dense::new(&mut p);
    let r = newton.minimize(&mut dp, &mut x);
    assert!(r.converged(), "{r}");
    assert!(r.max_shift > 0.0, "a shift was needed: {r}");
    assert!(
        r.shifted_steps > 0 && r.shifted_steps <= r.iterations,
        "{r:?}"
    );
    // A minimum, not a saddle: the final Hessian is positive definite.
    assert!(min_eigenvalue(n, dp.matrix.matrix()) > 0.0);
    // Energy decreases monotonically along accepted iterates.
    assert_eq!(p.accepted.len(), r.iterations + 1);
    for w in p.accepted.windows(2) {
        assert!(w[1] <= w[0], "energy increased: {} -> {}", w[0], w[1]);
    }
    // The wells are tilted past their fold: the minimum is x_i = root of
    // x^3 - x - 0.5 (coupling vanishes at a uniform state).
    let root = {
        let mut t = 1.2f64;
        for _ in 0..50 {
            t -= (t * t * t - t - 0.5) / (3.0 * t * t - 1.0);
        }
        t
    };
    assert!(max_abs_diff(&x, &vec![root; n]) < 1e-9);
    // a gradient-only minimiser reaches the same minimiser
    let x0: Vec<f64> = (0..n).map(|i| 0.1 * ((i as f64) * 0.7).sin()).collect();
    assert!(max_abs_diff(&x, &lbfgs(&mut p, &x0, 1e-9)) < 1e-6);
}

#[test]
fn newton_stationary_start_reports_converged() {
    // Untilted wells at x = 0: g = 0 exactly (a saddle/maximum).
    let n = 3;
    let mut p = DoubleWell {
        n,
        kappa: 0.0,
        tilt: 0.0,
        accepted: vec![],
    };
    let mut x = vec![0.0; n];
    let mut newton = Newton::new(n, NewtonOptions::default());
    let mut dp = Dense::new(&mut p);
    let r = newton.minimize(&mut dp, &mut x);
    assert!(r.converged());
    assert!(
        min_eigenvalue(n, dp.matrix.matrix()) < 0.0,
        "documented: stability must be checked"
    );
}

#[test]
fn newton_recovers_from_nan_region_by_backtracking() {
    let n = 4;
    let mut p = Huber {
        n,
        c: 1.0,
        radius: 5.0,
    };
    let mut x = vec![3.0, -2.0, 4.0, 0.0];
    let mut newton = Newton::new(n, NewtonOptions::default());
    let r = newton.minimize(&mut Dense::new(&mut p), &mut x);
    assert!(r.converged(), "{r}");
    assert!(max_abs_diff(&x, &[1.0; 4]) < 1e-9);
    assert!(r.energy.is_finite());
}

#[test]
fn newton_never_returns_nan() {
    // The minimiser (c = 10) lies in the undefined region (radius 5).
    let n = 2;
    let mut p = Huber {
        n,
        c: 10.0,
        radius: 5.0,
    };
    let mut x = vec![0.0, 1.0];
    let mut newton = Newton::new(n, NewtonOptions::default());
    let r = newton.minimize(&mut Dense::new(&mut p), &mut x);
    assert!(!r.converged());
    assert!(
        matches!(
            r.reason,
            Termination::LineSearchFailed | Termination::NonFinite | Termination::StepTolerance
        ),
        "{r}"
    );
    assert!(x.iter().all(|v| v.is_finite() && v.abs() <= 5.0), "{x:?}");
    assert!(r.energy.is_finite() && r.residual_norm.is_finite());

    // A start in the undefined region is reported, x untouched.
    let mut x = vec![7.0, 0.0];
    let r = newton.minimize(&mut Dense::new(&mut p), &mut x);
    assert_eq!(r.reason, Termination::NonFinite);
    assert_eq!(x, vec![7.0, 0.0]);
    assert_eq!(r.energy, f64::INFINITY);
}

/// A Hessian that goes non-finite at an accepted point.
#[test]
fn newton_nonfinite_hessian_is_reported() {
    struct BadH(Rosenbrock);
    impl Energy for BadH {
        fn dim(&self) -> usize {
            2
        }
        fn energy(&mut self, x: &[f64]) -> f64 {
            self.0.energy(x)
        }
    }
    impl Gradient for BadH {
        fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
            self.0.gradient(x, g)
        }
    }
    impl DenseHessian for BadH {
        fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
            let f = self.0.hessian(x, g, h);
            if x[0] > -1.0 {
                h[1] = f64::INFINITY;
            }
            f
        }
    }
    // The bad Hessian is caught when it is factorised: x stays at that
    // iterate, whose energy and gradient are finite.
    let mut x = rosenbrock_start(2);
    let r = Newton::new(2, NewtonOptions::default())
        .minimize(&mut Dense::new(BadH(Rosenbrock { n: 2 })), &mut x);
    assert_eq!(r.reason, Termination::NonFinite);
    assert!(x[0] > -1.0 && x.iter().all(|v| v.is_finite()));
    assert!(r.energy.is_finite() && r.residual_norm.is_finite());
    assert_eq!(r.energy, Rosenbrock { n: 2 }.energy(&x));
    // A Hessian with NaN only in the (never read) upper triangle is harmless.
    struct UpperNan(Rosenbrock);
    impl Energy for UpperNan {
        fn dim(&self) -> usize {
            2
        }
        fn energy(&mut self, x: &[f64]) -> f64 {
            self.0.energy(x)
        }
    }
    impl Gradient for UpperNan {
        fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
            self.0.gradient(x, g)
        }
    }
    impl DenseHessian for UpperNan {
        fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
            let f = self.0.hessian(x, g, h);
            h[2] = f64::NAN;
            f
        }
    }
    let mut x = rosenbrock_start(2);
    let r = Newton::new(2, NewtonOptions::default())
        .minimize(&mut Dense::new(UpperNan(Rosenbrock { n: 2 })), &mut x);
    assert!(r.converged(), "{r}");
}

#[test]
fn newton_max_iterations() {
    let mut newton = Newton::new(
        2,
        NewtonOptions {
            max_iter: 3,
            ..Default::default()
        },
    );
    let mut x = rosenbrock_start(2);
    let f0 = Rosenbrock { n: 2 }.energy(&x);
    let r = newton.minimize(&mut Dense::new(Rosenbrock { n: 2 }), &mut x);
    assert_eq!(r.reason, Termination::MaxIterations);
    assert_eq!(r.iterations, 3);
    assert!(!r.converged());
    assert!(r.energy < f0);
    assert_eq!(Rosenbrock { n: 2 }.energy(&x), r.energy);
    // max_iter = 0 only evaluates the start.
    let mut newton = Newton::new(
        2,
        NewtonOptions {
            max_iter: 0,
            ..Default::default()
        },
    );
    let r = newton.minimize(&mut Dense::new(Rosenbrock { n: 2 }), &mut x);
    assert_eq!(
        (r.reason, r.iterations, r.hessian_evals),
        (Termination::MaxIterations, 0, 1)
    );
}

#[test]
fn newton_step_tolerance() {
    // gtol = 0 cannot be met in floating point: the solve stalls on xtol.
    let opts = NewtonOptions {
        gtol: 0.0,
        xtol: 1e-6,
        ..Default::default()
    };
    let mut x = rosenbrock_start(2);
    let r = Newton::new(2, opts).minimize(&mut Dense::new(Rosenbrock { n: 2 }), &mut x);
    assert!(
        matches!(
            r.reason,
            Termination::StepTolerance | Termination::Converged | Termination::LineSearchFailed
        ),
        "{r}"
    );
    assert!(max_abs_diff(&x, &[1.0, 1.0]) < 1e-6);
}

#[test]
fn invalid_options_do_not_panic() {
    let bad = NewtonOptions {
        gtol: f64::NAN,
        ..Default::default()
    };
    assert_eq!(Newton::try_new(2, bad).unwrap_err().name, "gtol");
    let mut newton = Newton::new(2, bad);
    let mut x = rosenbrock_start(2);
    let r = newton.minimize(&mut Dense::new(Rosenbrock { n: 2 }), &mut x);
    assert_eq!(r.reason, Termination::InvalidInput);
    assert_eq!(r.hessian_evals, 0);
    assert!(newton.set_options(NewtonOptions::default()).is_ok());
    assert!(newton
        .minimize(&mut Dense::new(Rosenbrock { n: 2 }), &mut x)
        .converged());
}

#[test]
fn zero_dimensional_problem() {
    let mut q = QuadQuartic {
        n: 0,
        a: vec![],
        b: vec![],
        w: vec![],
    };
    let r = Newton::new(0, NewtonOptions::default()).minimize(&mut Dense::new(&mut q), &mut []);
    assert!(r.converged());
}

#[test]
#[should_panic(expected = "x.len() must equal")]
fn dimension_mismatch_is_a_programmer_error() {
    let mut x = vec![0.0; 3];
    Newton::new(2, NewtonOptions::default()).minimize(&mut Dense::new(Rosenbrock { n: 2 }), &mut x);
}

#[test]
fn workspace_is_reusable() {
    let mut rng = Lcg::new(9);
    let mut newton = Newton::new(6, NewtonOptions::default());
    for _ in 0..5 {
        let mut q = QuadQuartic::random(6, true, &mut rng);
        let mut x = vec![0.0; 6];
        let r = newton.minimize(&mut Dense::new(&mut q), &mut x);
        assert!(r.converged());
        let mut g = vec![0.0; 6];
        q.gradient(&x, &mut g);
        assert!(g.iter().all(|v| v.abs() <= 1e-10));
        assert_eq!(newton.gradient(), &g[..]);
    }
}

/// `chord_depth` below 1: every solve that ends on chord steps ends with
/// its gradient at most that fraction of `gtol`, on the same random
/// problems, with the same Hessians; depths outside (0, 1] are refused.
#[test]
fn deeper_chord_steps_end_deeper_at_no_extra_hessian() {
    let mut rng = Lcg::new(11);
    let deep = NewtonOptions {
        chord_depth: 1e-2,
        ..NewtonOptions::default()
    };
    let mut ended_on_chords = 0;
    for &n in &[3usize, 10, 33] {
        for _ in 0..8 {
            let mut q = QuadQuartic::random(n, true, &mut rng);
            let mut xa = vec![0.0; n];
            let ra =
                Newton::new(n, NewtonOptions::default()).minimize(&mut Dense::new(&mut q), &mut xa);
            let mut xb = vec![0.0; n];
            let rb = Newton::new(n, deep).minimize(&mut Dense::new(&mut q), &mut xb);
            assert!(ra.converged() && rb.converged(), "n = {n}: {ra} / {rb}");
            assert!(rb.hessian_evals <= ra.hessian_evals, "n = {n}: {rb} / {ra}");
            if rb.chord_steps > ra.chord_steps {
                ended_on_chords += 1;
                assert!(rb.residual_norm <= 1e-2 * deep.gtol, "n = {n}: {rb}");
            }
        }
    }
    assert!(ended_on_chords > 0, "no solve went deeper");
    for bad in [0.0, -1.0, 1.5, f64::NAN] {
        let o = NewtonOptions {
            chord_depth: bad,
            ..NewtonOptions::default()
        };
        assert!(o.validate().is_err(), "{bad}");
    }
}

/// Newton with `opts` (eager full steps off) from the indefinite start of
/// the tilted wells, n = 12: it must converge to the minimiser (the
/// cubic's root), with the energy falling at every accepted step, along
/// some modified-Hessian steps; its report.
fn solve_tilted_wells(opts: NewtonOptions) -> Report {
    let n = 12;
    let mut x: Vec<f64> = (0..n).map(|i| 0.1 * ((i as f64) * 0.7).sin()).collect();
    let root = {
        let mut t = 1.2f64;
        for _ in 0..50 {
            t -= (t * t * t - t - 0.5) / (3.0 * t * t - 1.0);
        }
        t
    };
    let mut p = DoubleWell {
        n,
        kappa: 0.1,
        tilt: 0.5,
        accepted: vec![],
    };
    let opts = NewtonOptions {
        eager_full_steps: false,
        ..opts
    };
    let r = Newton::new(n, opts).minimize(&mut Dense::new(&mut p), &mut x);
    assert!(r.converged(), "{r}");
    assert!(r.shifted_steps > 0, "{r:?}");
    assert!(max_abs_diff(&x, &vec![root; n]) < 1e-9);
    for w in p.accepted.windows(2) {
        assert!(w[1] <= w[0], "energy increased: {} -> {}", w[0], w[1]);
    }
    r
}

/// Modified pivots on the tilted wells: directions from the modified
/// factorisation (no shift at all), in no more steps than the shifted
/// path.
#[test]
fn modified_pivots_reach_the_wells_minimum_without_a_shift() {
    let shifted = solve_tilted_wells(NewtonOptions::default());
    assert!(shifted.max_shift > 0.0, "{shifted:?}");
    let modified = solve_tilted_wells(NewtonOptions {
        modified_pivots: true,
        step_growth: true,
        extend_modified: true,
        ..NewtonOptions::default()
    });
    assert_eq!(modified.max_shift, 0.0, "{modified:?}");
    assert!(
        modified.iterations <= shifted.iterations,
        "{modified} / {shifted}"
    );
}

/// Shifted steps (no modified pivots) on the tilted wells, with and
/// without `extend_modified`: doublings counted only with the option, and
/// fewer steps with it.
#[test]
fn extended_shifted_steps_reach_the_wells_minimum_in_fewer_steps() {
    let plain = solve_tilted_wells(NewtonOptions::default());
    let extended = solve_tilted_wells(NewtonOptions {
        extend_modified: true,
        ..NewtonOptions::default()
    });
    for r in [&plain, &extended] {
        assert!(r.max_shift > 0.0, "{r:?}");
    }
    assert_eq!(plain.extended_steps, 0, "{plain:?}");
    assert!(extended.extended_steps > 0, "{extended:?}");
    assert!(
        extended.iterations < plain.iterations,
        "{extended} / {plain}"
    );
}

/// A minimum far beyond the step cap: capped steps taken whole double the
/// cap, so Newton gets there in a few steps where a fixed cap needs one
/// per cap length; both end at the minimiser `A^-1 b` (faer's LU).
#[test]
fn step_growth_crosses_a_long_way_in_a_few_capped_steps() {
    let mut rng = Lcg::new(21);
    let n = 5;
    let mut q = QuadQuartic::random(n, false, &mut rng);
    q.b.iter_mut().for_each(|b| *b *= 40.0);
    let want = lu_solve(n, &q.a, &q.b);
    let far = norm_inf_of(&want);
    assert!(far > 10.0, "{far}");
    let mut steps = [0; 2];
    for (k, growth) in [false, true].into_iter().enumerate() {
        let opts = NewtonOptions {
            max_step: 0.25,
            max_iter: 10_000,
            step_growth: growth,
            ..NewtonOptions::default()
        };
        let mut x = vec![0.0; n];
        let r = Newton::new(n, opts).minimize(&mut Dense::new(&mut q), &mut x);
        assert!(r.converged(), "{r}");
        assert!(max_abs_diff(&x, &want) <= 1e-9 * far);
        // the cap doubles four times (0.25 to 4) and no more
        assert_eq!(r.grown_steps, if growth { 4 } else { 0 }, "{r:?}");
        steps[k] = r.iterations;
    }
    assert!(steps[0] as f64 >= far / 0.25, "{steps:?}");
    // caps 0.25, 0.5, 1, 2 and 4 (16 times 0.25, the most) cover 7.75,
    // then 4 a step, and a few Newton steps at the end
    let bound = 5.0 + ((far - 7.75) / 4.0).max(0.0).ceil() + 4.0;
    assert!((steps[1] as f64) <= bound, "{steps:?}, bound {bound}");
}

/// `x^4 / 4 - c x` in one unknown: the Newton step from a point of small
/// curvature overshoots the minimum far, where the energy rises steeply.
struct SteepQuartic {
    c: f64,
}

impl Energy for SteepQuartic {
    fn dim(&self) -> usize {
        1
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        0.25 * x[0].powi(4) - self.c * x[0]
    }
}
impl Gradient for SteepQuartic {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        g[0] = x[0].powi(3) - self.c;
        self.energy(x)
    }
}
impl DenseHessian for SteepQuartic {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        h[0] = 3.0 * x[0] * x[0];
        self.gradient(x, g)
    }
}

/// A backtracked step lands near the minimum along its direction: the
/// cubic through the rejected and the accepted trials places it, where
/// the quadratic estimate alone (which ignores the accepted trial's value)
/// stops short (half of the decrease or less on three of these starts).
/// Checked against the best energy along the Newton step, found by brute
/// force, on starts whose steps overshoot the minimum several times.
#[test]
fn a_backtracked_step_takes_most_of_the_decrease_along_its_direction() {
    for (i, &(c, x0)) in [(1.0, 0.1), (1.0, 0.3), (8.0, 0.2), (0.2, 0.05), (1.0, -0.2)]
        .iter()
        .enumerate()
    {
        let mut q = SteepQuartic { c };
        let opts = NewtonOptions {
            max_iter: 1,
            ..NewtonOptions::default()
        };
        let mut x = vec![x0];
        let r = Newton::new(1, opts).minimize(&mut Dense::new(&mut q), &mut x);
        assert_eq!((r.iterations, r.damped_steps), (1, 1), "start {i}: {r:?}");
        // the Newton step from x0 and the best energy along it
        let step = -(x0.powi(3) - c) / (3.0 * x0 * x0);
        let f0 = q.energy(&[x0]);
        let best = (0..=100_000)
            .map(|k| q.energy(&[x0 + step * k as f64 / 100_000.0]))
            .fold(f64::INFINITY, f64::min);
        let taken = f0 - q.energy(&x);
        assert!(
            taken >= 0.8 * (f0 - best),
            "start {i}: {taken} of {} ({r:?})",
            f0 - best
        );
    }
}

/// `s x^2 / 2 + y^4 / 4 - y^2 / 2`: a stiff unknown beside a soft double
/// well (minima at x = 0, y = +-1), so that the Hessian's diagonal spans
/// `s` to about 1 and is indefinite near y = 0.
struct StiffBesideWell {
    s: f64,
}

impl Energy for StiffBesideWell {
    fn dim(&self) -> usize {
        2
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        0.5 * self.s * x[0] * x[0] + 0.25 * x[1].powi(4) - 0.5 * x[1] * x[1]
    }
}
impl Gradient for StiffBesideWell {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        g[0] = self.s * x[0];
        g[1] = x[1].powi(3) - x[1];
        self.energy(x)
    }
}
impl DenseHessian for StiffBesideWell {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        h.copy_from_slice(&[self.s, 0.0, 0.0, 3.0 * x[1] * x[1] - 1.0]);
        self.gradient(x, g)
    }
}

/// A shift of 1e-3 of the largest diagonal entry (1e5 here) makes the soft
/// unknown's steps about 1e-7 long from y = 0.01, and Newton used up its
/// 100 iterations there. Under a step cap the first shift is at most the
/// gradient over the cap, so the doubling stops near the least shift that
/// factorises, and Newton leaves the top of the well for the minimum
/// (x, y) = (0, 1) in a few steps, each shorter than the cap. Without a
/// cap the shifts are the unchanged ones.
#[test]
fn shifts_under_a_cap_do_not_crawl_on_a_badly_scaled_hessian() {
    let mut p = StiffBesideWell { s: 1e8 };
    let opts = NewtonOptions {
        max_step: 1.0,
        ..NewtonOptions::default()
    };
    let mut x = vec![0.0, 0.01];
    let r = Newton::new(2, opts).minimize(&mut Dense::new(&mut p), &mut x);
    assert!(r.converged(), "{r:?}");
    assert!(r.max_shift > 0.0 && r.max_shift < 10.0, "{r:?}");
    assert!(r.iterations <= 15, "{r:?}");
    assert!(x[0].abs() < 1e-12 && (x[1] - 1.0).abs() < 1e-9, "{x:?}");
    // without a cap the first shift is 1e-3 of the diagonal's largest
    // entry, as before
    let mut x = vec![0.0, 0.01];
    let r = Newton::new(2, NewtonOptions::default()).minimize(&mut Dense::new(&mut p), &mut x);
    assert!(r.max_shift >= 1e5, "{r:?}");
}

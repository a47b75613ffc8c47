//! Solver tests. Every check compares against an independent method
//! (closed forms, nalgebra's LU, BFGS vs Newton, Newton vs the bordered
//! solve); randomness is seeded.

#![allow(clippy::needless_range_loop)]

use crate::testutil::Lcg;
use crate::*;

// ---------------------------------------------------------------- problems

/// `1/2 x^T A x - b^T x + sum_i w_i x_i^4 / 4` (convex when A is SPD, w >= 0).
#[derive(Clone)]
struct QuadQuartic {
    n: usize,
    a: Vec<f64>,
    b: Vec<f64>,
    w: Vec<f64>,
}

impl QuadQuartic {
    fn random(n: usize, quartic: bool, rng: &mut Lcg) -> Self {
        let m: Vec<f64> = (0..n * n).map(|_| rng.sym()).collect();
        let mut a = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                let s: f64 = (0..n).map(|k| m[i + k * n] * m[j + k * n]).sum();
                a[i + j * n] = s + if i == j { 0.1 } else { 0.0 };
            }
        }
        let b = (0..n).map(|_| 3.0 * rng.sym()).collect();
        let w = (0..n)
            .map(|_| if quartic { 2.0 * rng.unit() } else { 0.0 })
            .collect();
        QuadQuartic { n, a, b, w }
    }
    fn ax(&self, x: &[f64], i: usize) -> f64 {
        (0..self.n).map(|j| self.a[i + j * self.n] * x[j]).sum()
    }
}

impl Energy for QuadQuartic {
    fn dim(&self) -> usize {
        self.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        (0..self.n)
            .map(|i| {
                0.5 * x[i] * self.ax(x, i) - self.b[i] * x[i] + 0.25 * self.w[i] * x[i].powi(4)
            })
            .sum()
    }
}
impl Gradient for QuadQuartic {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        for i in 0..self.n {
            g[i] = self.ax(x, i) - self.b[i] + self.w[i] * x[i].powi(3);
        }
        self.energy(x)
    }
}
impl Hessian for QuadQuartic {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        h.copy_from_slice(&self.a);
        for i in 0..self.n {
            h[i * (self.n + 1)] += 3.0 * self.w[i] * x[i] * x[i];
        }
        self.gradient(x, g)
    }
}

/// Extended Rosenbrock (Moré–Garbow–Hillstrom): independent pairs,
/// unique minimiser at all ones.
struct Rosenbrock {
    n: usize,
}

impl Energy for Rosenbrock {
    fn dim(&self) -> usize {
        self.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        (0..self.n / 2)
            .map(|k| {
                let (u, v) = (x[2 * k], x[2 * k + 1]);
                100.0 * (v - u * u).powi(2) + (1.0 - u).powi(2)
            })
            .sum()
    }
}
impl Gradient for Rosenbrock {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        for k in 0..self.n / 2 {
            let (u, v) = (x[2 * k], x[2 * k + 1]);
            g[2 * k] = -400.0 * u * (v - u * u) - 2.0 * (1.0 - u);
            g[2 * k + 1] = 200.0 * (v - u * u);
        }
        self.energy(x)
    }
}
impl Hessian for Rosenbrock {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let n = self.n;
        h.fill(0.0);
        for k in 0..n / 2 {
            let (i, j) = (2 * k, 2 * k + 1);
            let (u, v) = (x[i], x[j]);
            h[i + i * n] = 1200.0 * u * u - 400.0 * v + 2.0;
            h[i + j * n] = -400.0 * u;
            h[j + i * n] = -400.0 * u;
            h[j + j * n] = 200.0;
        }
        self.gradient(x, g)
    }
}

fn rosenbrock_start(n: usize) -> Vec<f64> {
    (0..n)
        .map(|i| if i % 2 == 0 { -1.2 } else { 1.0 })
        .collect()
}

/// Tilted double wells with a chain coupling:
/// `sum_i (x_i^4/4 - x_i^2/2 - tilt x_i) + kappa/2 sum_i (x_{i+1} - x_i)^2`.
/// The Hessian `3 x_i^2 - 1 + coupling` is indefinite near 0. Records the
/// energy at every Hessian evaluation (= every accepted Newton iterate).
struct DoubleWell {
    n: usize,
    kappa: f64,
    tilt: f64,
    accepted: Vec<f64>,
}

impl Energy for DoubleWell {
    fn dim(&self) -> usize {
        self.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        let mut f = 0.0;
        for i in 0..self.n {
            f += x[i].powi(4) / 4.0 - x[i] * x[i] / 2.0 - self.tilt * x[i];
            if i + 1 < self.n {
                f += 0.5 * self.kappa * (x[i + 1] - x[i]).powi(2);
            }
        }
        f
    }
}
impl Gradient for DoubleWell {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let n = self.n;
        for i in 0..n {
            g[i] = x[i].powi(3) - x[i] - self.tilt;
        }
        for i in 0..n - 1 {
            let d = self.kappa * (x[i + 1] - x[i]);
            g[i + 1] += d;
            g[i] -= d;
        }
        self.energy(x)
    }
}
impl Hessian for DoubleWell {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let n = self.n;
        h.fill(0.0);
        for i in 0..n {
            h[i * (n + 1)] = 3.0 * x[i] * x[i] - 1.0;
        }
        for i in 0..n - 1 {
            let k = self.kappa;
            h[i * (n + 1)] += k;
            h[(i + 1) * (n + 1)] += k;
            h[i + (i + 1) * n] -= k;
            h[(i + 1) + i * n] -= k;
        }
        let f = self.gradient(x, g);
        self.accepted.push(f);
        f
    }
}

/// Pseudo-Huber `sum_i sqrt(1 + (x_i - c)^2)`, undefined (NaN) outside
/// `||x||_inf <= radius`. Newton's full step overshoots wildly far from
/// the minimiser `x = c`, into the undefined region.
struct Huber {
    n: usize,
    c: f64,
    radius: f64,
}

impl Huber {
    fn outside(&self, x: &[f64]) -> bool {
        x.iter().any(|v| v.abs() > self.radius)
    }
}
impl Energy for Huber {
    fn dim(&self) -> usize {
        self.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        if self.outside(x) {
            return f64::NAN;
        }
        x.iter().map(|v| (1.0 + (v - self.c).powi(2)).sqrt()).sum()
    }
}
impl Gradient for Huber {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        for (gi, v) in g.iter_mut().zip(x) {
            let d = v - self.c;
            *gi = if self.outside(x) {
                f64::NAN
            } else {
                d / (1.0 + d * d).sqrt()
            };
        }
        self.energy(x)
    }
}
impl Hessian for Huber {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let n = self.n;
        h.fill(0.0);
        for i in 0..n {
            let d = x[i] - self.c;
            h[i * (n + 1)] = (1.0 + d * d).powf(-1.5);
        }
        self.gradient(x, g)
    }
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max)
}

fn bfgs_tight() -> BfgsOptions {
    BfgsOptions::default().with_gtol(1e-9).unwrap()
}

// ------------------------------------------------------------------ Newton

#[test]
fn newton_convex_quadratic_takes_one_step() {
    let mut rng = Lcg::new(42);
    for &n in &[1usize, 3, 10, 33] {
        let mut q = QuadQuartic::random(n, false, &mut rng);
        let mut newton = Newton::new(n, NewtonOptions::default());
        let mut x = vec![0.0; n];
        let r = newton.minimize(&mut q, &mut x);
        assert!(r.converged(), "n = {n}: {r}");
        assert_eq!(r.iterations, 1, "n = {n}: {r}");
        assert_eq!(r.max_shift, 0.0);
        assert_eq!(r.hessian_evals, 2);
        // Independent: nalgebra LU solve of A x = b.
        let a = nalgebra::DMatrix::from_column_slice(n, n, &q.a);
        let xs = a
            .lu()
            .solve(&nalgebra::DVector::from_column_slice(&q.b))
            .unwrap();
        let d = max_abs_diff(&x, xs.as_slice());
        assert!(d < 1e-8 * (1.0 + xs.amax()), "n = {n}: differs by {d}");
    }
}

#[test]
fn newton_rosenbrock_2_and_10() {
    for &n in &[2usize, 10] {
        let mut p = Rosenbrock { n };
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

#[test]
fn newton_backends_agree() {
    let n = 10;
    let mut a = Newton::new(
        n,
        NewtonOptions::default().with_backend(LinearBackend::Dense),
    );
    let mut b = Newton::new(
        n,
        NewtonOptions::default().with_backend(LinearBackend::Faer),
    );
    assert_eq!(a.backend(), LinearBackend::Dense);
    assert_eq!(b.backend(), LinearBackend::Faer);
    let mut xa = rosenbrock_start(n);
    let mut xb = rosenbrock_start(n);
    let ra = a.minimize(&mut Rosenbrock { n }, &mut xa);
    let rb = b.minimize(&mut Rosenbrock { n }, &mut xb);
    assert!(ra.converged() && rb.converged());
    assert!(max_abs_diff(&xa, &xb) < 1e-10);
    // Indefinite starts too (the shift loop runs through faer).
    let mut dw = DoubleWell {
        n,
        kappa: 0.1,
        tilt: 0.5,
        accepted: vec![],
    };
    let mut xa = vec![0.05; n];
    let mut xb = vec![0.05; n];
    assert!(a.minimize(&mut dw, &mut xa).converged());
    assert!(b.minimize(&mut dw, &mut xb).converged());
    assert!(max_abs_diff(&xa, &xb) < 1e-9);
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
    let r = newton.minimize(&mut p, &mut x);
    assert!(r.converged(), "{r}");
    assert!(r.max_shift > 0.0, "a shift was needed: {r}");
    // A minimum, not a saddle: the final Hessian is positive definite.
    assert!(min_eigenvalue(n, newton.hessian()) > 0.0);
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
    // BFGS (never sees a Hessian) reaches the same minimiser.
    let mut xb: Vec<f64> = (0..n).map(|i| 0.1 * ((i as f64) * 0.7).sin()).collect();
    let rb = Bfgs::new(n, bfgs_tight()).minimize(&mut p, &mut xb);
    assert!(rb.converged(), "{rb}");
    assert!(max_abs_diff(&x, &xb) < 1e-6);
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
    let r = newton.minimize(&mut p, &mut x);
    assert!(r.converged());
    assert!(
        min_eigenvalue(n, newton.hessian()) < 0.0,
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
    let r = newton.minimize(&mut p, &mut x);
    assert!(r.converged(), "{r}");
    assert!(max_abs_diff(&x, &[1.0; 4]) < 1e-9);
    assert!(r.energy.is_finite());
    let mut xb = vec![3.0, -2.0, 4.0, 0.0];
    let rb = Bfgs::new(n, bfgs_tight()).minimize(&mut p, &mut xb);
    assert!(rb.converged(), "{rb}");
    assert!(max_abs_diff(&x, &xb) < 1e-6);
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
    let r = newton.minimize(&mut p, &mut x);
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
    let mut xb = vec![0.0, 1.0];
    let rb = Bfgs::new(n, BfgsOptions::default()).minimize(&mut p, &mut xb);
    assert!(!rb.converged());
    assert!(xb.iter().all(|v| v.is_finite() && v.abs() <= 5.0), "{xb:?}");

    // A start in the undefined region is reported, x untouched.
    let mut x = vec![7.0, 0.0];
    let r = newton.minimize(&mut p, &mut x);
    assert_eq!(r.reason, Termination::NonFinite);
    assert_eq!(x, vec![7.0, 0.0]);
    assert_eq!(r.energy, f64::INFINITY);
    let rb = Bfgs::new(n, BfgsOptions::default()).minimize(&mut p, &mut x);
    assert_eq!(rb.reason, Termination::NonFinite);
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
    impl Hessian for BadH {
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
    let r =
        Newton::new(2, NewtonOptions::default()).minimize(&mut BadH(Rosenbrock { n: 2 }), &mut x);
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
    impl Hessian for UpperNan {
        fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
            let f = self.0.hessian(x, g, h);
            h[2] = f64::NAN;
            f
        }
    }
    let mut x = rosenbrock_start(2);
    let r = Newton::new(2, NewtonOptions::default())
        .minimize(&mut UpperNan(Rosenbrock { n: 2 }), &mut x);
    assert!(r.converged(), "{r}");
}

#[test]
fn newton_max_iterations() {
    let mut newton = Newton::new(2, NewtonOptions::default().with_max_iter(3));
    let mut x = rosenbrock_start(2);
    let f0 = Rosenbrock { n: 2 }.energy(&x);
    let r = newton.minimize(&mut Rosenbrock { n: 2 }, &mut x);
    assert_eq!(r.reason, Termination::MaxIterations);
    assert_eq!(r.iterations, 3);
    assert!(!r.converged());
    assert!(r.energy < f0);
    assert_eq!(Rosenbrock { n: 2 }.energy(&x), r.energy);
    // max_iter = 0 only evaluates the start.
    let mut newton = Newton::new(2, NewtonOptions::default().with_max_iter(0));
    let r = newton.minimize(&mut Rosenbrock { n: 2 }, &mut x);
    assert_eq!(
        (r.reason, r.iterations, r.hessian_evals),
        (Termination::MaxIterations, 0, 1)
    );
}

#[test]
fn newton_step_tolerance() {
    // gtol = 0 cannot be met in floating point: the solve stalls on xtol.
    let opts = NewtonOptions::default()
        .with_gtol(0.0)
        .unwrap()
        .with_xtol(1e-6)
        .unwrap();
    let mut x = rosenbrock_start(2);
    let r = Newton::new(2, opts).minimize(&mut Rosenbrock { n: 2 }, &mut x);
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
    let r = newton.minimize(&mut Rosenbrock { n: 2 }, &mut x);
    assert_eq!(r.reason, Termination::InvalidInput);
    assert_eq!(r.hessian_evals, 0);
    assert!(newton.set_options(NewtonOptions::default()).is_ok());
    assert!(newton
        .minimize(&mut Rosenbrock { n: 2 }, &mut x)
        .converged());
    let bad_b = BfgsOptions {
        c2: f64::NAN,
        ..Default::default()
    };
    assert!(Bfgs::try_new(2, bad_b).is_err());
    assert_eq!(
        Bfgs::new(2, bad_b)
            .minimize(&mut Rosenbrock { n: 2 }, &mut x)
            .reason,
        Termination::InvalidInput
    );
}

#[test]
fn zero_dimensional_problem() {
    let mut q = QuadQuartic {
        n: 0,
        a: vec![],
        b: vec![],
        w: vec![],
    };
    let r = Newton::new(0, NewtonOptions::default()).minimize(&mut q, &mut []);
    assert!(r.converged());
    let r = Bfgs::new(0, BfgsOptions::default()).minimize(&mut q, &mut []);
    assert!(r.converged());
}

#[test]
#[should_panic(expected = "x.len() must equal")]
fn dimension_mismatch_is_a_programmer_error() {
    let mut x = vec![0.0; 3];
    Newton::new(2, NewtonOptions::default()).minimize(&mut Rosenbrock { n: 2 }, &mut x);
}

#[test]
fn workspace_is_reusable() {
    let mut rng = Lcg::new(9);
    let mut newton = Newton::new(6, NewtonOptions::default());
    for _ in 0..5 {
        let mut q = QuadQuartic::random(6, true, &mut rng);
        let mut x = vec![0.0; 6];
        let r = newton.minimize(&mut q, &mut x);
        assert!(r.converged());
        let mut g = vec![0.0; 6];
        q.gradient(&x, &mut g);
        assert!(g.iter().all(|v| v.abs() <= 1e-10));
        assert_eq!(newton.gradient(), &g[..]);
    }
}

// -------------------------------------------------------------------- BFGS

#[test]
fn bfgs_matches_newton() {
    let mut rng = Lcg::new(77);
    for &n in &[2usize, 10] {
        let mut xn = rosenbrock_start(n);
        let mut xb = rosenbrock_start(n);
        assert!(Newton::new(n, NewtonOptions::default())
            .minimize(&mut Rosenbrock { n }, &mut xn)
            .converged());
        let rb = Bfgs::new(n, bfgs_tight()).minimize(&mut Rosenbrock { n }, &mut xb);
        assert!(rb.converged(), "n = {n}: {rb}");
        assert_eq!(rb.hessian_evals, 0);
        assert!(max_abs_diff(&xn, &xb) < 1e-6, "n = {n}");
    }
    for _ in 0..3 {
        let n = 8;
        let mut q = QuadQuartic::random(n, true, &mut rng);
        let mut xn = vec![0.0; n];
        let mut xb = vec![0.0; n];
        assert!(Newton::new(n, NewtonOptions::default())
            .minimize(&mut q, &mut xn)
            .converged());
        let rb = Bfgs::new(n, bfgs_tight()).minimize(&mut q, &mut xb);
        assert!(rb.converged(), "{rb}");
        assert!(max_abs_diff(&xn, &xb) < 1e-6);
    }
}

#[test]
fn bfgs_max_iterations() {
    let mut x = rosenbrock_start(2);
    let r = Bfgs::new(2, BfgsOptions::default().with_max_iter(2))
        .minimize(&mut Rosenbrock { n: 2 }, &mut x);
    assert_eq!(r.reason, Termination::MaxIterations);
    assert_eq!(r.iterations, 2);
}

// ---------------------------------------------------------------- Bordered

/// `E = 1/2 x^T A x + sum w_i x_i^4/4 - lambda b^T x`, target
/// `c = e^T x - t`.
struct BorderedQQ {
    q: QuadQuartic,
    e: Vec<f64>,
    t: f64,
}

impl Bordered for BorderedQQ {
    fn dim(&self) -> usize {
        self.q.n
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval) -> bool {
        let n = self.q.n;
        for i in 0..n {
            out.g[i] = self.q.ax(x, i) + self.q.w[i] * x[i].powi(3) - lambda * self.q.b[i];
            out.g_lambda[i] = -self.q.b[i];
            out.c_x[i] = self.e[i];
        }
        out.h.copy_from_slice(&self.q.a);
        for i in 0..n {
            out.h[i * (n + 1)] += 3.0 * self.q.w[i] * x[i] * x[i];
        }
        out.c = (0..n).map(|i| self.e[i] * x[i]).sum::<f64>() - self.t;
        out.c_lambda = 0.0;
        true
    }
}

/// Plain energy of [`BorderedQQ`] at a fixed lambda.
struct AtLoad<'a>(&'a BorderedQQ, f64);

impl Energy for AtLoad<'_> {
    fn dim(&self) -> usize {
        self.0.q.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        let mut q = self.0.q.clone();
        q.b.iter_mut().for_each(|b| *b *= self.1);
        q.energy(x)
    }
}
impl Gradient for AtLoad<'_> {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let mut q = self.0.q.clone();
        q.b.iter_mut().for_each(|b| *b *= self.1);
        q.gradient(x, g)
    }
}
impl Hessian for AtLoad<'_> {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let mut q = self.0.q.clone();
        q.b.iter_mut().for_each(|b| *b *= self.1);
        q.hessian(x, g, h)
    }
}

#[test]
fn bordered_linear_matches_closed_form() {
    let mut rng = Lcg::new(21);
    for &n in &[1usize, 4, 12] {
        let q = QuadQuartic::random(n, false, &mut rng);
        let e: Vec<f64> = (0..n).map(|_| rng.sym()).collect();
        let mut p = BorderedQQ { q, e, t: 0.7 };
        let mut x = vec![0.0; n];
        let mut lambda = 0.0;
        let mut newton = Newton::new(n, NewtonOptions::default());
        let r = newton.solve_bordered(&mut p, &mut x, &mut lambda);
        assert!(r.converged(), "n = {n}: {r}");
        assert_eq!(r.iterations, 1, "linear problem: one step");
        // Closed form: x = lambda A^{-1} b, e^T x = t.
        let a = nalgebra::DMatrix::from_column_slice(n, n, &p.q.a);
        let z = a
            .lu()
            .solve(&nalgebra::DVector::from_column_slice(&p.q.b))
            .unwrap();
        let ez: f64 = (0..n).map(|i| p.e[i] * z[i]).sum();
        let lam = p.t / ez;
        assert!(
            (lambda - lam).abs() < 1e-9 * (1.0 + lam.abs()),
            "n = {n}: {lambda} vs {lam}"
        );
        for i in 0..n {
            assert!((x[i] - lam * z[i]).abs() < 1e-9 * (1.0 + (lam * z[i]).abs()));
        }
    }
}

#[test]
fn bordered_nonlinear_agrees_with_plain_newton() {
    let mut rng = Lcg::new(5);
    let n = 8;
    let q = QuadQuartic::random(n, true, &mut rng);
    let e: Vec<f64> = (0..n).map(|i| if i == n - 1 { 1.0 } else { 0.1 }).collect();
    let mut p = BorderedQQ { q, e, t: 2.5 };
    let mut x = vec![0.0; n];
    let mut lambda = 0.0;
    let mut newton = Newton::new(n, NewtonOptions::default());
    let r = newton.solve_bordered(&mut p, &mut x, &mut lambda);
    assert!(r.converged(), "{r}");
    assert_eq!(r.energy_evals, 0);
    assert!(r.hessian_evals > r.iterations);
    // Feed lambda back into plain minimisation from a cold start.
    let mut y = vec![0.0; n];
    let rr = newton.minimize(&mut AtLoad(&p, lambda), &mut y);
    assert!(rr.converged(), "{rr}");
    let c: f64 = (0..n).map(|i| p.e[i] * y[i]).sum::<f64>() - p.t;
    assert!(c.abs() < 1e-8, "target residual {c}");
    assert!(max_abs_diff(&x, &y) < 1e-8);
}

/// One dof past a limit point in load: `E = x^4/4 - x^2/2 - lambda x`,
/// target `x = t` with `t` where `E'' < 0`. Displacement control passes
/// where load control cannot.
#[test]
fn bordered_passes_limit_point() {
    struct Snap {
        t: f64,
    }
    impl Bordered for Snap {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval) -> bool {
            out.g[0] = x[0].powi(3) - x[0] - lambda;
            out.h[0] = 3.0 * x[0] * x[0] - 1.0;
            out.g_lambda[0] = -1.0;
            out.c = x[0] - self.t;
            out.c_x[0] = 1.0;
            out.c_lambda = 0.0;
            true
        }
    }
    for &t in &[-0.3, 0.2, 0.5, 1.5] {
        let mut x = [0.9];
        let mut lambda = 0.0;
        let r = Newton::new(1, NewtonOptions::default()).solve_bordered(
            &mut Snap { t },
            &mut x,
            &mut lambda,
        );
        assert!(r.converged(), "t = {t}: {r}");
        assert!((x[0] - t).abs() < 1e-12);
        assert!((lambda - (t * t * t - t)).abs() < 1e-12);
    }
}

#[test]
fn bordered_singular_and_nonfinite() {
    // c depends on nothing: the bordered Jacobian is singular.
    struct Flat;
    impl Bordered for Flat {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], _lambda: f64, out: &mut BorderedEval) -> bool {
            out.g[0] = x[0] - 1.0;
            out.h[0] = 1.0;
            out.g_lambda[0] = 0.0;
            out.c = 1.0;
            out.c_x[0] = 0.0;
            out.c_lambda = 0.0;
            true
        }
    }
    let mut x = [0.0];
    let mut lambda = 0.0;
    let mut newton = Newton::new(1, NewtonOptions::default());
    let r = newton.solve_bordered(&mut Flat, &mut x, &mut lambda);
    assert_eq!(r.reason, Termination::Singular);
    let mut lambda = f64::NAN;
    let r = newton.solve_bordered(&mut Flat, &mut x, &mut lambda);
    assert_eq!(r.reason, Termination::NonFinite);
}

// ------------------------------------------------------------ Continuation

/// `sum_i cosh(x_i - t) + kappa/2 sum (x_{i+1} - x_i)^2 + s/2 |x|^2 ...`:
/// minimiser `x_i = t`. Newton's step is at most ~1 per iteration far from
/// it (`-tanh`), so a cold start at large `t` needs many iterations.
struct CoshChain {
    n: usize,
    t: f64,
    kappa: f64,
}

impl Energy for CoshChain {
    fn dim(&self) -> usize {
        self.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        let mut f = 0.0;
        for i in 0..self.n {
            f += (x[i] - self.t).cosh();
            if i + 1 < self.n {
                f += 0.5 * self.kappa * (x[i + 1] - x[i]).powi(2);
            }
        }
        f
    }
}
impl Gradient for CoshChain {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let n = self.n;
        for i in 0..n {
            g[i] = (x[i] - self.t).sinh();
        }
        for i in 0..n - 1 {
            let d = self.kappa * (x[i + 1] - x[i]);
            g[i + 1] += d;
            g[i] -= d;
        }
        self.energy(x)
    }
}
impl Hessian for CoshChain {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let n = self.n;
        h.fill(0.0);
        for i in 0..n {
            h[i * (n + 1)] = (x[i] - self.t).cosh();
        }
        for i in 0..n - 1 {
            let k = self.kappa;
            h[i * (n + 1)] += k;
            h[(i + 1) * (n + 1)] += k;
            h[i + (i + 1) * n] -= k;
            h[(i + 1) + i * n] -= k;
        }
        self.gradient(x, g)
    }
}

#[test]
fn continuation_succeeds_where_cold_start_fails() {
    let n = 4;
    let opts = NewtonOptions::default().with_max_iter(8);
    let mut newton = Newton::new(n, opts);
    let mut p = CoshChain {
        n,
        t: 0.0,
        kappa: 0.5,
    };

    // Cold start at t = 20 fails within 8 iterations.
    p.t = 20.0;
    let mut x = vec![0.0; n];
    let cold = newton.minimize(&mut p, &mut x);
    assert_eq!(cold.reason, Termination::MaxIterations);

    // Continuation with a deliberately too-large first step.
    let copts = ContinuationOptions::default()
        .with_steps(12.0, 1e-3, 20.0)
        .unwrap();
    let mut x = vec![0.0; n];
    let rep = continuation(0.0, 20.0, &mut x, &copts, |t, x| {
        p.t = t;
        newton.minimize(&mut p, x)
    });
    assert!(rep.complete, "{rep:?}");
    assert_eq!(rep.reached, 20.0);
    assert!(
        rep.rejected > 0,
        "the first 12-unit step must fail: {rep:?}"
    );
    assert!(rep.last.converged());
    assert!(max_abs_diff(&x, &[20.0; 4]) < 1e-9);
    assert!(rep.newton_iterations > 0);

    // Back down (reverse direction), without predictor.
    let copts = copts.with_predictor(false);
    let rep = continuation(20.0, 0.0, &mut x, &copts, |t, x| {
        p.t = t;
        newton.minimize(&mut p, x)
    });
    assert!(rep.complete, "{rep:?}");
    assert!(max_abs_diff(&x, &[0.0; 4]) < 1e-9);
}

#[test]
fn continuation_stops_incomplete_and_restores_state() {
    let n = 2;
    let mut newton = Newton::new(n, NewtonOptions::default().with_max_iter(8));
    let mut p = CoshChain {
        n,
        t: 0.0,
        kappa: 0.0,
    };
    // Beyond t = 5 the "solver" refuses: the driver must stop at <= 5.
    let copts = ContinuationOptions::default()
        .with_steps(1.0, 0.01, 2.0)
        .unwrap();
    let mut x = vec![0.0; n];
    let mut calls = 0;
    let rep = continuation(0.0, 10.0, &mut x, &copts, |t, x| {
        calls += 1;
        p.t = t;
        let r = newton.minimize(&mut p, x);
        if t > 5.0 {
            x.iter_mut().for_each(|v| *v = f64::NAN);
            Report {
                reason: Termination::NonFinite,
                ..r
            }
        } else {
            r
        }
    });
    assert!(!rep.complete);
    assert!(rep.reached <= 5.0 && rep.reached > 4.9, "{rep:?}");
    assert!(rep.rejected > 0);
    assert_eq!(rep.steps + rep.rejected, calls);
    assert!(
        max_abs_diff(&x, &[rep.reached; 2]) < 1e-9,
        "x restored to the last accepted state"
    );

    // max_steps bounds the attempts.
    let mut x = vec![0.0; n];
    let rep = continuation(0.0, 10.0, &mut x, &copts.with_max_steps(3), |t, x| {
        p.t = t;
        newton.minimize(&mut p, x)
    });
    assert!(!rep.complete);
    assert_eq!(rep.steps + rep.rejected, 3);

    // Invalid input: nothing is called.
    let rep = continuation(0.0, f64::NAN, &mut x, &copts, |_, _| unreachable!());
    assert_eq!(rep.last.reason, Termination::InvalidInput);
    let bad = ContinuationOptions {
        shrink: 2.0,
        ..Default::default()
    };
    let rep = continuation(0.0, 1.0, &mut x, &bad, |_, _| unreachable!());
    assert!(!rep.complete);

    // from == to: a single solve.
    let mut x = vec![0.3; n];
    let rep = continuation(0.3, 0.3, &mut x, &copts, |t, x| {
        p.t = t;
        newton.minimize(&mut p, x)
    });
    assert!(rep.complete && rep.steps == 1);
}

// ---------------------------------------------------------------- proptest

mod prop {
    use super::*;
    use proptest::prelude::*;

    proptest! {
        #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

        /// On random convex quadratic + quartic energies, Newton converges
        /// and, when it reports convergence, the gradient recomputed
        /// independently is within gtol.
        #[test]
        fn newton_gradient_within_gtol(seed in any::<u64>(), n in 1usize..14, scale in 0.1f64..10.0) {
            let mut rng = Lcg::new(seed);
            let mut q = QuadQuartic::random(n, true, &mut rng);
            q.b.iter_mut().for_each(|b| *b *= scale);
            let mut x: Vec<f64> = (0..n).map(|_| 2.0 * rng.sym()).collect();
            let opts = NewtonOptions::default();
            let r = Newton::new(n, opts).minimize(&mut q, &mut x);
            prop_assert!(r.converged(), "{}", r);
            let mut g = vec![0.0; n];
            q.gradient(&x, &mut g);
            let gn = g.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            prop_assert!(gn <= opts.gtol, "|g| = {}", gn);
            prop_assert_eq!(gn, r.residual_norm);
        }

        /// Cholesky + solve residual on random SPD matrices, both kernels.
        #[test]
        fn cholesky_residual(seed in any::<u64>(), n in 1usize..40) {
            let mut rng = Lcg::new(seed);
            let q = QuadQuartic::random(n, false, &mut rng);
            let mut l = q.a.clone();
            cholesky_in_place(n, &mut l).unwrap();
            let mut x = q.b.clone();
            cholesky_solve(n, &l, &mut x);
            let mut lp = q.a.clone();
            crate::dense::cholesky_portable(n, &mut lp).unwrap();
            let mut xp = q.b.clone();
            crate::dense::cholesky_solve_portable(n, &lp, &mut xp);
            let amax = q.a.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            for (xx, tag) in [(&x, "kernel"), (&xp, "portable")] {
                let xmax = xx.iter().fold(0.0f64, |m, v| m.max(v.abs()));
                for i in 0..n {
                    let r = q.ax(xx, i) - q.b[i];
                    // Condition number of A = B B^T + 0.1 I can reach ~1e3 n.
                    prop_assert!(r.abs() <= 1e-13 * n as f64 * amax * xmax.max(1.0), "{} row {}: {}", tag, i, r);
                }
            }
        }
    }
}

/// Timing of complete Newton solves. Run with
/// `cargo test -p fpc-newton --release -- --ignored --nocapture newton_timing`.
#[test]
#[ignore]
fn newton_timing() {
    use std::time::Instant;
    for &n in &[8usize, 16, 32, 64, 128] {
        let mut rng = Lcg::new(n as u64);
        let mut q = QuadQuartic::random(n, true, &mut rng);
        let x0: Vec<f64> = (0..n).map(|_| rng.sym()).collect();
        let mut newton = Newton::new(n, NewtonOptions::default());
        let mut x = x0.clone();
        let r = newton.minimize(&mut q, &mut x);
        assert!(r.converged());
        let reps = (2_000_000 / (n * n)).max(50);
        let mut best = f64::INFINITY;
        for _ in 0..5 {
            let t = Instant::now();
            for _ in 0..reps {
                x.copy_from_slice(&x0);
                std::hint::black_box(newton.minimize(&mut q, &mut x));
            }
            best = best.min(t.elapsed().as_secs_f64() / reps as f64);
        }
        // The same objective calls without the solver.
        let (mut g, mut h) = (vec![0.0; n], vec![0.0; n * n]);
        let mut best_eval = f64::INFINITY;
        for _ in 0..5 {
            let t = Instant::now();
            for _ in 0..reps {
                for _ in 0..r.hessian_evals {
                    std::hint::black_box(q.hessian(&x0, &mut g, &mut h));
                }
                for _ in 0..r.energy_evals {
                    std::hint::black_box(q.energy(&x0));
                }
            }
            best_eval = best_eval.min(t.elapsed().as_secs_f64() / reps as f64);
        }
        println!(
            "n = {n:3}: {} iterations, total {:.2} us, objective calls {:.2} us, solver {:.2} us ({:.2} us/iteration)",
            r.iterations,
            best * 1e6,
            best_eval * 1e6,
            (best - best_eval) * 1e6,
            (best - best_eval) * 1e6 / r.iterations as f64
        );
    }
}

/// A problem that solves its own Newton systems (through the public dense
/// kernels) and counts the calls.
struct OwnSolve {
    inner: Rosenbrock,
    calls: usize,
}

impl Energy for OwnSolve {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.inner.energy(x)
    }
}

impl Gradient for OwnSolve {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.inner.gradient(x, g)
    }
}

impl Hessian for OwnSolve {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        self.inner.hessian(x, g, h)
    }
    fn solve_shifted(&mut self, h: &[f64], g: &[f64], tau: f64, p: &mut [f64]) -> Option<bool> {
        self.calls += 1;
        let n = g.len();
        let mut l = h.to_vec();
        for i in 0..n {
            l[i * (n + 1)] += tau;
        }
        if crate::cholesky_in_place(n, &mut l).is_err() {
            return Some(false);
        }
        for (pi, gi) in p.iter_mut().zip(g) {
            *pi = -gi;
        }
        crate::cholesky_solve(n, &l, p);
        Some(true)
    }
}

#[test]
fn a_problem_can_solve_its_own_newton_systems() {
    let n = 10;
    let mut own = OwnSolve {
        inner: Rosenbrock { n },
        calls: 0,
    };
    let mut x = rosenbrock_start(n);
    let r = Newton::new(n, NewtonOptions::default()).minimize(&mut own, &mut x);
    assert!(r.converged(), "{r}");
    assert!(own.calls >= r.iterations && own.calls > 0);
    let mut plain = Rosenbrock { n };
    let mut xp = rosenbrock_start(n);
    let rp = Newton::new(n, NewtonOptions::default()).minimize(&mut plain, &mut xp);
    assert!(rp.converged());
    assert!(max_abs_diff(&x, &xp) < 1e-9, "{x:?} vs {xp:?}");
}

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
impl DenseHessian for QuadQuartic {
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
impl DenseHessian for Rosenbrock {
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
impl DenseHessian for DoubleWell {
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
impl DenseHessian for Huber {
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
        let r = newton.minimize(&mut Dense::new(&mut q), &mut x);
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

#[test]
fn newton_backends_agree() {
    let n = 10;
    let mut a = Newton::new(n, NewtonOptions::default());
    let mut b = Newton::new(n, NewtonOptions::default());
    let mut pa = Dense::with_backend(Rosenbrock { n }, LinearBackend::Dense);
    let mut pb = Dense::with_backend(Rosenbrock { n }, LinearBackend::Faer);
    assert_eq!(pa.matrix.backend(), LinearBackend::Dense);
    assert_eq!(pb.matrix.backend(), LinearBackend::Faer);
    let mut xa = rosenbrock_start(n);
    let mut xb = rosenbrock_start(n);
    let ra = a.minimize(&mut pa, &mut xa);
    let rb = b.minimize(&mut pb, &mut xb);
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
    assert!(a
        .minimize(
            &mut Dense::with_backend(&mut dw, LinearBackend::Dense),
            &mut xa
        )
        .converged());
    assert!(b
        .minimize(
            &mut Dense::with_backend(&mut dw, LinearBackend::Faer),
            &mut xb
        )
        .converged());
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
    let mut dp = Dense::new(&mut p);
    let r = newton.minimize(&mut dp, &mut x);
    assert!(r.converged(), "{r}");
    assert!(r.max_shift > 0.0, "a shift was needed: {r}");
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
    let mut xb = vec![0.0, 1.0];
    let rb = Bfgs::new(n, BfgsOptions::default()).minimize(&mut p, &mut xb);
    assert!(!rb.converged());
    assert!(xb.iter().all(|v| v.is_finite() && v.abs() <= 5.0), "{xb:?}");

    // A start in the undefined region is reported, x untouched.
    let mut x = vec![7.0, 0.0];
    let r = newton.minimize(&mut Dense::new(&mut p), &mut x);
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
    let mut newton = Newton::new(2, NewtonOptions::default().with_max_iter(3));
    let mut x = rosenbrock_start(2);
    let f0 = Rosenbrock { n: 2 }.energy(&x);
    let r = newton.minimize(&mut Dense::new(Rosenbrock { n: 2 }), &mut x);
    assert_eq!(r.reason, Termination::MaxIterations);
    assert_eq!(r.iterations, 3);
    assert!(!r.converged());
    assert!(r.energy < f0);
    assert_eq!(Rosenbrock { n: 2 }.energy(&x), r.energy);
    // max_iter = 0 only evaluates the start.
    let mut newton = Newton::new(2, NewtonOptions::default().with_max_iter(0));
    let r = newton.minimize(&mut Dense::new(Rosenbrock { n: 2 }), &mut x);
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
    let r = Newton::new(0, NewtonOptions::default()).minimize(&mut Dense::new(&mut q), &mut []);
    assert!(r.converged());
    let r = Bfgs::new(0, BfgsOptions::default()).minimize(&mut q, &mut []);
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

// -------------------------------------------------------------------- BFGS

#[test]
fn bfgs_matches_newton() {
    let mut rng = Lcg::new(77);
    for &n in &[2usize, 10] {
        let mut xn = rosenbrock_start(n);
        let mut xb = rosenbrock_start(n);
        assert!(Newton::new(n, NewtonOptions::default())
            .minimize(&mut Dense::new(Rosenbrock { n }), &mut xn)
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
            .minimize(&mut Dense::new(&mut q), &mut xn)
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

impl DenseBorderedProblem for BorderedQQ {
    fn dim(&self) -> usize {
        self.q.n
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
        let n = self.q.n;
        for i in 0..n {
            out.g[i] = self.q.ax(x, i) + self.q.w[i] * x[i].powi(3) - lambda * self.q.b[i];
            out.g_lambda[i] = -self.q.b[i];
            out.c_x[i] = self.e[i];
        }
        h.copy_from_slice(&self.q.a);
        for i in 0..n {
            h[i * (n + 1)] += 3.0 * self.q.w[i] * x[i] * x[i];
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
impl DenseHessian for AtLoad<'_> {
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
        let mut p = DenseBordered::new(BorderedQQ { q, e, t: 0.7 });
        let mut x = vec![0.0; n];
        let mut lambda = 0.0;
        let mut newton = BorderedNewton::new(n, NewtonOptions::default()).unwrap();
        let r = newton.solve(&mut p, &mut x, &mut lambda);
        assert!(r.converged(), "n = {n}: {r}");
        assert_eq!(r.iterations, 1, "linear problem: one step");
        let p = &p.problem;
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
    let mut p = DenseBordered::new(BorderedQQ { q, e, t: 2.5 });
    let mut x = vec![0.0; n];
    let mut lambda = 0.0;
    let mut newton = BorderedNewton::new(n, NewtonOptions::default()).unwrap();
    let r = newton.solve(&mut p, &mut x, &mut lambda);
    assert!(r.converged(), "{r}");
    assert_eq!(r.energy_evals, 0);
    assert!(r.hessian_evals > r.iterations);
    // Feed lambda back into plain minimisation from a cold start.
    let p = &p.problem;
    let mut y = vec![0.0; n];
    let rr = Newton::new(n, NewtonOptions::default())
        .minimize(&mut Dense::new(AtLoad(p, lambda)), &mut y);
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
    impl DenseBorderedProblem for Snap {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
            out.g[0] = x[0].powi(3) - x[0] - lambda;
            h[0] = 3.0 * x[0] * x[0] - 1.0;
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
        let r = BorderedNewton::new(1, NewtonOptions::default())
            .unwrap()
            .solve(&mut DenseBordered::new(Snap { t }), &mut x, &mut lambda);
        assert!(r.converged(), "t = {t}: {r}");
        assert!((x[0] - t).abs() < 1e-12);
        assert!((lambda - (t * t * t - t)).abs() < 1e-12);
    }
}

#[test]
fn bordered_singular_and_nonfinite() {
    // c depends on nothing: the bordered Jacobian is singular (H is not).
    struct Flat;
    impl DenseBorderedProblem for Flat {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], _lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
            out.g[0] = x[0] - 1.0;
            h[0] = 1.0;
            out.g_lambda[0] = 0.0;
            out.c = 1.0;
            out.c_x[0] = 0.0;
            out.c_lambda = 0.0;
            true
        }
    }
    let mut x = [0.0];
    let mut lambda = 0.0;
    let mut newton = BorderedNewton::new(1, NewtonOptions::default()).unwrap();
    let mut flat = DenseBordered::new(Flat);
    let r = newton.solve(&mut flat, &mut x, &mut lambda);
    assert_eq!(r.reason, Termination::Singular);
    // H itself was factorised: the step, not H, was singular.
    assert_eq!(
        newton.last_inertia(),
        Some(Inertia {
            positive: 1,
            negative: 0
        })
    );
    let mut lambda = f64::NAN;
    let r = newton.solve(&mut flat, &mut x, &mut lambda);
    assert_eq!(r.reason, Termination::NonFinite);
    assert_eq!(newton.last_inertia(), None);

    // A singular H (a zero pivot) is Singular even where the bordered
    // Jacobian is not: `E = x^3/3 - lambda x`, target x = 0, where E'' = 0
    // but [[0, -1], [1, 0]] is regular.
    struct Inflection;
    impl DenseBorderedProblem for Inflection {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
            out.g[0] = x[0] * x[0] - lambda;
            h[0] = 2.0 * x[0];
            out.g_lambda[0] = -1.0;
            out.c = x[0];
            out.c_x[0] = 1.0;
            out.c_lambda = 0.0;
            true
        }
    }
    let mut x = [0.0];
    let mut lambda = 0.5;
    let r = newton.solve(&mut DenseBordered::new(Inflection), &mut x, &mut lambda);
    assert_eq!(r.reason, Termination::Singular, "{r}");
    assert_eq!((x[0], lambda), (0.0, 0.5), "the start is kept");
    assert_eq!(newton.last_inertia(), None);
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
impl DenseHessian for CoshChain {
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
    let mut p = Dense::new(CoshChain {
        n,
        t: 0.0,
        kappa: 0.5,
    });

    // Cold start at t = 20 fails within 8 iterations.
    p.problem.t = 20.0;
    let mut x = vec![0.0; n];
    let cold = newton.minimize(&mut p, &mut x);
    assert_eq!(cold.reason, Termination::MaxIterations);

    // Continuation with a deliberately too-large first step.
    let copts = ContinuationOptions::default()
        .with_steps(12.0, 1e-3, 20.0)
        .unwrap();
    let mut x = vec![0.0; n];
    let rep = continuation(0.0, 20.0, &mut x, &copts, |t, x| {
        p.problem.t = t;
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
        p.problem.t = t;
        newton.minimize(&mut p, x)
    });
    assert!(rep.complete, "{rep:?}");
    assert!(max_abs_diff(&x, &[0.0; 4]) < 1e-9);
}

#[test]
fn continuation_stops_incomplete_and_restores_state() {
    let n = 2;
    let mut newton = Newton::new(n, NewtonOptions::default().with_max_iter(8));
    let mut p = Dense::new(CoshChain {
        n,
        t: 0.0,
        kappa: 0.0,
    });
    // Beyond t = 5 the "solver" refuses: the driver must stop at <= 5.
    let copts = ContinuationOptions::default()
        .with_steps(1.0, 0.01, 2.0)
        .unwrap();
    let mut x = vec![0.0; n];
    let mut calls = 0;
    let rep = continuation(0.0, 10.0, &mut x, &copts, |t, x| {
        calls += 1;
        p.problem.t = t;
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
        p.problem.t = t;
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
        p.problem.t = t;
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
            let r = Newton::new(n, opts).minimize(&mut Dense::new(&mut q), &mut x);
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
        let mut dq = Dense::new(q.clone());
        let mut x = x0.clone();
        let r = newton.minimize(&mut dq, &mut x);
        assert!(r.converged());
        let reps = (2_000_000 / (n * n)).max(50);
        let mut best = f64::INFINITY;
        for _ in 0..5 {
            let t = Instant::now();
            for _ in 0..reps {
                x.copy_from_slice(&x0);
                std::hint::black_box(newton.minimize(&mut dq, &mut x));
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

// ------------------------------------------------- problem-owned algebra

/// Records the point of every Hessian evaluation of the problem it wraps
/// (dense or not), so two solves can be compared iterate by iterate.
struct Track<P> {
    p: P,
    iterates: Vec<Vec<f64>>,
}

impl<P> Track<P> {
    fn new(p: P) -> Self {
        Track {
            p,
            iterates: vec![],
        }
    }
}

impl<P: Energy> Energy for Track<P> {
    fn dim(&self) -> usize {
        self.p.dim()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.p.energy(x)
    }
}
impl<P: Gradient> Gradient for Track<P> {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.p.gradient(x, g)
    }
}
impl<P: DenseHessian> DenseHessian for Track<P> {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        self.iterates.push(x.to_vec());
        self.p.hessian(x, g, h)
    }
}
impl<P: Hessian> Hessian for Track<P> {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.iterates.push(x.to_vec());
        self.p.hessian(x, g)
    }
}
impl<P: LinearSystem> LinearSystem for Track<P> {
    fn diagonal_range(&self) -> (f64, f64) {
        self.p.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.p.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.p.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.p.apply(x, out)
    }
}

/// Two tracked solves (Hessian points `a`, `b`, results `xa`, `xb`)
/// visited the same points, to `path_tol` relative to `1 + |x|`, took the
/// same shifts, and reached the same result to `tol`. Once both are
/// within `tol` of their result the decisions are made on round-off
/// (Armijo tests on energy differences of a few ulps, the round-off
/// acceptance): there one may evaluate a point more than the other, so
/// the longer path's extra points need only lie within `tol` of the
/// result.
fn assert_same_path(
    (a, xa, ra): (&[Vec<f64>], &[f64], &Report),
    (b, xb, rb): (&[Vec<f64>], &[f64], &Report),
    path_tol: f64,
    tol: f64,
) {
    assert_eq!(ra.reason, rb.reason, "{ra:?} vs {rb:?}");
    let last = xa;
    let scale = 1.0 + norm_inf_of(last);
    let d = max_abs_diff(xa, xb);
    assert!(d <= tol * scale, "results differ by {d}");
    for (k, (xa, xb)) in a.iter().zip(b).enumerate() {
        let d = max_abs_diff(xa, xb);
        assert!(
            d <= path_tol * scale,
            "iterate {k} differs by {d}: {ra:?} vs {rb:?}"
        );
    }
    let (long, short) = if a.len() >= b.len() { (a, b) } else { (b, a) };
    for (k, x) in long.iter().enumerate().skip(short.len()) {
        let d = max_abs_diff(x, last);
        assert!(d <= tol * scale, "extra iterate {k} is {d} from the result");
    }
    assert!(long.len() - short.len() <= 2, "{ra:?} vs {rb:?}");
    assert!((ra.max_shift - rb.max_shift).abs() <= path_tol * (1.0 + ra.max_shift));
}

/// [`Rosenbrock`] keeping its Hessian as what it is, 2 x 2 diagonal blocks,
/// and factorising them itself (explicit inverses; a block is positive
/// definite when its leading entry and determinant are positive). Counts
/// its factorisations.
struct BlockRosenbrock {
    inner: Rosenbrock,
    /// `(h00, h10, h11)` per block.
    h: Vec<[f64; 3]>,
    /// The inverse of each shifted block, same layout.
    inv: Vec<[f64; 3]>,
    factorizations: usize,
}

impl BlockRosenbrock {
    fn new(n: usize) -> Self {
        BlockRosenbrock {
            inner: Rosenbrock { n },
            h: vec![[0.0; 3]; n / 2],
            inv: vec![[0.0; 3]; n / 2],
            factorizations: 0,
        }
    }
}

impl Energy for BlockRosenbrock {
    fn dim(&self) -> usize {
        self.inner.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.inner.energy(x)
    }
}
impl Gradient for BlockRosenbrock {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.inner.gradient(x, g)
    }
}
impl Hessian for BlockRosenbrock {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        for (k, b) in self.h.iter_mut().enumerate() {
            let (u, v) = (x[2 * k], x[2 * k + 1]);
            *b = [1200.0 * u * u - 400.0 * v + 2.0, -400.0 * u, 200.0];
        }
        self.inner.gradient(x, g)
    }
}
impl LinearSystem for BlockRosenbrock {
    fn diagonal_range(&self) -> (f64, f64) {
        self.h.iter().fold((f64::INFINITY, 0.0f64), |(lo, hi), b| {
            (lo.min(b[0]).min(b[2]), hi.max(b[0].abs()).max(b[2].abs()))
        })
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.factorizations += 1;
        let mut inertia = Inertia::default();
        for (k, (b, inv)) in self.h.iter().zip(&mut self.inv).enumerate() {
            let (a, c, d) = (b[0] + tau, b[1], b[2] + tau);
            if !(a.is_finite() && c.is_finite() && d.is_finite()) {
                return Err(FactorError::NonFinite { block: k });
            }
            let det = a * d - c * c;
            if kind == PivotKind::Cholesky && !(a > 0.0 && det > 0.0) {
                return Err(FactorError::NotPositiveDefinite { index: 2 * k });
            }
            if det == 0.0 {
                return Err(FactorError::Singular { block: k });
            }
            *inv = [d / det, -c / det, a / det];
            match (det > 0.0, a > 0.0) {
                (true, true) => inertia.positive += 2,
                (true, false) => inertia.negative += 2,
                _ => {
                    inertia.positive += 1;
                    inertia.negative += 1;
                }
            }
        }
        Ok(inertia)
    }
    fn solve(&mut self, b: &mut [f64]) {
        for (k, inv) in self.inv.iter().enumerate() {
            let (p, q) = (b[2 * k], b[2 * k + 1]);
            b[2 * k] = inv[0] * p + inv[1] * q;
            b[2 * k + 1] = inv[1] * p + inv[2] * q;
        }
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        for (k, h) in self.h.iter().enumerate() {
            let (p, q) = (x[2 * k], x[2 * k + 1]);
            out[2 * k] = h[0] * p + h[1] * q;
            out[2 * k + 1] = h[1] * p + h[2] * q;
        }
    }
}

/// [`Rosenbrock`] with its Hessian as a [`Semiseparable`] without coupling
/// (2 x 2 blocks, block diagonal).
struct SemiRosenbrock {
    inner: Rosenbrock,
    h: Semiseparable,
}

impl Energy for SemiRosenbrock {
    fn dim(&self) -> usize {
        self.inner.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.inner.energy(x)
    }
}
impl Gradient for SemiRosenbrock {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.inner.gradient(x, g)
    }
}
impl Hessian for SemiRosenbrock {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        for k in 0..self.inner.n / 2 {
            let (u, v) = (x[2 * k], x[2 * k + 1]);
            let off = -400.0 * u;
            self.h.block_mut(k).copy_from_slice(&[
                1200.0 * u * u - 400.0 * v + 2.0,
                off,
                off,
                200.0,
            ]);
        }
        self.h.clear_coupling();
        self.inner.gradient(x, g)
    }
}
impl LinearSystem for SemiRosenbrock {
    fn diagonal_range(&self) -> (f64, f64) {
        self.h.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.h.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.h.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.h.apply(x, out)
    }
}

/// The equivalent of a problem solving its own Newton systems: a problem
/// with its own (block-diagonal) linear algebra takes the same path as the
/// same objective written densely and wrapped in [`Dense`].
#[test]
fn a_problem_can_solve_its_own_newton_systems() {
    let n = 10;
    // the standard start, and one where H is indefinite (h00 < 0)
    let indefinite: Vec<f64> = (0..n).map(|i| if i % 2 == 0 { 0.3 } else { 1.0 }).collect();
    let mut shifted = false;
    for (start, opts) in [
        (rosenbrock_start(n), NewtonOptions::default()),
        (indefinite.clone(), NewtonOptions::default()),
        (
            indefinite,
            NewtonOptions {
                eager_full_steps: false,
                ..NewtonOptions::default()
            },
        ),
    ] {
        let mut own = Track::new(BlockRosenbrock::new(n));
        let mut x = start.clone();
        let r = Newton::new(n, opts).minimize(&mut own, &mut x);
        assert!(r.converged(), "{r}");
        shifted |= r.max_shift > 0.0;
        assert_eq!(own.p.factorizations, r.factorizations);
        let mut dense = Dense::new(Track::new(Rosenbrock { n }));
        let mut xd = start.clone();
        let rd = Newton::new(n, opts).minimize(&mut dense, &mut xd);
        assert!(rd.converged());
        assert_same_path(
            (&own.iterates, &x, &r),
            (&dense.problem.iterates, &xd, &rd),
            1e-12,
            1e-12,
        );
        assert!(max_abs_diff(&x, &xd) <= 1e-12, "{x:?} vs {xd:?}");
        assert!(max_abs_diff(&x, &vec![1.0; n]) < 1e-9);
        // the same blocks through Semiseparable (no coupling)
        let mut semi = Track::new(SemiRosenbrock {
            inner: Rosenbrock { n },
            h: Semiseparable::new(2, n / 2),
        });
        let mut xs = start.clone();
        let rs = Newton::new(n, opts).minimize(&mut semi, &mut xs);
        assert!(rs.converged(), "{rs}");
        assert_same_path(
            (&semi.iterates, &xs, &rs),
            (&dense.problem.iterates, &xd, &rd),
            1e-12,
            1e-12,
        );
    }
    assert!(shifted, "the shifted factorisations ran");
}

// --------------------------------------------------- semiseparable chain

/// A chain of `blocks` elements with `n` unknowns each, elastica-like:
/// every element has its own quadratic + quartic energy, and passes a
/// "rotation" `s_k = sum_{j <= k} a_j . x_j` down the chain, held at each
/// element by a spring `phi_k(s) = p_k s^2/2 + q_k s^4/4`; `lambda` scales
/// the load `b`:
///
/// `E = sum_k [x_k^T A_k x_k / 2 + sum_i c_ki x_ki^4 / 4 + phi_k(s_k)] - lambda b^T x`.
///
/// The Hessian is exactly block diagonal plus rank-one semiseparable: with
/// `T_i = sum_{k >= i} phi_k''(s_k)`, block `(i, j)`, `i > j`, is
/// `T_i a_i a_j^T` (`= -w_i u_j^T` for `u_j = a_j`, `w_i = -T_i a_i`), and
/// block `j` is `A_j + 3 diag(c_j x_j^2) + T_j a_j a_j^T`. As a bordered
/// problem the target is `c = e^T x - t`.
#[derive(Clone)]
struct ChainModel {
    n: usize,
    blocks: usize,
    /// `A_k`, column-major `n x n` each, symmetric.
    a: Vec<f64>,
    c: Vec<f64>,
    arm: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
    b: Vec<f64>,
    e: Vec<f64>,
    t: f64,
    lambda: f64,
    // per block: s_k, then suffix sums of phi'(s) and phi''(s)
    s: Vec<f64>,
    d1: Vec<f64>,
    d2: Vec<f64>,
}

impl ChainModel {
    /// Random data; `shift` moves the spectrum of every `A_k` (negative:
    /// `H` is indefinite near `x = 0`); springs `p_k = kappa`, `q_k = kappa
    /// beta`.
    #[allow(clippy::too_many_arguments)]
    fn random(
        n: usize,
        blocks: usize,
        shift: f64,
        quartic: f64,
        kappa: f64,
        beta: f64,
        rng: &mut Lcg,
    ) -> Self {
        let dim = n * blocks;
        let mut a = vec![0.0; n * n * blocks];
        for k in 0..blocks {
            let m: Vec<f64> = (0..n * n).map(|_| rng.sym()).collect();
            let ak = &mut a[k * n * n..(k + 1) * n * n];
            for j in 0..n {
                for i in 0..n {
                    let v: f64 = (0..n).map(|l| m[i + l * n] * m[j + l * n]).sum();
                    ak[i + j * n] = v / n as f64 + if i == j { shift } else { 0.0 };
                }
            }
        }
        ChainModel {
            n,
            blocks,
            a,
            c: (0..dim).map(|_| quartic * (0.5 + rng.unit())).collect(),
            arm: (0..dim).map(|_| rng.sym()).collect(),
            p: vec![kappa; blocks],
            q: vec![kappa * beta; blocks],
            b: (0..dim).map(|_| 0.5 + rng.unit()).collect(),
            e: (0..dim).map(|_| (0.5 + rng.unit()) / dim as f64).collect(),
            t: 0.0,
            lambda: 1.0,
            s: vec![0.0; blocks],
            d1: vec![0.0; blocks],
            d2: vec![0.0; blocks],
        }
    }

    /// The tip spring made a double well (`p = -mu`, `q = nu`), loaded by
    /// a tip moment (`b = a`, conjugate to `s_N`) and controlled by the tip
    /// rotation (`c = s_N - t`). `H` is indefinite where `phi_N'' = -mu + 3
    /// nu s_N^2` is negative enough, so the load passes limit points along
    /// the path; with `A_k` positive definite, `H` is positive definite on
    /// `s_N = const` and the bordered Jacobian stays regular.
    fn tip_controlled(mut self, mu: f64, nu: f64) -> Self {
        let last = self.blocks - 1;
        self.p[last] = -mu;
        self.q[last] = nu;
        self.b = self.arm.clone();
        self.e = self.arm.clone();
        self
    }

    fn size(&self) -> usize {
        self.n * self.blocks
    }

    /// The chain quantities at `x`; returns `sum_k phi(s_k)`.
    fn sweep(&mut self, x: &[f64]) -> f64 {
        let n = self.n;
        let mut s = 0.0;
        let mut f = 0.0;
        for k in 0..self.blocks {
            s += (0..n)
                .map(|i| self.arm[k * n + i] * x[k * n + i])
                .sum::<f64>();
            self.s[k] = s;
            f += self.p[k] * s * s / 2.0 + self.q[k] * s.powi(4) / 4.0;
        }
        let (mut d1, mut d2) = (0.0, 0.0);
        for k in (0..self.blocks).rev() {
            let (s, p, q) = (self.s[k], self.p[k], self.q[k]);
            d1 += p * s + q * s * s * s;
            d2 += p + 3.0 * q * s * s;
            self.d1[k] = d1;
            self.d2[k] = d2;
        }
        f
    }

    fn block_ax(&self, x: &[f64], k: usize, i: usize) -> f64 {
        let n = self.n;
        (0..n)
            .map(|j| self.a[k * n * n + i + j * n] * x[k * n + j])
            .sum()
    }

    fn value(&mut self, x: &[f64]) -> f64 {
        let mut f = self.sweep(x);
        for k in 0..self.blocks {
            for i in 0..self.n {
                let xi = x[k * self.n + i];
                f += 0.5 * xi * self.block_ax(x, k, i) + 0.25 * self.c[k * self.n + i] * xi.powi(4)
                    - self.lambda * self.b[k * self.n + i] * xi;
            }
        }
        f
    }

    /// Gradient at `x` (after [`ChainModel::sweep`] there).
    fn grad(&self, x: &[f64], g: &mut [f64]) {
        let n = self.n;
        for k in 0..self.blocks {
            for i in 0..n {
                let r = k * n + i;
                g[r] = self.block_ax(x, k, i) + self.c[r] * x[r].powi(3) + self.d1[k] * self.arm[r]
                    - self.lambda * self.b[r];
            }
        }
    }

    /// The Hessian as a [`Semiseparable`] (after a sweep at `x`).
    fn structured(&self, x: &[f64], h: &mut Semiseparable) {
        let n = self.n;
        for k in 0..self.blocks {
            let arm = &self.arm[k * n..(k + 1) * n];
            let blk = h.block_mut(k);
            for j in 0..n {
                for i in 0..n {
                    blk[i + j * n] = self.a[k * n * n + i + j * n] + self.d2[k] * arm[i] * arm[j];
                }
                blk[j * (n + 1)] += 3.0 * self.c[k * n + j] * x[k * n + j].powi(2);
            }
            let (u, w) = h.coupling_mut(k);
            for i in 0..n {
                u[i] = arm[i];
                w[i] = -self.d2[k] * arm[i];
            }
        }
    }

    /// The Hessian assembled densely from the formulas (after a sweep at
    /// `x`), independently of [`Semiseparable`].
    fn dense(&self, x: &[f64], h: &mut [f64]) {
        let n = self.n;
        let dim = self.size();
        for cb in 0..self.blocks {
            for cc in 0..n {
                let col = cb * n + cc;
                for rb in 0..self.blocks {
                    // T of the later of the two blocks
                    let t = self.d2[rb.max(cb)];
                    for rr in 0..n {
                        let row = rb * n + rr;
                        let mut v = t * self.arm[row] * self.arm[col];
                        if rb == cb {
                            v += self.a[cb * n * n + rr + cc * n];
                            if rr == cc {
                                v += 3.0 * self.c[row] * x[row].powi(2);
                            }
                        }
                        h[row + col * dim] = v;
                    }
                }
            }
        }
    }

    fn bordered(&self, x: &[f64], out: &mut BorderedEval) {
        self.grad(x, &mut out.g);
        for i in 0..self.size() {
            out.g_lambda[i] = -self.b[i];
            out.c_x[i] = self.e[i];
        }
        out.c = (0..self.size()).map(|i| self.e[i] * x[i]).sum::<f64>() - self.t;
        out.c_lambda = 0.0;
    }

    /// `negative_eigenvalues` of the dense Hessian at `(x, lambda)`.
    fn negative_eigenvalues_at(&self, x: &[f64]) -> usize {
        let mut m = self.clone();
        m.sweep(x);
        let dim = m.size();
        let mut h = vec![0.0; dim * dim];
        m.dense(x, &mut h);
        negative_eigenvalues(dim, &h).unwrap()
    }
}

impl Energy for ChainModel {
    fn dim(&self) -> usize {
        self.size()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.value(x)
    }
}
impl Gradient for ChainModel {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let f = self.value(x);
        self.grad(x, g);
        f
    }
}
impl DenseHessian for ChainModel {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let f = self.gradient(x, g);
        self.dense(x, h);
        f
    }
}
impl DenseBorderedProblem for ChainModel {
    fn dim(&self) -> usize {
        self.size()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
        self.lambda = lambda;
        self.sweep(x);
        self.bordered(x, out);
        self.dense(x, h);
        true
    }
}

/// [`ChainModel`] with its Hessian kept as a [`Semiseparable`]: `O(N)`
/// storage and work, no dense matrix anywhere.
struct SemiChain {
    m: ChainModel,
    h: Semiseparable,
}

impl SemiChain {
    fn new(m: ChainModel) -> Self {
        let h = Semiseparable::new(m.n, m.blocks);
        SemiChain { m, h }
    }
}

impl Energy for SemiChain {
    fn dim(&self) -> usize {
        self.m.size()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.m.value(x)
    }
}
impl Gradient for SemiChain {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.m.gradient(x, g)
    }
}
impl Hessian for SemiChain {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let f = self.m.gradient(x, g);
        self.m.structured(x, &mut self.h);
        f
    }
}
impl LinearSystem for SemiChain {
    fn diagonal_range(&self) -> (f64, f64) {
        self.h.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.h.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.h.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.h.apply(x, out)
    }
}
impl Bordered for SemiChain {
    fn dim(&self) -> usize {
        self.m.size()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval) -> bool {
        self.m.lambda = lambda;
        self.m.sweep(x);
        self.m.bordered(x, out);
        self.m.structured(x, &mut self.h);
        true
    }
}

/// A bordered problem that remembers where the solver last factorised `H`
/// (the point of the evaluation before the factorisation).
struct Recording<P> {
    p: P,
    last_eval: (Vec<f64>, f64),
    factored_at: Option<(Vec<f64>, f64)>,
}

impl<P> Recording<P> {
    fn new(p: P) -> Self {
        Recording {
            p,
            last_eval: (vec![], f64::NAN),
            factored_at: None,
        }
    }
}

impl<P: Bordered> Bordered for Recording<P> {
    fn dim(&self) -> usize {
        self.p.dim()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval) -> bool {
        self.last_eval = (x.to_vec(), lambda);
        self.p.eval(x, lambda, out)
    }
}
impl<P: LinearSystem> LinearSystem for Recording<P> {
    fn diagonal_range(&self) -> (f64, f64) {
        self.p.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.factored_at = Some(self.last_eval.clone());
        self.p.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.p.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.p.apply(x, out)
    }
}

fn norm_inf_of(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// The structured Hessian is the dense one: same entries, same products.
#[test]
fn semiseparable_chain_hessian_is_exact() {
    let mut rng = Lcg::new(3);
    let mut m = ChainModel::random(3, 7, -0.3, 1.0, 0.4, 0.5, &mut rng);
    let dim = m.size();
    let x: Vec<f64> = (0..dim).map(|_| rng.sym()).collect();
    m.sweep(&x);
    let mut hs = Semiseparable::new(3, 7);
    m.structured(&x, &mut hs);
    let (mut hd, mut hr) = (vec![0.0; dim * dim], vec![0.0; dim * dim]);
    m.dense(&x, &mut hd);
    hs.dense(&mut hr);
    assert!(max_abs_diff(&hd, &hr) <= 1e-14 * norm_inf_of(&hd));
    // the dense Hessian is the derivative of the gradient (central
    // differences, exact for the quadratic part)
    let (mut gp, mut gm) = (vec![0.0; dim], vec![0.0; dim]);
    let step = 1e-5;
    for j in 0..dim {
        let mut xp = x.clone();
        xp[j] += step;
        m.gradient(&xp, &mut gp);
        xp[j] -= 2.0 * step;
        m.gradient(&xp, &mut gm);
        for i in 0..dim {
            let fd = (gp[i] - gm[i]) / (2.0 * step);
            assert!(
                (fd - hd[i + j * dim]).abs() <= 1e-7 * (1.0 + fd.abs()),
                "H[{i},{j}] = {} vs {fd}",
                hd[i + j * dim]
            );
        }
    }
    // and the gradient the derivative of the energy
    let mut g = vec![0.0; dim];
    m.gradient(&x, &mut g);
    for j in 0..dim {
        let mut xp = x.clone();
        xp[j] += step;
        let fp = m.energy(&xp);
        xp[j] -= 2.0 * step;
        let fm = m.energy(&xp);
        let fd = (fp - fm) / (2.0 * step);
        assert!((fd - g[j]).abs() <= 1e-7 * (1.0 + fd.abs()), "g[{j}]");
    }
}

/// A semiseparable-backed problem follows the dense path iterate by
/// iterate, from an indefinite start (shifted factorisations).
#[test]
fn semiseparable_newton_iterates_match_dense() {
    let mut rng = Lcg::new(8);
    for (n, blocks) in [(1, 12), (2, 7), (3, 6), (4, 10), (5, 4), (6, 3), (7, 2)] {
        let m = ChainModel::random(n, blocks, -0.5, 1.0, 0.05, 0.5, &mut rng);
        let dim = m.size();
        let start: Vec<f64> = (0..dim).map(|i| 0.05 * (i as f64 * 0.9).sin()).collect();
        assert!(m.negative_eigenvalues_at(&start) > 0, "indefinite start");
        let mut semi = Track::new(SemiChain::new(m.clone()));
        let mut x = start.clone();
        let r = Newton::new(dim, NewtonOptions::default()).minimize(&mut semi, &mut x);
        assert!(r.converged(), "{n} x {blocks}: {r}");
        assert!(r.max_shift > 0.0, "{r}");
        let mut dense = Dense::new(Track::new(m.clone()));
        let mut xd = start.clone();
        let rd = Newton::new(dim, NewtonOptions::default()).minimize(&mut dense, &mut xd);
        // far from the minimum (indefinite H, shifts, backtracking) Newton
        // is not contractive: rounding differences of the two algebras
        // grow by up to ~1e5 before the quadratic phase removes them
        assert_same_path(
            (&semi.iterates, &x, &r),
            (&dense.problem.iterates, &xd, &rd),
            1e-9,
            1e-12,
        );
        assert!(max_abs_diff(&x, &xd) <= 1e-12 * (1.0 + norm_inf_of(&x)));
        // a minimum: the structured factorisation's inertia says so
        assert_eq!(
            semi.p.h.factor(0.0, PivotKind::Symmetric).unwrap().negative,
            0
        );
        assert_eq!(m.negative_eigenvalues_at(&x), 0);
    }
}

/// The bordered solve of a semiseparable-backed chain agrees with the
/// same chain through [`DenseBordered`] along a path in the controlled
/// tip rotation that starts where `H` is indefinite (the load falls) and
/// passes a limit point in load to where `H` is definite (the load rises).
/// After every solve, `last_inertia` is that of the dense `H` where the
/// solver last factorised it.
#[test]
fn bordered_semiseparable_chain_matches_dense_past_a_limit_point() {
    let mut rng = Lcg::new(12);
    for (n, blocks) in [(3, 8), (2, 10), (4, 4), (1, 16), (5, 3), (6, 3)] {
        let m =
            ChainModel::random(n, blocks, 0.3, 0.5, 0.5, 0.2, &mut rng).tip_controlled(2.0, 1.0);
        let dim = m.size();
        let mut semi = Recording::new(SemiChain::new(m.clone()));
        let mut dense = Recording::new(DenseBordered::new(m.clone()));
        let opts = NewtonOptions::default();
        let mut bs = BorderedNewton::new(dim, opts).unwrap();
        let mut bd = BorderedNewton::new(dim, opts).unwrap();
        let (mut xs, mut ls) = (vec![0.0; dim], 0.0);
        let (mut xd, mut ld) = (vec![0.0; dim], 0.0);
        let mut loads = vec![];
        let mut unstable = vec![];
        for step in 1..=20 {
            let t = 0.1 * step as f64;
            semi.p.m.t = t;
            dense.p.problem.t = t;
            let rs = bs.solve(&mut semi, &mut xs, &mut ls);
            let rd = bd.solve(&mut dense, &mut xd, &mut ld);
            assert!(rs.converged(), "{n} x {blocks}, t = {t}: {rs}");
            assert!(rd.converged(), "{n} x {blocks}, t = {t}: {rd}");
            let scale = 1.0 + norm_inf_of(&xs);
            let dx = max_abs_diff(&xs, &xd);
            assert!(
                dx <= 1e-10 * scale,
                "{n} x {blocks}, t = {t}: x differs by {dx}"
            );
            assert!(
                (ls - ld).abs() <= 1e-10 * (1.0 + ls.abs()),
                "{n} x {blocks}, t = {t}: lambda {ls} vs {ld}"
            );
            // the target holds
            let c: f64 = (0..dim).map(|i| m.e[i] * xs[i]).sum::<f64>() - t;
            assert!(c.abs() <= 1e-10);
            // the inertia of the last factorisation, both ways
            for (bn, at, what) in [
                (&bs, &semi.factored_at, "structured"),
                (&bd, &dense.factored_at, "dense"),
            ] {
                let inertia = bn.last_inertia().expect("a factorisation");
                let (xf, lf) = at.clone().unwrap();
                let mut mf = m.clone();
                mf.lambda = lf;
                let neg = mf.negative_eigenvalues_at(&xf);
                assert_eq!(
                    (inertia.negative, inertia.positive),
                    (neg, dim - neg),
                    "{n} x {blocks}, t = {t}, {what}"
                );
            }
            loads.push(ls);
            unstable.push(m.negative_eigenvalues_at(&xs));
        }
        // H indefinite at the first solutions, definite at the last ones
        assert_eq!(unstable[0], 1, "{unstable:?}");
        assert_eq!(*unstable.last().unwrap(), 0, "{unstable:?}");
        // the load falls, then rises: a limit point was passed
        assert!(loads[1] < loads[0] && loads[19] > loads[18], "{loads:?}");
        let (kmin, _) = loads
            .iter()
            .enumerate()
            .min_by(|a, b| a.1.total_cmp(b.1))
            .unwrap();
        assert!(kmin > 0 && kmin < 19, "{loads:?}");
    }
}

/// `last_inertia` from cold starts, where the solve takes several steps:
/// the inertia of `H` at the last factorised point (not the returned one),
/// for the structured and the dense algebra alike.
#[test]
fn bordered_last_inertia_matches_dense_eigenvalues() {
    let mut rng = Lcg::new(31);
    let m = ChainModel::random(3, 6, 0.3, 0.5, 0.5, 0.2, &mut rng).tip_controlled(2.0, 1.0);
    let dim = m.size();
    let opts = NewtonOptions::default();
    let mut seen = vec![];
    for &t in &[0.1, 0.4, 1.6] {
        for structured in [true, false] {
            let mut model = m.clone();
            model.t = t;
            let mut x = vec![0.0; dim];
            let mut lambda = 0.0;
            let mut bn = BorderedNewton::new(dim, opts).unwrap();
            let (r, at) = if structured {
                let mut p = Recording::new(SemiChain::new(model));
                (bn.solve(&mut p, &mut x, &mut lambda), p.factored_at)
            } else {
                let mut p = Recording::new(DenseBordered::new(model));
                (bn.solve(&mut p, &mut x, &mut lambda), p.factored_at)
            };
            assert!(r.converged(), "t = {t}: {r}");
            assert!(r.iterations > 1, "{r}");
            let inertia = bn.last_inertia().expect("a factorisation");
            let (xf, lf) = at.unwrap();
            assert!(
                max_abs_diff(&xf, &x) > 0.0,
                "factorised before the last step"
            );
            let mut mf = m.clone();
            mf.lambda = lf;
            let neg = mf.negative_eigenvalues_at(&xf);
            assert_eq!(inertia.negative, neg, "t = {t}, structured {structured}");
            assert_eq!(inertia.positive, dim - neg);
            seen.push(neg);
        }
    }
    assert!(seen.iter().any(|&k| k > 0) && seen.contains(&0), "{seen:?}");
}

/// `Newton::minimize` on a release-size chain (4 x 500 unknowns) converges
/// through the semiseparable algebra, and agrees with the dense path (a
/// 2000 x 2000 Cholesky per iteration, about a second each in a debug
/// build: that comparison starts near the minimum, where Newton takes
/// three steps).
#[test]
fn newton_semiseparable_release_size_matches_dense() {
    let mut rng = Lcg::new(500);
    let mut m = ChainModel::random(4, 500, 0.5, 0.1, 0.002, 0.1, &mut rng);
    m.lambda = 0.3;
    let dim = m.size();
    let mut semi = SemiChain::new(m.clone());
    let mut x = vec![0.0; dim];
    let mut newton = Newton::new(dim, NewtonOptions::default());
    let r = newton.minimize(&mut semi, &mut x);
    assert!(r.converged(), "{r}");
    assert!(r.iterations >= 4, "a nonlinear problem: {r}");
    let mut g = vec![0.0; dim];
    semi.gradient(&x, &mut g);
    assert!(norm_inf_of(&g) <= 1e-10);
    assert_eq!(
        semi.h.factor(0.0, PivotKind::Symmetric).unwrap().negative,
        0
    );
    // both algebras from the same start near the minimum
    let start: Vec<f64> = (0..dim)
        .map(|i| x[i] + 0.005 * (0.37 * i as f64).sin())
        .collect();
    let mut xs = start.clone();
    let rs = newton.minimize(&mut semi, &mut xs);
    let mut dense = Dense::new(m);
    assert_eq!(dense.matrix.backend(), LinearBackend::Faer);
    let mut xd = start;
    let rd = newton.minimize(&mut dense, &mut xd);
    assert!(rs.converged() && rd.converged(), "{rs}\n{rd}");
    assert_eq!(
        (rs.iterations, rs.factorizations),
        (rd.iterations, rd.factorizations)
    );
    assert!(rd.factorizations <= 3, "{rd}");
    let scale = 1.0 + norm_inf_of(&x);
    for (y, what) in [(&xs, "structured"), (&xd, "dense")] {
        let d = max_abs_diff(&x, y);
        assert!(d <= 1e-10 * scale, "{what} differs by {d}");
    }
}

#[test]
fn dense_errors_name_the_pivot() {
    let mut a = vec![1.0, 0.0, 0.0, -1.0];
    let e = cholesky_in_place(2, &mut a).unwrap_err();
    assert_eq!(e, DenseError::NonPositivePivot { index: 1 });
    assert_eq!(e.index(), 1);
    let mut s = vec![1.0, 2.0, 2.0, 4.0];
    let e = lu_in_place(2, &mut s, &mut [0; 2]).unwrap_err();
    assert_eq!((e, e.index()), (DenseError::ZeroPivot { index: 1 }, 1));
    // negative_eigenvalues of Q diag(lam) Q^T against a known count
    let mut rng = Lcg::new(2);
    let n = 9;
    let m: Vec<f64> = (0..n * n).map(|_| rng.sym()).collect();
    // a symmetric matrix and its spectrum, by nalgebra
    let mut h = vec![0.0; n * n];
    for j in 0..n {
        for i in 0..n {
            h[i + j * n] = m[i + j * n] + m[j + i * n];
        }
    }
    let eig = nalgebra::DMatrix::from_column_slice(n, n, &h).symmetric_eigenvalues();
    let want = eig.iter().filter(|&&l| l < 0.0).count();
    assert!(want > 0 && want < n);
    assert_eq!(negative_eigenvalues(n, &h), Some(want));
    assert_eq!(negative_eigenvalues(0, &[]), Some(0));
    assert_eq!(negative_eigenvalues(1, &[f64::NAN]), None);
}

/// As [`newton_nonfinite_hessian_is_reported`], for a problem whose
/// Hessian is a [`Semiseparable`]: a non-finite entry (in a block, or in a
/// coupling vector) is `FactorError::NonFinite` (the contract of
/// [`LinearSystem::factor`]) and the solve ends `NonFinite` at the first
/// factorisation, instead of escalating the shift.
#[test]
fn newton_nonfinite_structured_hessian_is_reported() {
    struct BadSemi {
        p: SemiChain,
        coupling: bool,
    }
    impl Energy for BadSemi {
        fn dim(&self) -> usize {
            self.p.m.size()
        }
        fn energy(&mut self, x: &[f64]) -> f64 {
            self.p.energy(x)
        }
    }
    impl Gradient for BadSemi {
        fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
            self.p.gradient(x, g)
        }
    }
    impl Hessian for BadSemi {
        fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
            let f = self.p.hessian(x, g);
            if self.coupling {
                self.p.h.coupling_mut(0).1[0] = f64::NAN;
            } else {
                self.p.h.block_mut(2)[4] = f64::INFINITY;
            }
            f
        }
    }
    impl LinearSystem for BadSemi {
        fn diagonal_range(&self) -> (f64, f64) {
            self.p.diagonal_range()
        }
        fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
            self.p.factor(tau, kind)
        }
        fn solve(&mut self, b: &mut [f64]) {
            self.p.solve(b)
        }
        fn apply(&self, x: &[f64], out: &mut [f64]) {
            self.p.apply(x, out)
        }
    }
    let mut rng = Lcg::new(3);
    let m = ChainModel::random(3, 4, 0.5, 0.5, 0.1, 0.1, &mut rng);
    for coupling in [false, true] {
        let mut bad = BadSemi {
            p: SemiChain::new(m.clone()),
            coupling,
        };
        let mut x = vec![0.1; 12];
        let r = Newton::new(12, NewtonOptions::default()).minimize(&mut bad, &mut x);
        assert_eq!(r.reason, Termination::NonFinite, "coupling {coupling}: {r}");
        assert_eq!(r.factorizations, 1, "{r}");
        assert!(x.iter().all(|v| v.is_finite()));
        for kind in [PivotKind::Cholesky, PivotKind::Symmetric] {
            assert!(
                matches!(bad.factor(0.0, kind), Err(FactorError::NonFinite { .. })),
                "coupling {coupling}, {kind:?}: {:?}",
                bad.factor(0.0, kind)
            );
        }
    }
}

#[test]
fn zz_probe_path() {
    let mut rng = Lcg::new(8);
    for (n, blocks) in [(1, 12), (2, 7), (3, 6), (4, 10), (5, 4), (6, 3), (7, 2)] {
        let m = ChainModel::random(n, blocks, -0.5, 1.0, 0.05, 0.5, &mut rng);
        let dim = m.size();
        let start: Vec<f64> = (0..dim).map(|i| 0.05 * (i as f64 * 0.9).sin()).collect();
        let mut semi = Track::new(SemiChain::new(m.clone()));
        let mut x = start.clone();
        let r = Newton::new(dim, NewtonOptions::default()).minimize(&mut semi, &mut x);
        let mut dense = Dense::new(Track::new(m.clone()));
        let mut xd = start.clone();
        let rd = Newton::new(dim, NewtonOptions::default()).minimize(&mut dense, &mut xd);
        let d: Vec<String> = semi
            .iterates
            .iter()
            .zip(&dense.problem.iterates)
            .map(|(a, b)| format!("{:.0e}", max_abs_diff(a, b)))
            .collect();
        println!(
            "{n}x{blocks}: {} {} {:?}",
            r.factorizations, rd.factorizations, d
        );
        // per-iterate: condition of the Hessian
        let mut conds = vec![];
        for xi in &semi.iterates {
            let mut mm = m.clone();
            mm.sweep(xi);
            let mut h = vec![0.0; dim * dim];
            mm.dense(xi, &mut h);
            let e = nalgebra::DMatrix::from_column_slice(dim, dim, &h).symmetric_eigenvalues();
            let (lo, hi) = e.iter().fold((f64::INFINITY, 0.0f64), |(a, b), &v| {
                (a.min(v.abs()), b.max(v.abs()))
            });
            conds.push(format!("{:.0e}", hi / lo));
        }
        println!("   cond {:?}", conds);
    }
}

/// A non-finite Hessian (with a finite residual) ends a bordered solve as
/// `NonFinite`, not `Singular`, and leaves the start unchanged.
#[test]
fn bordered_nonfinite_hessian_is_reported() {
    struct InfH;
    impl DenseBorderedProblem for InfH {
        fn dim(&self) -> usize {
            1
        }
        fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
            out.g[0] = x[0] - lambda;
            h[0] = f64::INFINITY;
            out.g_lambda[0] = -1.0;
            out.c = x[0] - 1.0;
            out.c_x[0] = 1.0;
            out.c_lambda = 0.0;
            true
        }
    }
    let mut p = DenseBordered::new(InfH);
    let mut solver = BorderedNewton::new(1, NewtonOptions::default()).unwrap();
    let (mut x, mut lambda) = ([0.0], 0.0);
    let rep = solver.solve(&mut p, &mut x, &mut lambda);
    assert_eq!(rep.reason, Termination::NonFinite, "{rep:?}");
    assert_eq!((x[0], lambda), (0.0, 0.0));
    assert!(solver.last_inertia().is_none());
}

//! Solver tests. Every check compares against an independent method
//! (closed forms, faer's LU, argmin's L-BFGS vs Newton, Newton vs the
//! bordered solve); randomness is seeded.

#![allow(clippy::needless_range_loop)]

use crate::testutil::Lcg;
use crate::*;

mod algebra;
mod bordered;
mod chain;
mod continuation;
mod dense;
mod newton;
mod prop;
mod semiseparable;

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

fn norm_inf_of(v: &[f64]) -> f64 {
    v.iter().fold(0.0f64, |m, x| m.max(x.abs()))
}

/// `A x = b` by faer's LU with partial pivoting (an elimination
/// independent of the factorisations under test).
fn lu_solve(n: usize, a: &[f64], b: &[f64]) -> Vec<f64> {
    use faer::linalg::solvers::Solve as _;
    let a = faer::MatRef::from_column_major_slice(a, n, n);
    let b = faer::MatRef::from_column_major_slice(b, n, 1);
    let x = a.partial_piv_lu().solve(b);
    (0..n).map(|i| x[(i, 0)]).collect()
}

/// An independent, gradient-only minimiser of `p` from `x0`: argmin's
/// L-BFGS with the More-Thuente line search, until the gradient's 2-norm
/// is below `gtol` (which bounds its largest entry too).
fn lbfgs<P: Gradient>(p: P, x0: &[f64], gtol: f64) -> Vec<f64> {
    use argmin::core::{CostFunction, Error, Executor};
    use argmin::solver::{linesearch::MoreThuenteLineSearch, quasinewton::LBFGS};
    use std::cell::RefCell;

    struct Objective<'a, P>(&'a RefCell<P>);
    impl<P: Gradient> CostFunction for Objective<'_, P> {
        type Param = Vec<f64>;
        type Output = f64;
        fn cost(&self, x: &Vec<f64>) -> Result<f64, Error> {
            // a step of NaNs (L-BFGS's update at a standstill) ends the run
            if !x.iter().all(|v| v.is_finite()) {
                return Err(argmin::core::ArgminError::InvalidParameter {
                    text: "a non-finite point".into(),
                }
                .into());
            }
            Ok(self.0.borrow_mut().energy(x))
        }
    }
    impl<P: Gradient> argmin::core::Gradient for Objective<'_, P> {
        type Param = Vec<f64>;
        type Gradient = Vec<f64>;
        fn gradient(&self, x: &Vec<f64>) -> Result<Vec<f64>, Error> {
            let mut g = vec![0.0; x.len()];
            self.0.borrow_mut().gradient(x, &mut g);
            Ok(g)
        }
    }
    // a bounded step: extrapolation never overflows the objective
    let search = MoreThuenteLineSearch::new()
        .with_bounds(f64::EPSILON.sqrt(), 1e3)
        .expect("valid bounds");
    let solver = LBFGS::new(search, 10)
        .with_tolerance_grad(gtol)
        .and_then(|s| s.with_tolerance_cost(0.0))
        .expect("valid tolerances");
    let p = RefCell::new(p);
    let result = Executor::new(Objective(&p), solver)
        .configure(|s| s.param(x0.to_vec()).max_iters(10_000))
        .run()
        .expect("L-BFGS runs");
    let mut g = vec![0.0; x0.len()];
    // the last point (whose gradient met the test), else the best one
    let state = result.state;
    let x = state.param.or(state.best_param).expect("a point");
    p.into_inner().gradient(&x, &mut g);
    let g2 = g.iter().map(|v| v * v).sum::<f64>().sqrt();
    assert!(g2 < gtol, "L-BFGS stopped at |g| = {g2:e}");
    x
}

// ------------------------------------------------------- path comparison

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

//! Pseudo-arclength continuation ([`Palc`]) and the restricted inertia:
//!
//! * the 1-D snap-through `g = x^3 - x - lambda`, followed through both
//!   folds (located to 1e-10) and its unstable middle part;
//! * the same snap-through rotated into `n` dimensions with stiff (and one
//!   unstable) decoupled directions: folds to 1e-9, inertia at every point
//!   against dense eigenvalue counts;
//! * a chain whose Hessian is a [`Semiseparable`], past a fold, against the
//!   same chain through [`DensePath`];
//! * step control: landing on the target, a stop predicate, non-finite
//!   evaluations, the step limit, a failed start;
//! * [`restricted_inertia`] against eigenvalues of `Z^T H Z`, and
//!   [`BorderedNewton::last_restricted_inertia`];
//! * accepted steps (events included) do not allocate.

use fpc_newton::{
    factor_restricted_inertia, negative_eigenvalues, restricted_inertia, Bordered, BorderedEval,
    BorderedNewton, BorderedPath, Control, DenseBordered, DenseBorderedProblem, DenseMatrix,
    DensePath, DensePathProblem, Direction, EventKind, FactorError, Inertia, LinearBackend,
    LinearSystem, NewtonOptions, Palc, PalcOptions, Path, PathEvent, PathObserver, PathPoint,
    PathTermination, PivotKind, RestrictedInertiaError, Semiseparable,
};
use std::alloc::{GlobalAlloc, Layout, System};
use std::cell::Cell;

// ------------------------------------------------------ counting allocator

struct Counting;

thread_local! {
    static ALLOCS: Cell<usize> = const { Cell::new(0) };
}

fn count() {
    let _ = ALLOCS.try_with(|c| c.set(c.get() + 1));
}

unsafe impl GlobalAlloc for Counting {
    unsafe fn alloc(&self, layout: Layout) -> *mut u8 {
        count();
        System.alloc(layout)
    }
    unsafe fn alloc_zeroed(&self, layout: Layout) -> *mut u8 {
        count();
        System.alloc_zeroed(layout)
    }
    unsafe fn dealloc(&self, ptr: *mut u8, layout: Layout) {
        System.dealloc(ptr, layout)
    }
    unsafe fn realloc(&self, ptr: *mut u8, layout: Layout, new_size: usize) -> *mut u8 {
        count();
        System.realloc(ptr, layout, new_size)
    }
}

#[global_allocator]
static GLOBAL: Counting = Counting;

/// Allocations made by this thread in `f`.
fn allocations_in(f: impl FnOnce()) -> usize {
    let before = ALLOCS.with(|c| c.get());
    f();
    ALLOCS.with(|c| c.get()) - before
}

// ------------------------------------------------------------- helpers

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Random orthogonal `n x n` matrix (column-major), by modified
/// Gram-Schmidt on a random matrix.
fn random_orthogonal(n: usize, rng: &mut fastrand::Rng) -> Vec<f64> {
    let mut q: Vec<f64> = (0..n * n).map(|_| 2.0 * rng.f64() - 1.0).collect();
    for j in 0..n {
        for k in 0..j {
            let d: f64 = (0..n).map(|i| q[i + n * j] * q[i + n * k]).sum();
            for i in 0..n {
                q[i + n * j] -= d * q[i + n * k];
            }
        }
        let norm = (0..n).map(|i| q[i + n * j].powi(2)).sum::<f64>().sqrt();
        for i in 0..n {
            q[i + n * j] /= norm;
        }
    }
    q
}

/// Orthonormal basis (column-major `n x (n-1)`) of `{v : c . v = 0}`: the
/// last `n - 1` columns of the Householder reflector mapping `c` to a
/// multiple of `e_1`.
fn null_basis(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    let norm = dot(c, c).sqrt();
    let mut v = c.to_vec();
    v[0] += norm.copysign(c[0]);
    let vv = dot(&v, &v);
    let mut z = vec![0.0; n * (n - 1)];
    for j in 1..n {
        for i in 0..n {
            let e = if i == j { 1.0 } else { 0.0 };
            z[i + n * (j - 1)] = e - 2.0 * v[i] * v[j] / vv;
        }
    }
    z
}

/// `Z^T A Z` for the column-major `n x n` `a` and `n x (n-1)` `z`.
fn reduce(n: usize, a: &[f64], z: &[f64]) -> Vec<f64> {
    let m = n - 1;
    let mut az = vec![0.0; n * m];
    for q in 0..m {
        for i in 0..n {
            az[i + n * q] = (0..n).map(|j| a[i + n * j] * z[j + n * q]).sum();
        }
    }
    let mut red = vec![0.0; m * m];
    for q in 0..m {
        for p in 0..m {
            red[p + m * q] = (0..n).map(|i| z[i + n * p] * az[i + n * q]).sum();
        }
    }
    red
}

/// An observer that counts points and checks nothing (allocation tests).
struct Tally {
    points: usize,
    events: usize,
    folds: usize,
}

impl PathObserver for Tally {
    fn point(&mut self, _: &PathPoint<'_>) -> Control {
        self.points += 1;
        Control::Continue
    }
    fn event(&mut self, e: &PathEvent<'_>) {
        self.events += 1;
        if e.kind == EventKind::Fold && e.located {
            self.folds += 1;
        }
    }
}

// ------------------------------------------------------ 1-D snap-through

/// `E = x^4/4 - x^2/2 - lambda x`: `g = x^3 - x - lambda`, `H = 3 x^2 - 1`.
/// Optionally not evaluable beyond `x_max`.
struct Snap {
    x_max: f64,
    refuse: bool,
}

impl Snap {
    fn new() -> Snap {
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

fn lambda_fold() -> f64 {
    2.0 / (3.0 * 3f64.sqrt())
}

fn x_fold() -> f64 {
    1.0 / 3f64.sqrt()
}

/// The equilibrium at `lambda = -1`: the real root of `x^3 - x + 1`.
const X_START: f64 = -1.324_717_957_244_746;

#[test]
fn snap_through_passes_both_folds_and_the_unstable_middle() {
    for theta in [1.0, 0.3, 3.0] {
        let opts = PalcOptions::default().with_theta(theta).unwrap();
        let mut palc = Palc::new(1, opts).unwrap();
        let mut p = DensePath::new(Snap::new());
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
    let mut p = DensePath::new(Snap::new());
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
        let opts = PalcOptions::default()
            .with_steps(initial, 1e-8, max)
            .unwrap();
        let mut palc = Palc::new(1, opts).unwrap();
        let mut p = DensePath::new(Snap::new());
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
    let mut p = DensePath::new(Snap::new());
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
    let mut palc = Palc::new(1, PalcOptions::default().with_max_steps(3)).unwrap();
    let mut p = DensePath::new(Snap::new());
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
        let mut p = DensePath::new(Snap { x_max: 0.9, refuse });
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
    let mut p = DensePath::new(Snap::new());
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
struct Pitchfork;

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
    let mut p = DensePath::new(Pitchfork);
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
    let mut palc = Palc::new(2, PalcOptions::default().with_events(false)).unwrap();
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

// ------------------------------------------- rotated snap-through in n-D

/// The snap-through in `y_0` rotated into `x = Q y`, plus decoupled
/// directions `y_i` with energy `k_i y_i^2/2 + q_i y_i^4/4 - lambda b_i y_i`
/// (stiff, or one with `k < 0, q = 0`: unstable everywhere). The folds
/// are those of `y_0` (`b_0 = 1`), the other `y_i(lambda)` solve their
/// scalar equations.
struct Rotated {
    n: usize,
    q: Vec<f64>,
    k: Vec<f64>,
    quartic: Vec<f64>,
    b: Vec<f64>,
    y: Vec<f64>,
    dy: Vec<f64>,
}

impl Rotated {
    fn new(n: usize, seed: u64) -> Rotated {
        let mut rng = fastrand::Rng::with_seed(seed);
        let mut k: Vec<f64> = (0..n).map(|_| 10f64.powf(1.0 + 3.0 * rng.f64())).collect();
        let mut quartic: Vec<f64> = (0..n).map(|_| rng.f64()).collect();
        let b: Vec<f64> = (0..n)
            .map(|i| {
                if i == 0 {
                    1.0
                } else {
                    5.0 * (2.0 * rng.f64() - 1.0)
                }
            })
            .collect();
        k[0] = -1.0;
        quartic[0] = 1.0;
        // one unstable direction
        k[n - 1] = -3.0;
        quartic[n - 1] = 0.0;
        Rotated {
            n,
            q: random_orthogonal(n, &mut rng),
            k,
            quartic,
            b,
            y: vec![0.0; n],
            dy: vec![0.0; n],
        }
    }

    /// `y = Q^T x`.
    fn set_y(&mut self, x: &[f64]) {
        let n = self.n;
        for j in 0..n {
            self.y[j] = (0..n).map(|i| self.q[i + n * j] * x[i]).sum();
        }
    }

    /// `out = Q v`.
    fn rotate(&self, v: &[f64], out: &mut [f64]) {
        let n = self.n;
        for (i, o) in out.iter_mut().enumerate() {
            *o = (0..n).map(|j| self.q[i + n * j] * v[j]).sum();
        }
    }

    fn curvature(&self, i: usize) -> f64 {
        self.k[i] + 3.0 * self.quartic[i] * self.y[i] * self.y[i]
    }

    /// The dense `H = Q diag(h) Q^T` at the last `set_y`.
    fn hessian(&self, h: &mut [f64]) {
        let n = self.n;
        for c in 0..n {
            for r in 0..n {
                h[r + n * c] = (0..n)
                    .map(|j| self.q[r + n * j] * self.curvature(j) * self.q[c + n * j])
                    .sum();
            }
        }
    }

    /// The exact fold with `y_0 = y0` (`lambda = y0^3 - y0`).
    fn fold(&self, y0: f64) -> (f64, Vec<f64>) {
        let lambda = y0 * y0 * y0 - y0;
        let y: Vec<f64> = (0..self.n)
            .map(|i| {
                if i == 0 {
                    return y0;
                }
                // k y + q y^3 = b lambda, unique (k > 0, q >= 0, or q = 0)
                let (k, q, r) = (self.k[i], self.quartic[i], self.b[i] * lambda);
                let mut v = r / k;
                for _ in 0..100 {
                    v -= (k * v + q * v * v * v - r) / (k + 3.0 * q * v * v);
                }
                v
            })
            .collect();
        let mut x = vec![0.0; self.n];
        self.rotate(&y, &mut x);
        (lambda, x)
    }
}

impl DensePathProblem for Rotated {
    fn dim(&self) -> usize {
        self.n
    }
    fn eval(&mut self, x: &[f64], l: f64, g: &mut [f64], gl: &mut [f64], h: &mut [f64]) -> bool {
        self.set_y(x);
        for i in 0..self.n {
            let y = self.y[i];
            self.dy[i] = self.k[i] * y + self.quartic[i] * y * y * y - l * self.b[i];
        }
        let n = self.n;
        for i in 0..n {
            g[i] = (0..n).map(|j| self.q[i + n * j] * self.dy[j]).sum();
            gl[i] = -(0..n).map(|j| self.q[i + n * j] * self.b[j]).sum::<f64>();
        }
        self.hessian(h);
        true
    }
}

#[test]
fn rotated_snap_through_folds_and_inertia_match_dense_eigenvalues() {
    for (n, seed) in [(6, 1), (12, 2), (30, 3)] {
        let mut p = DensePath::new(Rotated::new(n, seed));
        let opts = PalcOptions::default().with_steps(0.05, 1e-8, 0.2).unwrap();
        let mut palc = Palc::new(n, opts).unwrap();
        // start: y = the equilibrium at lambda = -1 (y_0 = X_START)
        let (l0, x0) = p.problem.fold(X_START);
        assert!((l0 + 1.0).abs() < 1e-14);
        let (l1, _) = p.problem.fold(-X_START);
        let b = palc.branch(&mut p, &x0, l0, Direction::Increasing, Some(l1), |_| {
            Control::Continue
        });
        assert_eq!(
            b.report.termination,
            PathTermination::ReachedTarget,
            "{}",
            b.report
        );
        // inertia at every point = dense eigenvalue count: 1 (the unstable
        // direction) + 1 in the middle part
        let mut h = vec![0.0; n * n];
        let mut middle = 0;
        for pt in &b.points {
            p.problem.set_y(&pt.x);
            p.problem.hessian(&mut h);
            let neg = negative_eigenvalues(n, &h).unwrap();
            assert_eq!(pt.inertia.negative, neg, "n = {n}, lambda = {}", pt.lambda);
            assert_eq!(pt.inertia.positive, n - neg);
            assert!(neg == 1 || neg == 2);
            middle += usize::from(neg == 2);
        }
        assert!(middle >= 3, "n = {n}: {middle} points in the middle part");
        let folds: Vec<_> = b.folds().collect();
        assert_eq!((folds.len(), b.events.len()), (2, 2), "{:?}", b.events);
        for (f, y0, (before, after)) in
            [(folds[0], -x_fold(), (1, 2)), (folds[1], x_fold(), (2, 1))]
        {
            let (lf, xf) = p.problem.fold(y0);
            assert!(f.located);
            assert!(
                (f.lambda - lf).abs() <= 1e-9,
                "n = {n}: {} vs {lf}",
                f.lambda
            );
            let dx = max_abs_diff(&f.x, &xf);
            assert!(dx <= 1e-9, "n = {n}: fold x off by {dx:e}");
            assert_eq!(
                (f.inertia_before.negative, f.inertia_after.negative),
                (before, after)
            );
        }
    }
}

// -------------------------------------------- semiseparable chain model

/// A chain of `blocks` elements with `n` unknowns each (copied, trimmed,
/// from the crate's unit tests): every element has a quadratic + quartic
/// energy and passes a rotation `s_k = sum_{j <= k} a_j . x_j` down the
/// chain, held at each element by a spring `phi_k(s) = p_k s^2/2 + q_k
/// s^4/4`; the tip spring is a double well (`p = -mu`, `q = nu`) and the
/// load a tip moment, conjugate to `s_N`:
///
/// `E = sum_k [x_k^T A_k x_k / 2 + sum_i c_ki x_ki^4 / 4 + phi_k(s_k)] - lambda s_N`.
///
/// The Hessian is block diagonal plus rank-one semiseparable; the load
/// passes limit points where `phi_N''` is negative enough.
#[derive(Clone)]
struct ChainModel {
    n: usize,
    blocks: usize,
    a: Vec<f64>,
    c: Vec<f64>,
    arm: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
    lambda: f64,
    s: Vec<f64>,
    d1: Vec<f64>,
    d2: Vec<f64>,
}

impl ChainModel {
    #[allow(clippy::too_many_arguments)]
    fn random(
        n: usize,
        blocks: usize,
        shift: f64,
        quartic: f64,
        kappa: f64,
        beta: f64,
        mu: f64,
        nu: f64,
        seed: u64,
    ) -> Self {
        let mut rng = fastrand::Rng::with_seed(seed);
        let mut sym = || 2.0 * rng.f64() - 1.0;
        let dim = n * blocks;
        let mut a = vec![0.0; n * n * blocks];
        for k in 0..blocks {
            let m: Vec<f64> = (0..n * n).map(|_| sym()).collect();
            let ak = &mut a[k * n * n..(k + 1) * n * n];
            for j in 0..n {
                for i in 0..n {
                    let v: f64 = (0..n).map(|l| m[i + l * n] * m[j + l * n]).sum();
                    ak[i + j * n] = v / n as f64 + if i == j { shift } else { 0.0 };
                }
            }
        }
        let c = (0..dim)
            .map(|_| quartic * (1.0 + sym()) * 0.5 + 0.5 * quartic)
            .collect();
        let arm = (0..dim).map(|_| sym()).collect();
        let mut p = vec![kappa; blocks];
        let mut q = vec![kappa * beta; blocks];
        p[blocks - 1] = -mu;
        q[blocks - 1] = nu;
        ChainModel {
            n,
            blocks,
            a,
            c,
            arm,
            p,
            q,
            lambda: 0.0,
            s: vec![0.0; blocks],
            d1: vec![0.0; blocks],
            d2: vec![0.0; blocks],
        }
    }

    fn size(&self) -> usize {
        self.n * self.blocks
    }

    fn sweep(&mut self, x: &[f64]) {
        let n = self.n;
        let mut s = 0.0;
        for k in 0..self.blocks {
            s += (0..n)
                .map(|i| self.arm[k * n + i] * x[k * n + i])
                .sum::<f64>();
            self.s[k] = s;
        }
        let (mut d1, mut d2) = (0.0, 0.0);
        for k in (0..self.blocks).rev() {
            let (s, p, q) = (self.s[k], self.p[k], self.q[k]);
            d1 += p * s + q * s * s * s;
            d2 += p + 3.0 * q * s * s;
            self.d1[k] = d1;
            self.d2[k] = d2;
        }
    }

    fn block_ax(&self, x: &[f64], k: usize, i: usize) -> f64 {
        let n = self.n;
        (0..n)
            .map(|j| self.a[k * n * n + i + j * n] * x[k * n + j])
            .sum()
    }

    /// `g` and `g_lambda` (after a sweep at `x`).
    fn grad(&self, x: &[f64], g: &mut [f64], gl: &mut [f64]) {
        let n = self.n;
        for k in 0..self.blocks {
            for i in 0..n {
                let r = k * n + i;
                g[r] = self.block_ax(x, k, i) + self.c[r] * x[r].powi(3) + self.d1[k] * self.arm[r]
                    - self.lambda * self.arm[r];
                gl[r] = -self.arm[r];
            }
        }
    }

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

    /// The dense Hessian from the formulas (after a sweep at `x`).
    fn dense(&self, x: &[f64], h: &mut [f64]) {
        let n = self.n;
        let dim = self.size();
        for cb in 0..self.blocks {
            for cc in 0..n {
                let col = cb * n + cc;
                for rb in 0..self.blocks {
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

    fn negative_eigenvalues_at(&self, x: &[f64]) -> usize {
        let mut m = self.clone();
        m.sweep(x);
        let dim = m.size();
        let mut h = vec![0.0; dim * dim];
        m.dense(x, &mut h);
        negative_eigenvalues(dim, &h).unwrap()
    }
}

impl DensePathProblem for ChainModel {
    fn dim(&self) -> usize {
        self.size()
    }
    fn eval(&mut self, x: &[f64], l: f64, g: &mut [f64], gl: &mut [f64], h: &mut [f64]) -> bool {
        self.lambda = l;
        self.sweep(x);
        self.grad(x, g, gl);
        self.dense(x, h);
        true
    }
}

/// The tip rotation `s_N = t` as a target (bordered solves).
struct TipTarget {
    m: ChainModel,
    t: f64,
}

impl DenseBorderedProblem for TipTarget {
    fn dim(&self) -> usize {
        self.m.size()
    }
    fn eval(&mut self, x: &[f64], l: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
        self.m.lambda = l;
        self.m.sweep(x);
        self.m.grad(x, &mut out.g, &mut out.g_lambda);
        self.m.dense(x, h);
        out.c = self.m.s[self.m.blocks - 1] - self.t;
        out.c_x.copy_from_slice(&self.m.arm);
        out.c_lambda = 0.0;
        true
    }
}

/// [`ChainModel`] with its Hessian as a [`Semiseparable`]: no dense matrix.
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

impl Path for SemiChain {
    fn dim(&self) -> usize {
        self.m.size()
    }
    fn eval(&mut self, x: &[f64], l: f64, g: &mut [f64], gl: &mut [f64]) -> bool {
        self.m.lambda = l;
        self.m.sweep(x);
        self.m.grad(x, g, gl);
        self.m.structured(x, &mut self.h);
        true
    }
}

/// As a [`Bordered`] problem too (target ignored by the path), to check
/// [`BorderedPath`].
impl Bordered for SemiChain {
    fn dim(&self) -> usize {
        self.m.size()
    }
    fn eval(&mut self, x: &[f64], l: f64, out: &mut BorderedEval) -> bool {
        Path::eval(self, x, l, &mut out.g, &mut out.g_lambda);
        out.c = 0.0;
        out.c_x.fill(0.0);
        out.c_lambda = 1.0;
        true
    }
}

fn chain(n: usize, blocks: usize, seed: u64) -> ChainModel {
    ChainModel::random(n, blocks, 0.3, 0.5, 0.5, 0.2, 2.0, 1.0, seed)
}

#[test]
fn semiseparable_chain_passes_a_fold_like_the_dense_path() {
    for (n, blocks, seed) in [(3, 8, 1), (2, 10, 2), (1, 16, 3), (5, 3, 4)] {
        let m = chain(n, blocks, seed);
        let dim = m.size();
        let opts = PalcOptions::default().with_steps(0.02, 1e-8, 0.2).unwrap();
        // (0, 0) is an equilibrium on the unstable part (H indefinite);
        // decreasing load: s_N grows, the load falls to a fold, then rises
        let x0 = vec![0.0; dim];
        let target = 0.5;
        let mut semi = SemiChain::new(m.clone());
        let bs = Palc::new(dim, opts).unwrap().branch(
            &mut semi,
            &x0,
            0.0,
            Direction::Decreasing,
            Some(target),
            |_| Control::Continue,
        );
        let mut dense = DensePath::new(m.clone());
        let bd = Palc::new(dim, opts).unwrap().branch(
            &mut dense,
            &x0,
            0.0,
            Direction::Decreasing,
            Some(target),
            |_| Control::Continue,
        );
        let mut bordered = BorderedPath::new(SemiChain::new(m.clone()));
        let bb = Palc::new(dim, opts).unwrap().branch(
            &mut bordered,
            &x0,
            0.0,
            Direction::Decreasing,
            Some(target),
            |_| Control::Continue,
        );
        for b in [&bs, &bd, &bb] {
            assert_eq!(
                b.report.termination,
                PathTermination::ReachedTarget,
                "{n} x {blocks}: {}",
                b.report
            );
            assert_eq!(b.last().unwrap().lambda, target);
            let folds: Vec<_> = b.folds().collect();
            assert_eq!((folds.len(), b.events.len()), (1, 1), "{:?}", b.events);
            assert_eq!(
                (
                    folds[0].inertia_before.negative,
                    folds[0].inertia_after.negative
                ),
                (1, 0)
            );
            assert!(folds[0].lambda < 0.0 && folds[0].located);
        }
        // structured and dense agree: the folds, the end, the point count
        let (fs, fd) = (&bs.events[0], &bd.events[0]);
        let scale = 1.0 + fs.x.iter().fold(0.0f64, |a, v| a.max(v.abs()));
        assert!(
            (fs.lambda - fd.lambda).abs() <= 1e-10 * (1.0 + fs.lambda.abs()),
            "{n} x {blocks}: fold lambda {} vs {}",
            fs.lambda,
            fd.lambda
        );
        let dx = max_abs_diff(&fs.x, &fd.x);
        assert!(dx <= 1e-8 * scale, "{n} x {blocks}: fold x off by {dx:e}");
        assert!(max_abs_diff(&bs.last().unwrap().x, &bd.last().unwrap().x) <= 1e-9 * scale);
        assert_eq!(bs.points.len(), bd.points.len());
        assert_eq!(bs.points, bb.points);
        // the inertia at each point against dense eigenvalues
        for pt in &bs.points {
            let neg = m.negative_eigenvalues_at(&pt.x);
            assert_eq!(
                pt.inertia.negative, neg,
                "{n} x {blocks}, lambda = {}",
                pt.lambda
            );
            assert_eq!(pt.inertia.positive, dim - neg);
        }
        // at the fold, H is (nearly) singular: its smallest eigenvalue is
        // tiny compared with the others
        let mut mm = m.clone();
        mm.lambda = fs.lambda;
        mm.sweep(&fs.x);
        let mut h = vec![0.0; dim * dim];
        mm.dense(&fs.x, &mut h);
        let emin = fpc_newton::min_eigenvalue(dim, &h).abs();
        assert!(
            emin < 1e-6,
            "{n} x {blocks}: min eigenvalue {emin:e} at the fold"
        );
    }
}

// ------------------------------------------------------ restricted inertia

/// A [`Semiseparable`] as a [`LinearSystem`].
struct Semi(Semiseparable);

impl LinearSystem for Semi {
    fn diagonal_range(&self) -> (f64, f64) {
        self.0.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.0.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.0.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.0.apply(x, out)
    }
}

#[test]
fn restricted_inertia_matches_the_reduced_hessian() {
    let mut rng = fastrand::Rng::with_seed(99);
    let mut checked = 0;
    for trial in 0..400 {
        let n = 2 + trial % 11;
        // H = Q diag(d) Q^T with eigenvalues of both signs, some small
        let q = random_orthogonal(n, &mut rng);
        let d: Vec<f64> = (0..n)
            .map(|_| {
                let v = 2.0 * rng.f64() - 1.0;
                if rng.f64() < 0.2 {
                    1e-6 * v
                } else {
                    v
                }
            })
            .collect();
        let mut a = vec![0.0; n * n];
        for c in 0..n {
            for r in 0..n {
                a[r + n * c] = (0..n).map(|j| q[r + n * j] * d[j] * q[c + n * j]).sum();
            }
        }
        let c: Vec<f64> = (0..n).map(|_| 2.0 * rng.f64() - 1.0).collect();
        let mut m = DenseMatrix::new(n, LinearBackend::Auto);
        m.matrix_mut().copy_from_slice(&a);
        let mut work = vec![0.0; 2 * n];
        let inertia = m.factor(0.0, PivotKind::Symmetric).unwrap();
        let r = restricted_inertia(&mut m, inertia, &c, &mut work).unwrap();
        let red = reduce(n, &a, &null_basis(&c));
        let neg = negative_eigenvalues(n - 1, &red).unwrap();
        assert_eq!(r.negative, neg, "trial {trial}, n = {n}, d = {d:?}");
        assert_eq!(r.positive, n - 1 - neg);
        // the same through factor_restricted_inertia
        assert_eq!(factor_restricted_inertia(&mut m, &c, &mut work), Ok(r));
        checked += 1;
    }
    assert_eq!(checked, 400);

    // structured: random semiseparable matrices against their dense form
    for trial in 0..60 {
        let (bn, nb) = (1 + trial % 4, 2 + trial % 5);
        let dim = bn * nb;
        let mut s = Semiseparable::new(bn, nb);
        for k in 0..nb {
            let blk = s.block_mut(k);
            for j in 0..bn {
                for i in j..bn {
                    let v = 2.0 * rng.f64() - 1.0;
                    blk[i + bn * j] = v;
                    blk[j + bn * i] = v;
                }
            }
            let (u, w) = s.coupling_mut(k);
            for i in 0..bn {
                u[i] = 2.0 * rng.f64() - 1.0;
                w[i] = 0.5 * (2.0 * rng.f64() - 1.0);
            }
        }
        let mut a = vec![0.0; dim * dim];
        s.dense(&mut a);
        let c: Vec<f64> = (0..dim).map(|_| 2.0 * rng.f64() - 1.0).collect();
        let mut work = vec![0.0; 2 * dim];
        let mut semi = Semi(s);
        let Ok(r) = factor_restricted_inertia(&mut semi, &c, &mut work) else {
            continue;
        };
        let neg = negative_eigenvalues(dim - 1, &reduce(dim, &a, &null_basis(&c))).unwrap();
        assert_eq!(r.negative, neg, "structured trial {trial}");
        assert_eq!(r.positive, dim - 1 - neg);
    }

    // H singular but the bordered matrix regular: an error, documented
    let mut m = DenseMatrix::new(2, LinearBackend::Auto);
    m.matrix_mut().copy_from_slice(&[0.0, 0.0, 0.0, 1.0]);
    let mut work = [0.0; 4];
    assert!(matches!(
        factor_restricted_inertia(&mut m, &[1.0, 0.0], &mut work),
        Err(RestrictedInertiaError::Hessian(
            FactorError::Singular { .. }
        ))
    ));
}

#[test]
fn bordered_newton_restricted_inertia_of_a_tip_controlled_chain() {
    // Controlling the tip rotation s_N: H is indefinite at small s_N (the
    // double well's maximum), but positive definite on s_N = const, so the
    // controlled equilibrium is stable although H is not.
    for (n, blocks, seed) in [(3, 6, 5), (2, 8, 6), (1, 16, 3)] {
        let m = chain(n, blocks, seed);
        let dim = m.size();
        let mut p = DenseBordered::new(TipTarget {
            m: m.clone(),
            t: 0.0,
        });
        let mut bn = BorderedNewton::new(dim, NewtonOptions::default()).unwrap();
        let (mut x, mut lambda) = (vec![0.0; dim], 0.0);
        let mut indefinite = 0;
        for t in [0.05, 0.1, 0.2, 0.4, 0.8, 1.6] {
            p.problem.t = t;
            let r = bn.solve(&mut p, &mut x, &mut lambda);
            assert!(r.converged(), "{r}");
            let restricted = bn.last_restricted_inertia(&mut p).unwrap();
            // against Z^T H Z at the returned point
            let mut mm = m.clone();
            mm.lambda = lambda;
            mm.sweep(&x);
            let mut h = vec![0.0; dim * dim];
            mm.dense(&x, &mut h);
            let red = reduce(dim, &h, &null_basis(&m.arm));
            let neg = negative_eigenvalues(dim - 1, &red).unwrap();
            assert_eq!(restricted.negative, neg, "t = {t}");
            assert_eq!(restricted.positive, dim - 1 - neg);
            assert_eq!(restricted.negative, 0, "t = {t}");
            indefinite += usize::from(negative_eigenvalues(dim, &h).unwrap() > 0);
        }
        assert!(indefinite > 0, "{n} x {blocks}: H itself was indefinite");
    }
}

// ------------------------------------------------------------ allocations

#[test]
fn accepted_steps_and_events_do_not_allocate() {
    // dense 1-D, dense n-D, semiseparable chain: a warm-up run, then the
    // same run counted (the Palc workspace and the problems exist already)
    let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
    let mut p = DensePath::new(Snap::new());
    let mut tally = Tally {
        points: 0,
        events: 0,
        folds: 0,
    };
    palc.follow(
        &mut p,
        &[-1.3],
        -1.0,
        Direction::Increasing,
        Some(1.0),
        &mut tally,
    );
    let allocs = allocations_in(|| {
        let r = palc.follow(
            &mut p,
            &[-1.3],
            -1.0,
            Direction::Increasing,
            Some(1.0),
            &mut tally,
        );
        assert_eq!(r.termination, PathTermination::ReachedTarget);
    });
    assert_eq!(allocs, 0, "allocations in Palc::follow (1-D)");
    assert_eq!(tally.folds, 4);

    let m = chain(3, 8, 1);
    let dim = m.size();
    let x0 = vec![0.0; dim];
    let mut semi = SemiChain::new(m.clone());
    let mut palc = Palc::new(dim, PalcOptions::default()).unwrap();
    let mut tally = Tally {
        points: 0,
        events: 0,
        folds: 0,
    };
    palc.follow(
        &mut semi,
        &x0,
        0.0,
        Direction::Decreasing,
        Some(0.5),
        &mut tally,
    );
    let mut steps = 0;
    let allocs = allocations_in(|| {
        let r = palc.follow(
            &mut semi,
            &x0,
            0.0,
            Direction::Decreasing,
            Some(0.5),
            &mut tally,
        );
        assert_eq!(r.termination, PathTermination::ReachedTarget);
        steps = r.steps;
    });
    assert_eq!(allocs, 0, "allocations in Palc::follow (semiseparable)");
    assert!(steps > 5 && tally.folds == 2 && tally.events == 2);

    // a closure observer, dense chain
    let mut dense = DensePath::new(m);
    let mut palc = Palc::new(dim, PalcOptions::default()).unwrap();
    let mut lowest = f64::INFINITY;
    let mut obs = |pt: &PathPoint<'_>| {
        lowest = lowest.min(pt.lambda);
        Control::Continue
    };
    palc.follow(
        &mut dense,
        &x0,
        0.0,
        Direction::Decreasing,
        Some(0.5),
        &mut obs,
    );
    let allocs = allocations_in(|| {
        palc.follow(
            &mut dense,
            &x0,
            0.0,
            Direction::Decreasing,
            Some(0.5),
            &mut obs,
        );
    });
    assert_eq!(allocs, 0, "allocations in Palc::follow (dense chain)");
    assert!(lowest < 0.0);
}

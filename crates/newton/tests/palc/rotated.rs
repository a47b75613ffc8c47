//! The snap-through rotated into `n` dimensions: folds and inertia against
//! dense eigenvalues.

use super::snap::*;
use super::*;

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
        let mut p = Dense::path(Rotated::new(n, seed));
        let opts = PalcOptions {
            initial_step: 0.05,
            min_step: 1e-8,
            max_step: 0.2,
            ..Default::default()
        };
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

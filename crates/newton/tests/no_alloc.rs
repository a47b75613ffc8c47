//! The solvers' iterations must not touch the heap: after the workspace is
//! built and a warm-up solve, repeated `Newton::minimize` and
//! `BorderedNewton::solve` calls perform zero allocations, for a problem
//! wrapped in `Dense` (faer's dense factorisations) and for one that keeps its Hessian
//! as a `Semiseparable`. Checked with a counting global allocator that
//! counts per thread, so the tests of this file may run concurrently.

use fpc_newton::{
    Bordered, BorderedEval, BorderedNewton, Dense, DenseBorderedProblem, DenseHessian, Energy,
    FactorError, Gradient, Hessian, Inertia, LinearSystem, Newton, NewtonOptions, PivotKind,
    Semiseparable,
};
#[path = "common/counting.rs"]
mod counting;
use counting::allocations_in;

// ------------------------------------------------------------ dense chain

/// Chain of tilted double wells with nearest-neighbour and all-to-all
/// weak coupling (dense Hessian, indefinite near 0):
/// `sum x_i^4/4 - x_i^2/2 - t x_i + 1/4 sum (x_{i+1}-x_i)^2 + 0.1/n (sum x_i)^2`.
struct Chain {
    n: usize,
    tilt: f64,
}

impl Energy for Chain {
    fn dim(&self) -> usize {
        self.n
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        let s: f64 = x.iter().sum();
        let mut f = 0.1 / self.n as f64 * s * s;
        for i in 0..self.n {
            f += x[i].powi(4) / 4.0 - x[i] * x[i] / 2.0 - self.tilt * x[i];
            if i + 1 < self.n {
                f += 0.25 * (x[i + 1] - x[i]).powi(2);
            }
        }
        f
    }
}

impl Gradient for Chain {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let s: f64 = x.iter().sum();
        for i in 0..self.n {
            g[i] = x[i].powi(3) - x[i] - self.tilt + 0.2 / self.n as f64 * s;
        }
        for i in 0..self.n - 1 {
            let d = 0.5 * (x[i + 1] - x[i]);
            g[i + 1] += d;
            g[i] -= d;
        }
        self.energy(x)
    }
}

impl DenseHessian for Chain {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let n = self.n;
        h.fill(0.2 / n as f64);
        for i in 0..n {
            h[i * (n + 1)] += 3.0 * x[i] * x[i] - 1.0;
        }
        for i in 0..n - 1 {
            h[i * (n + 1)] += 0.5;
            h[(i + 1) * (n + 1)] += 0.5;
            h[i + (i + 1) * n] -= 0.5;
            h[(i + 1) + i * n] -= 0.5;
        }
        self.gradient(x, g)
    }
}

/// The same chain with the tilt as load `lambda` and target `x_{n-1} = t`.
struct ChainTarget {
    chain: Chain,
    t: f64,
}

impl DenseBorderedProblem for ChainTarget {
    fn dim(&self) -> usize {
        self.chain.n
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool {
        let n = self.chain.n;
        self.chain.tilt = lambda;
        self.chain.hessian(x, &mut out.g, h);
        out.g_lambda.fill(-1.0);
        out.c = x[n - 1] - self.t;
        out.c_x.fill(0.0);
        out.c_x[n - 1] = 1.0;
        out.c_lambda = 0.0;
        true
    }
}

const DENSE_CASES: [usize; 2] = [32, 200];

#[test]
fn dense_minimize_does_not_allocate() {
    for n in DENSE_CASES {
        let mut newton = Newton::new(n, NewtonOptions::default());
        let mut p = Dense::new(Chain { n, tilt: 0.5 });
        let start: Vec<f64> = (0..n).map(|i| 0.1 + 0.01 * (i as f64).sin()).collect();
        let mut x = start.clone();
        let r = newton.minimize(&mut p, &mut x);
        assert!(r.converged(), "n = {n}: {r}");

        let mut shifted = 0.0f64;
        let allocs = allocations_in(|| {
            for k in 0..10 {
                x.copy_from_slice(&start);
                p.problem.tilt = 0.5 + 0.01 * k as f64;
                let r = newton.minimize(&mut p, &mut x);
                assert!(r.converged());
                shifted = shifted.max(r.max_shift);
            }
        });
        assert_eq!(allocs, 0, "n = {n}: allocations inside minimize");
        assert!(shifted > 0.0, "the shifted-Cholesky path was exercised");
    }
}

#[test]
fn dense_bordered_solve_does_not_allocate() {
    for n in DENSE_CASES {
        let mut newton = Newton::new(n, NewtonOptions::default());
        let mut x: Vec<f64> = (0..n).map(|i| 0.1 + 0.01 * (i as f64).sin()).collect();
        assert!(newton
            .minimize(&mut Dense::new(Chain { n, tilt: 0.5 }), &mut x)
            .converged());
        let eq = x;
        // Bordered solves warm-started from the equilibrium at tilt 0.5,
        // with the last coordinate prescribed a little further.
        let mut bordered = BorderedNewton::new(n, NewtonOptions::default()).unwrap();
        let mut bt = Dense::bordered(ChainTarget {
            chain: Chain { n, tilt: 0.0 },
            t: eq[n - 1] + 0.05,
        });
        let mut xb = eq.clone();
        let mut lambda = 0.5;
        let r = bordered.solve(&mut bt, &mut xb, &mut lambda);
        assert!(r.converged(), "{r}");

        let allocs = allocations_in(|| {
            for k in 0..10 {
                xb.copy_from_slice(&eq);
                lambda = 0.5;
                bt.problem.t = eq[n - 1] + 0.01 * k as f64;
                assert!(bordered.solve(&mut bt, &mut xb, &mut lambda).converged());
            }
        });
        // where they come from, if any: the dense symmetric factorisation
        let factor = allocations_in(|| {
            bt.factor(0.0, PivotKind::Symmetric).unwrap();
        });
        assert_eq!(
            allocs, 0,
            "n = {n}: allocations inside BorderedNewton::solve \
             ({factor} in one DenseMatrix::factor(_, PivotKind::Symmetric))"
        );
    }
}

// ---------------------------------------------------- semiseparable chain

/// Blocks of `m` tilted double wells with a nearest-neighbour coupling
/// inside each block, and the running sum `s_k` of the unknowns of blocks
/// `0..=k` held by a spring `kappa s_k^2 / 2` at every block:
/// `sum x^4/4 - x^2/2 - tilt x + 1/4 sum_(within blocks) (x_{i+1}-x_i)^2 +
/// kappa/2 sum_k s_k^2`. Its Hessian is a [`Semiseparable`]: blocks `D_k +
/// T_k 1 1^T`, coupling `u_k = 1`, `w_k = -T_k 1`, with `T_k = kappa (N -
/// k)`. Evaluations do not allocate.
struct SemiChain {
    m: usize,
    blocks: usize,
    tilt: f64,
    kappa: f64,
    /// target `x_last = t` (bordered, with the tilt as load)
    t: f64,
    sums: Vec<f64>,
    h: Semiseparable,
    /// One block and its coupling vectors on their way into `h`.
    blk: Vec<f64>,
    u: Vec<f64>,
    w: Vec<f64>,
}

impl SemiChain {
    fn new(m: usize, blocks: usize, tilt: f64) -> SemiChain {
        SemiChain {
            m,
            blocks,
            tilt,
            kappa: 0.1 / blocks as f64,
            t: 0.0,
            sums: vec![0.0; blocks],
            h: Semiseparable::new(m, blocks),
            blk: vec![0.0; m * m],
            u: vec![0.0; m],
            w: vec![0.0; m],
        }
    }

    fn n(&self) -> usize {
        self.m * self.blocks
    }

    fn running_sums(&mut self, x: &[f64]) -> f64 {
        let mut s = 0.0;
        let mut f = 0.0;
        for k in 0..self.blocks {
            s += x[k * self.m..(k + 1) * self.m].iter().sum::<f64>();
            self.sums[k] = s;
            f += 0.5 * self.kappa * s * s;
        }
        f
    }

    fn structured_hessian(&mut self, x: &[f64]) {
        let m = self.m;
        for k in 0..self.blocks {
            let t = self.kappa * (self.blocks - k) as f64;
            let b = &mut self.blk;
            b.fill(t);
            for i in 0..m {
                let xi = x[k * m + i];
                b[i * (m + 1)] += 3.0 * xi * xi - 1.0;
                if i + 1 < m {
                    b[i * (m + 1)] += 0.5;
                    b[(i + 1) * (m + 1)] += 0.5;
                    b[i + (i + 1) * m] -= 0.5;
                    b[(i + 1) + i * m] -= 0.5;
                }
            }
            self.h.set_block(k, b);
            self.u.fill(1.0);
            self.w.fill(-t);
            self.h.set_coupling(k, &self.u, &self.w);
        }
    }
}

impl Energy for SemiChain {
    fn dim(&self) -> usize {
        self.n()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        let mut f = self.running_sums(x);
        for (i, &v) in x.iter().enumerate() {
            f += v.powi(4) / 4.0 - v * v / 2.0 - self.tilt * v;
            if (i + 1) % self.m != 0 {
                f += 0.25 * (x[i + 1] - v).powi(2);
            }
        }
        f
    }
}

impl Gradient for SemiChain {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let f = self.energy(x);
        // d/dx_(k,i) of kappa/2 sum_j s_j^2 = kappa sum_{j >= k} s_j
        let mut tail = 0.0;
        for k in (0..self.blocks).rev() {
            tail += self.kappa * self.sums[k];
            for i in 0..self.m {
                let v = x[k * self.m + i];
                g[k * self.m + i] = v * v * v - v - self.tilt + tail;
            }
        }
        for i in 0..self.n() - 1 {
            if (i + 1) % self.m != 0 {
                let d = 0.5 * (x[i + 1] - x[i]);
                g[i + 1] += d;
                g[i] -= d;
            }
        }
        f
    }
}

impl Hessian for SemiChain {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let f = self.gradient(x, g);
        self.structured_hessian(x);
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
        self.n()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval) -> bool {
        let n = self.n();
        self.tilt = lambda;
        self.hessian(x, &mut out.g);
        out.g_lambda.fill(-1.0);
        out.c = x[n - 1] - self.t;
        out.c_x.fill(0.0);
        out.c_x[n - 1] = 1.0;
        out.c_lambda = 0.0;
        true
    }
}

const SEMI_CASES: [(usize, usize); 3] = [(4, 50), (2, 16), (1, 40)];

#[test]
fn semiseparable_minimize_does_not_allocate() {
    for (m, blocks) in SEMI_CASES {
        let mut p = SemiChain::new(m, blocks, 0.5);
        let n = p.n();
        let mut newton = Newton::new(n, NewtonOptions::default());
        let start: Vec<f64> = (0..n).map(|i| 0.1 + 0.01 * (i as f64).sin()).collect();
        let mut x = start.clone();
        let r = newton.minimize(&mut p, &mut x);
        assert!(r.converged(), "{m} x {blocks}: {r}");

        let mut shifted = 0.0f64;
        let allocs = allocations_in(|| {
            for k in 0..10 {
                x.copy_from_slice(&start);
                p.tilt = 0.5 + 0.01 * k as f64;
                let r = newton.minimize(&mut p, &mut x);
                assert!(r.converged());
                shifted = shifted.max(r.max_shift);
            }
        });
        assert_eq!(allocs, 0, "{m} x {blocks}: allocations inside minimize");
        assert!(shifted > 0.0, "the shifted-Cholesky path was exercised");
    }
}

#[test]
fn semiseparable_bordered_solve_does_not_allocate() {
    for (m, blocks) in SEMI_CASES {
        let mut p = SemiChain::new(m, blocks, 0.5);
        let n = p.n();
        let mut x: Vec<f64> = (0..n).map(|i| 0.1 + 0.01 * (i as f64).sin()).collect();
        assert!(Newton::new(n, NewtonOptions::default())
            .minimize(&mut p, &mut x)
            .converged());
        let eq = x;
        let mut bordered = BorderedNewton::new(n, NewtonOptions::default()).unwrap();
        p.t = eq[n - 1] + 0.05;
        let mut xb = eq.clone();
        let mut lambda = 0.5;
        let r = bordered.solve(&mut p, &mut xb, &mut lambda);
        assert!(r.converged(), "{r}");

        let allocs = allocations_in(|| {
            for k in 0..10 {
                xb.copy_from_slice(&eq);
                lambda = 0.5;
                p.t = eq[n - 1] + 0.01 * k as f64;
                assert!(bordered.solve(&mut p, &mut xb, &mut lambda).converged());
            }
        });
        assert_eq!(
            allocs, 0,
            "{m} x {blocks}: allocations inside BorderedNewton::solve"
        );

        // the symmetric (and Cholesky) factorisation itself, where H is
        // indefinite (near x = 0, the double wells' maxima)
        let near_zero: Vec<f64> = (0..n).map(|i| 0.1 * (1.3 * i as f64).sin()).collect();
        let mut g = vec![0.0; n];
        p.hessian(&near_zero, &mut g);
        let mut rhs = vec![1.0; n];
        let mut inertia = None;
        let allocs = allocations_in(|| {
            for k in 0..5 {
                inertia = Some(p.factor(0.01 * k as f64, PivotKind::Symmetric).unwrap());
                p.solve(&mut rhs);
                assert!(p.factor(0.0, PivotKind::Cholesky).is_err());
            }
        });
        assert_eq!(
            allocs, 0,
            "{m} x {blocks}: allocations inside Semiseparable::factor (Symmetric) / solve"
        );
        assert!(inertia.unwrap().negative > 0, "indefinite pivots were met");
    }
}

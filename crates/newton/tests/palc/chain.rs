//! A chain whose Hessian is a `Semiseparable`, past a fold, against the
//! same chain through the dense reference path.

use super::*;

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
pub(super) struct ChainModel {
    pub(super) n: usize,
    pub(super) blocks: usize,
    pub(super) a: Vec<f64>,
    pub(super) c: Vec<f64>,
    pub(super) arm: Vec<f64>,
    pub(super) p: Vec<f64>,
    pub(super) q: Vec<f64>,
    pub(super) lambda: f64,
    pub(super) s: Vec<f64>,
    pub(super) d1: Vec<f64>,
    pub(super) d2: Vec<f64>,
}

impl ChainModel {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn random(
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

    pub(super) fn size(&self) -> usize {
        self.n * self.blocks
    }

    pub(super) fn sweep(&mut self, x: &[f64]) {
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

    pub(super) fn block_ax(&self, x: &[f64], k: usize, i: usize) -> f64 {
        let n = self.n;
        (0..n)
            .map(|j| self.a[k * n * n + i + j * n] * x[k * n + j])
            .sum()
    }

    /// `g` and `g_lambda` (after a sweep at `x`).
    pub(super) fn grad(&self, x: &[f64], g: &mut [f64], gl: &mut [f64]) {
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

    pub(super) fn structured(&self, x: &[f64], h: &mut Semiseparable) {
        let n = self.n;
        for k in 0..self.blocks {
            let arm = &self.arm[k * n..(k + 1) * n];
            // (on the stack: the allocation tests run this)
            let (mut blk, mut w) = ([0.0; 64], [0.0; 8]);
            assert!(n <= 8, "blocks of at most 8 here");
            for j in 0..n {
                for i in 0..n {
                    blk[i + j * n] = self.a[k * n * n + i + j * n] + self.d2[k] * arm[i] * arm[j];
                }
                blk[j * (n + 1)] += 3.0 * self.c[k * n + j] * x[k * n + j].powi(2);
            }
            h.set_block(k, &blk[..n * n]);
            for i in 0..n {
                w[i] = -self.d2[k] * arm[i];
            }
            h.set_coupling(k, arm, &w[..n]);
        }
    }

    /// The dense Hessian from the formulas (after a sweep at `x`).
    pub(super) fn dense(&self, x: &[f64], h: &mut [f64]) {
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

    pub(super) fn negative_eigenvalues_at(&self, x: &[f64]) -> usize {
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
pub(super) struct TipTarget {
    pub(super) m: ChainModel,
    pub(super) t: f64,
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
pub(super) struct SemiChain {
    m: ChainModel,
    h: Semiseparable,
}

impl SemiChain {
    pub(super) fn new(m: ChainModel) -> Self {
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

pub(super) fn chain(n: usize, blocks: usize, seed: u64) -> ChainModel {
    ChainModel::random(n, blocks, 0.3, 0.5, 0.5, 0.2, 2.0, 1.0, seed)
}

#[test]
fn semiseparable_chain_passes_a_fold_like_the_dense_path() {
    for (n, blocks, seed) in [(3, 8, 1), (2, 10, 2), (1, 16, 3), (5, 3, 4)] {
        let m = chain(n, blocks, seed);
        let dim = m.size();
        let opts = PalcOptions {
            initial_step: 0.02,
            min_step: 1e-8,
            max_step: 0.2,
            ..Default::default()
        };
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
        let mut dense = Dense::path(m.clone());
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

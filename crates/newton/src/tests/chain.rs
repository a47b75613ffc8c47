//! The semiseparable test chain: an elastica-like model with a dense and a
//! structured Hessian.

use super::*;

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
pub(super) struct ChainModel {
    n: usize,
    blocks: usize,
    /// `A_k`, column-major `n x n` each, symmetric.
    a: Vec<f64>,
    c: Vec<f64>,
    arm: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
    b: Vec<f64>,
    pub(super) e: Vec<f64>,
    pub(super) t: f64,
    pub(super) lambda: f64,
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
    pub(super) fn random(
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
    pub(super) fn tip_controlled(mut self, mu: f64, nu: f64) -> Self {
        let last = self.blocks - 1;
        self.p[last] = -mu;
        self.q[last] = nu;
        self.b = self.arm.clone();
        self.e = self.arm.clone();
        self
    }

    pub(super) fn size(&self) -> usize {
        self.n * self.blocks
    }

    /// The chain quantities at `x`; returns `sum_k phi(s_k)`.
    pub(super) fn sweep(&mut self, x: &[f64]) -> f64 {
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

    /// The Hessian assembled densely from the formulas (after a sweep at
    /// `x`), independently of [`Semiseparable`].
    pub(super) fn dense(&self, x: &[f64], h: &mut [f64]) {
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
    pub(super) fn negative_eigenvalues_at(&self, x: &[f64]) -> usize {
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
pub(super) struct SemiChain {
    pub(super) m: ChainModel,
    pub(super) h: Semiseparable,
}

impl SemiChain {
    pub(super) fn new(m: ChainModel) -> Self {
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

/// [`SemiChain`] staging each new Hessian beside the last factorisation
/// ([`Hessian::stages_hessian`]): two matrices, `h[active]` the factorised
/// one.
pub(super) struct StagedChain {
    pub(super) m: ChainModel,
    h: [Semiseparable; 2],
    active: usize,
    staged: bool,
}

impl StagedChain {
    pub(super) fn new(m: ChainModel) -> Self {
        let h = [0; 2].map(|_| Semiseparable::new(m.n, m.blocks));
        StagedChain {
            m,
            h,
            active: 0,
            staged: false,
        }
    }

    fn latest(&self) -> &Semiseparable {
        &self.h[self.active ^ usize::from(self.staged)]
    }
}

impl Energy for StagedChain {
    fn dim(&self) -> usize {
        self.m.size()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.m.value(x)
    }
}
impl Gradient for StagedChain {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.m.gradient(x, g)
    }
}
impl Hessian for StagedChain {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        let f = self.m.gradient(x, g);
        self.staged = true;
        self.m.structured(x, &mut self.h[self.active ^ 1]);
        f
    }
    fn stages_hessian(&self) -> bool {
        true
    }
}
impl LinearSystem for StagedChain {
    fn diagonal_range(&self) -> (f64, f64) {
        self.latest().diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.active ^= usize::from(std::mem::take(&mut self.staged));
        self.h[self.active].factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.h[self.active].solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.latest().apply(x, out)
    }
}

/// A bordered problem that remembers where the solver last factorised `H`
/// (the point of the evaluation before the factorisation).
pub(super) struct Recording<P> {
    pub(super) p: P,
    last_eval: (Vec<f64>, f64),
    pub(super) factored_at: Option<(Vec<f64>, f64)>,
}

impl<P> Recording<P> {
    pub(super) fn new(p: P) -> Self {
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

//! Symmetric matrices that are block diagonal plus a rank-one
//! semiseparable coupling, factorised and solved in linear time.
//!
//! The matrix has `N` diagonal blocks `B_k` of size `n x n` and, for block
//! row `k` below block column `j` (`k > j`), the block `-w_k u_j^T` (and its
//! transpose above the diagonal):
//!
//! ```text
//! H = blockdiag(B_k) - sum_{k > j} (E_k w_k u_j^T E_j^T + E_j u_j w_k^T E_k^T)
//! ```
//!
//! Such matrices arise wherever a chain of elements passes a quantity
//! down the chain (the coupling of block `j` to every later block is through
//! one vector `u_j`). Eliminating the blocks in order keeps the structure: the
//! Schur complement after eliminating block `m` has the same form with
//! `u_j <- u_j + gamma_m w_j` and `B_k <- B_k - gamma_m w_k w_k^T`, so the
//! block LDL^T factorisation needs `N` small `n x n` factorisations and two
//! scalar recurrences:
//!
//! ```text
//! Gamma_1 = 0
//! v_m = u_m + Gamma_m w_m,   P_m = B_m + tau I - Gamma_m w_m w_m^T
//! q_m = P_m^-1 v_m,          Gamma_{m+1} = Gamma_m + v_m^T q_m
//! ```
//!
//! `H + tau I` is congruent to `blockdiag(P_m)`, so its inertia is the sum
//! of the pivots' inertias (Sylvester's law) and it is positive definite
//! exactly when every pivot is.
//!
//! Written this way, each block's factorisation waits for the previous
//! one's (through `Gamma_m`): a chain of small dependent factorisations,
//! whose latency, not their arithmetic, sets the time. For Cholesky pivots
//! the work is reordered so that it does not: `Gamma_m >= 0` (it only
//! grows), so `P_m = B'_m - Gamma_m w_m w_m^T` (`B'_m = B_m + tau I`) is
//! positive definite exactly when `B'_m` is and `d_m = 1 - Gamma_m beta_m >
//! 0`, with `b_m = B'_m^-1 w_m` and `beta_m = w_m^T b_m`; and Sherman-Morrison
//! gives `P_m^-1 = B'_m^-1 + c_m b_m b_m^T` with `c_m = Gamma_m / d_m`. Every
//! block's Cholesky factorisation of `B'_m` and its solves for `b_m` and
//! `a_m = B'_m^-1 u_m` are then independent of the others, and only scalars
//! run along the chain:
//!
//! ```text
//! kappa_m = Gamma_m + c_m (alpha_m + Gamma_m beta_m),   alpha_m = u_m^T b_m
//! q_m = a_m + kappa_m b_m
//! Gamma_{m+1} = Gamma_m + u_m^T a_m + (kappa_m + Gamma_m) alpha_m + Gamma_m kappa_m beta_m
//! ```
//!
//! and likewise in the solves (`omega_m = w_m^T q_m`). A solve is a forward sweep (`z_k = b_k + w_k
//! sigma_k`, `sigma_{k+1} = sigma_k + q_k^T z_k`), the pivot solves, and a
//! backward sweep (`x_m = y_m + q_m rho_m`, `rho_{m-1} = rho_m + w_m^T x_m`).
//! Work and storage are `O(N n^3)` and `O(N n^2)`.

use crate::linear::{FactorError, Inertia};

/// How the pivots are factorised.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PivotKind {
    /// Cholesky (square-root-free, `L D L^T`): fails unless every pivot is
    /// positive definite (Newton's minimisation, where that is the test for
    /// a descent direction).
    Cholesky,
    /// Symmetric eigendecomposition: any nonsingular pivot, with its inertia
    /// (bordered solves, stability).
    Symmetric,
    /// Symmetric eigendecomposition with every pivot's eigenvalues replaced
    /// by their absolute values, and those below [`MODIFIED_FLOOR`] times
    /// the pivot's largest raised to that: the exact factorisation of
    /// `H + tau I + E` with `E` block diagonal and positive semidefinite
    /// (zero where `H + tau I` is positive definite), itself positive
    /// definite. Newton's direction where the Hessian is indefinite: unlike
    /// a shift of the whole diagonal, it leaves the directions of positive
    /// curvature as they are.
    Modified,
}

/// Relative floor on the modified pivots' eigenvalues
/// ([`PivotKind::Modified`]).
pub const MODIFIED_FLOOR: f64 = 1e-6;

/// A block-diagonal plus rank-one semiseparable symmetric matrix (module
/// docs) with its factorisation.
#[derive(Debug, Clone)]
pub struct Semiseparable {
    n: usize,
    blocks: usize,
    /// `B_k`, column-major `n x n` each (the full symmetric block).
    b: Vec<f64>,
    u: Vec<f64>,
    w: Vec<f64>,
    // factorisation
    kind: PivotKind,
    /// `L D L^T` factor of `B_k + tau I` (see [`cholesky`]) or the
    /// eigenvectors of the pivot `P_k`, per block.
    f: Vec<f64>,
    /// Cholesky pivots: `(B_k + tau I)^-1 w_k` per block.
    bw: Vec<f64>,
    /// Cholesky pivots: `[beta_k, c_k, omega_k]` per block (module docs).
    sm: Vec<[f64; 3]>,
    /// Eigenvalues per block (symmetric pivots).
    lambda: Vec<f64>,
    q: Vec<f64>,
    factored: bool,
    /// False while every coupling vector is zero (block diagonal: the
    /// recurrences are skipped).
    coupled: bool,
    scratch: Vec<f64>,
}

/// Jacobi sweeps before the eigenvalue iteration of a pivot gives up.
const MAX_SWEEPS: usize = 60;

impl Semiseparable {
    /// `blocks` blocks of size `n`, all zero.
    pub fn new(n: usize, blocks: usize) -> Semiseparable {
        Semiseparable {
            n,
            blocks,
            b: vec![0.0; n * n * blocks],
            u: vec![0.0; n * blocks],
            w: vec![0.0; n * blocks],
            kind: PivotKind::Cholesky,
            f: vec![0.0; n * n * blocks],
            bw: vec![0.0; n * blocks],
            sm: vec![[0.0; 3]; blocks],
            lambda: vec![0.0; n * blocks],
            q: vec![0.0; n * blocks],
            factored: false,
            coupled: false,
            scratch: vec![0.0; n * n + 4 * n],
        }
    }

    /// Block size `n`.
    pub fn block_size(&self) -> usize {
        self.n
    }

    /// Number of blocks `N`.
    pub fn blocks(&self) -> usize {
        self.blocks
    }

    /// The dimension `N n`.
    pub fn dim(&self) -> usize {
        self.n * self.blocks
    }

    /// Block `k`'s `B_k` (column-major, full), to fill in; invalidates the
    /// factorisation.
    pub fn block_mut(&mut self, k: usize) -> &mut [f64] {
        self.factored = false;
        let nn = self.n * self.n;
        &mut self.b[k * nn..(k + 1) * nn]
    }

    /// Block `k`'s coupling vectors `(u_k, w_k)`, to fill in; invalidates
    /// the factorisation.
    pub fn coupling_mut(&mut self, k: usize) -> (&mut [f64], &mut [f64]) {
        self.factored = false;
        self.coupled = true;
        let n = self.n;
        (
            &mut self.u[k * n..(k + 1) * n],
            &mut self.w[k * n..(k + 1) * n],
        )
    }

    /// Sets every coupling vector to zero (no coupling: block diagonal).
    pub fn clear_coupling(&mut self) {
        self.factored = false;
        if self.coupled {
            self.u.fill(0.0);
            self.w.fill(0.0);
        }
        self.coupled = false;
    }

    /// `(min_i H_ii, max_i |H_ii|)` (the coupling has no diagonal).
    pub fn diagonal_range(&self) -> (f64, f64) {
        let n = self.n;
        let mut lo = f64::INFINITY;
        let mut hi = 0.0f64;
        for k in 0..self.blocks {
            for i in 0..n {
                let d = self.b[k * n * n + i * (n + 1)];
                lo = lo.min(d);
                hi = hi.max(d.abs());
            }
        }
        (lo, hi)
    }

    /// True when every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.b
            .iter()
            .chain(&self.u)
            .chain(&self.w)
            .all(|v| v.is_finite())
    }

    /// `out = H x` in linear time.
    pub fn apply(&self, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        let nb = self.blocks;
        if !self.coupled {
            for k in 0..nb {
                let xk = &x[k * n..(k + 1) * n];
                let bk = &self.b[k * n * n..(k + 1) * n * n];
                for i in 0..n {
                    out[k * n + i] = (0..n).map(|j| bk[i + n * j] * xk[j]).sum();
                }
            }
            return;
        }
        // sum_{j<k} u_j^T x_j, running forward
        let mut s = 0.0;
        for k in 0..nb {
            let xk = &x[k * n..(k + 1) * n];
            let bk = &self.b[k * n * n..(k + 1) * n * n];
            let wk = &self.w[k * n..(k + 1) * n];
            for i in 0..n {
                let mut v = 0.0;
                for j in 0..n {
                    v += bk[i + n * j] * xk[j];
                }
                out[k * n + i] = v - wk[i] * s;
            }
            s += dot(&self.u[k * n..(k + 1) * n], xk);
        }
        // sum_{j>k} w_j^T x_j, running backward
        let mut t = 0.0;
        for k in (0..nb).rev() {
            let uk = &self.u[k * n..(k + 1) * n];
            for i in 0..n {
                out[k * n + i] -= uk[i] * t;
            }
            t += dot(&self.w[k * n..(k + 1) * n], &x[k * n..(k + 1) * n]);
        }
    }

    /// The dense matrix (column-major, `dim x dim`): for tests and for a
    /// dense fallback.
    pub fn dense(&self, h: &mut [f64]) {
        let n = self.n;
        let dim = self.dim();
        h.fill(0.0);
        for k in 0..self.blocks {
            for c in 0..n {
                for r in 0..n {
                    h[(k * n + r) + dim * (k * n + c)] = self.b[k * n * n + r + n * c];
                }
            }
            for j in 0..k {
                for c in 0..n {
                    for r in 0..n {
                        let v = -self.w[k * n + r] * self.u[j * n + c];
                        h[(k * n + r) + dim * (j * n + c)] = v;
                        h[(j * n + c) + dim * (k * n + r)] = v;
                    }
                }
            }
        }
    }

    /// Factorises `H + tau I` (module docs); returns its inertia.
    /// `PivotKind::Cholesky` fails at the first pivot that is not positive
    /// definite; `PivotKind::Symmetric` at the first (numerically) singular
    /// pivot.
    /// A non-finite entry (or shift) is reported as
    /// [`FactorError::NonFinite`] naming the first such block.
    pub fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        // the common block sizes run with the size known at compile time
        let r = match self.n {
            4 => self.factor_sized::<4>(tau, kind),
            5 => self.factor_sized::<5>(tau, kind),
            6 => self.factor_sized::<6>(tau, kind),
            _ => self.factor_sized::<0>(tau, kind),
        };
        // a failed pivot may come from an infinity or NaN: say so (checked
        // only on failure, so the successful path pays nothing)
        r.map_err(|e| match self.first_non_finite_block(tau) {
            Some(block) => FactorError::NonFinite { block },
            None => e,
        })
    }

    /// The inertia of `H + tau I` alone, as [`Semiseparable::factor`] with
    /// [`PivotKind::Symmetric`] counts it and with the same errors, but
    /// leaving nothing to solve with (the stability count). A pivot that a
    /// Cholesky factorisation shows clearly positive definite (its smallest
    /// eigenvalue provably above `1e-12` times its largest, far
    /// from the symmetric path's singularity threshold) counts as such
    /// without its eigenvalues; any other pivot takes the symmetric path.
    pub fn inertia(&mut self, tau: f64) -> Result<Inertia, FactorError> {
        let r = match self.n {
            4 => self.pivots_sized::<4>(tau, PivotKind::Symmetric, true),
            5 => self.pivots_sized::<5>(tau, PivotKind::Symmetric, true),
            6 => self.pivots_sized::<6>(tau, PivotKind::Symmetric, true),
            _ => self.pivots_sized::<0>(tau, PivotKind::Symmetric, true),
        };
        self.factored = false;
        r.map_err(|e| match self.first_non_finite_block(tau) {
            Some(block) => FactorError::NonFinite { block },
            None => e,
        })
    }

    /// The first block holding a non-finite entry (diagonal block or
    /// coupling vectors), or 0 for a non-finite shift.
    fn first_non_finite_block(&self, tau: f64) -> Option<usize> {
        if !tau.is_finite() {
            return Some(0);
        }
        let (n, nn) = (self.n, self.n * self.n);
        (0..self.blocks).find(|&m| {
            let finite = |v: &[f64]| v.iter().all(|x| x.is_finite());
            !(finite(&self.b[m * nn..(m + 1) * nn])
                && finite(&self.u[m * n..(m + 1) * n])
                && finite(&self.w[m * n..(m + 1) * n]))
        })
    }

    /// [`Semiseparable::factor`] for blocks of size `N` (0: `self.n`).
    fn factor_sized<const N: usize>(
        &mut self,
        tau: f64,
        kind: PivotKind,
    ) -> Result<Inertia, FactorError> {
        self.factored = false;
        self.kind = kind;
        if kind == PivotKind::Cholesky {
            self.factor_cholesky::<N>(tau)?;
            self.factored = true;
            return Ok(Inertia {
                positive: self.dim(),
                negative: 0,
            });
        }
        let inertia = self.pivots_sized::<N>(tau, kind, false)?;
        self.factored = true;
        Ok(inertia)
    }

    /// The symmetric or modified pivots' recurrence (module docs), with
    /// their inertia; `count_only` (for [`Semiseparable::inertia`]) lets a
    /// certified positive definite pivot skip its eigenvalues, which leaves
    /// the pivots unusable for solves.
    fn pivots_sized<const N: usize>(
        &mut self,
        tau: f64,
        kind: PivotKind,
        count_only: bool,
    ) -> Result<Inertia, FactorError> {
        let n = if N > 0 { N } else { self.n };
        let nn = n * n;
        let mut gamma = 0.0;
        let mut inertia = Inertia::default();
        for m in 0..self.blocks {
            let (um, wm) = (&self.u[m * n..(m + 1) * n], &self.w[m * n..(m + 1) * n]);
            let p = &mut self.f[m * nn..(m + 1) * nn];
            let bm = &self.b[m * nn..(m + 1) * nn];
            for c in 0..n {
                for r in 0..n {
                    p[r + n * c] = bm[r + n * c] - gamma * wm[r] * wm[c];
                }
                p[c + n * c] += tau;
            }
            let coupled = self.coupled;
            let qm = &mut self.q[m * n..(m + 1) * n];
            if coupled {
                for i in 0..n {
                    qm[i] = um[i] + gamma * wm[i];
                }
            }
            if count_only && certified_positive::<N>(n, p, &mut self.scratch) {
                inertia.positive += n;
                if coupled {
                    // the Cholesky factor sits at the front of the scratch
                    let (c, rest) = self.scratch.split_at_mut(nn);
                    let s = &mut rest[..n];
                    s.copy_from_slice(qm);
                    cholesky_solve::<N>(n, c, qm);
                    gamma += dot(s, qm);
                }
                if !gamma.is_finite() {
                    return Err(FactorError::NonFinite { block: m });
                }
                continue;
            }
            let lam = &mut self.lambda[m * n..(m + 1) * n];
            jacobi(n, p, lam, &mut self.scratch).ok_or(FactorError::NoConvergence { block: m })?;
            let scale = lam.iter().fold(0.0f64, |a, l| a.max(l.abs()));
            if kind == PivotKind::Modified {
                for l in lam.iter_mut() {
                    *l = l.abs().max(MODIFIED_FLOOR * scale);
                }
            }
            for &l in lam.iter() {
                if l.abs().partial_cmp(&(1e-14 * scale)) != Some(core::cmp::Ordering::Greater) {
                    return Err(FactorError::Singular { block: m });
                }
                if l > 0.0 {
                    inertia.positive += 1;
                } else {
                    inertia.negative += 1;
                }
            }
            if coupled {
                let (s, rest) = self.scratch.split_at_mut(n);
                s.copy_from_slice(qm);
                eigen_solve(n, p, lam, qm, rest);
                gamma += dot(s, qm);
            }
            if !gamma.is_finite() {
                return Err(FactorError::NonFinite { block: m });
            }
        }
        Ok(inertia)
    }

    /// The Cholesky factorisation of `H + tau I` in the reordered form of
    /// the module docs: block `m` fails with the index of its first
    /// non-positive pivot when `B'_m` is not positive definite, and with
    /// its last row when the chain's update makes `P_m` indefinite
    /// (`d_m <= 0`).
    fn factor_cholesky<const N: usize>(&mut self, tau: f64) -> Result<(), FactorError> {
        let n = if N > 0 { N } else { self.n };
        let nn = n * n;
        let coupled = self.coupled;
        let mut gamma = 0.0;
        for m in 0..self.blocks {
            let f = &mut self.f[m * nn..(m + 1) * nn];
            f.copy_from_slice(&self.b[m * nn..(m + 1) * nn]);
            for c in 0..n {
                f[c + n * c] += tau;
            }
            cholesky::<N>(n, f).map_err(|index| FactorError::NotPositiveDefinite {
                index: m * n + index,
            })?;
            if !coupled {
                continue;
            }
            let (um, wm) = (&self.u[m * n..(m + 1) * n], &self.w[m * n..(m + 1) * n]);
            let (a, b) = (
                &mut self.q[m * n..(m + 1) * n],
                &mut self.bw[m * n..(m + 1) * n],
            );
            a.copy_from_slice(um);
            b.copy_from_slice(wm);
            cholesky_solve::<N>(n, f, a);
            cholesky_solve::<N>(n, f, b);
            let (beta, alpha, uu) = (dot(wm, b), dot(um, b), dot(um, a));
            // the chain: scalars only
            let d = 1.0 - gamma * beta;
            // (a NaN fails too)
            if d.is_nan() || d <= 0.0 {
                return Err(FactorError::NotPositiveDefinite {
                    index: m * n + n - 1,
                });
            }
            let c = gamma / d;
            let kappa = gamma + c * (alpha + gamma * beta);
            for (ai, bi) in a.iter_mut().zip(b.iter()) {
                *ai += kappa * bi;
            }
            self.sm[m] = [beta, c, alpha + kappa * beta];
            gamma += uu + (kappa + gamma) * alpha + gamma * kappa * beta;
            if !gamma.is_finite() {
                return Err(FactorError::NonFinite { block: m });
            }
        }
        Ok(())
    }

    /// Solves `(H + tau I) x = b` in place with the last successful
    /// factorisation.
    ///
    /// # Panics
    /// When nothing is factorised (programmer error).
    pub fn solve(&mut self, b: &mut [f64]) {
        assert!(
            self.factored,
            "Semiseparable::solve without a factorisation"
        );
        match self.n {
            4 => self.solve_sized::<4>(b),
            5 => self.solve_sized::<5>(b),
            6 => self.solve_sized::<6>(b),
            _ => self.solve_sized::<0>(b),
        }
    }

    /// [`Semiseparable::solve`] for blocks of size `N` (0: `self.n`).
    fn solve_sized<const N: usize>(&mut self, b: &mut [f64]) {
        let n = if N > 0 { N } else { self.n };
        let nn = n * n;
        let nb = self.blocks;
        if !self.coupled {
            for k in 0..nb {
                let fk = &self.f[k * nn..(k + 1) * nn];
                let bk = &mut b[k * n..(k + 1) * n];
                match self.kind {
                    PivotKind::Cholesky => cholesky_solve::<N>(n, fk, bk),
                    PivotKind::Symmetric | PivotKind::Modified => eigen_solve(
                        n,
                        fk,
                        &self.lambda[k * n..(k + 1) * n],
                        bk,
                        &mut self.scratch,
                    ),
                }
            }
            return;
        }
        if self.kind == PivotKind::Cholesky {
            self.solve_cholesky::<N>(b);
            return;
        }
        // forward sweep and pivot solves
        let mut sigma = 0.0;
        for k in 0..nb {
            let wk = &self.w[k * n..(k + 1) * n];
            let zk = &mut b[k * n..(k + 1) * n];
            for i in 0..n {
                zk[i] += wk[i] * sigma;
            }
            let qk = &self.q[k * n..(k + 1) * n];
            sigma += dot(qk, zk);
            let fk = &self.f[k * nn..(k + 1) * nn];
            match self.kind {
                PivotKind::Cholesky => cholesky_solve::<N>(n, fk, zk),
                PivotKind::Symmetric | PivotKind::Modified => eigen_solve(
                    n,
                    fk,
                    &self.lambda[k * n..(k + 1) * n],
                    zk,
                    &mut self.scratch,
                ),
            }
        }
        // backward sweep
        let mut rho = 0.0;
        for m in (0..nb).rev() {
            let qm = &self.q[m * n..(m + 1) * n];
            let xm = &mut b[m * n..(m + 1) * n];
            for i in 0..n {
                xm[i] += qm[i] * rho;
            }
            rho += dot(&self.w[m * n..(m + 1) * n], xm);
        }
    }
}

impl Semiseparable {
    /// [`Semiseparable::solve`] of a coupled Cholesky factorisation: the
    /// sweeps of the module docs with `P_k^-1 = B'_k^-1 + c_k b_k b_k^T`, so
    /// that each block's solve is independent of the running sums.
    fn solve_cholesky<const N: usize>(&self, x: &mut [f64]) {
        let n = if N > 0 { N } else { self.n };
        let nn = n * n;
        // forward: z_k = b_k + sigma_k w_k, y_k = P_k^-1 z_k,
        // sigma_{k+1} = sigma_k + q_k^T z_k = sigma_k (1 + omega_k) + q_k^T b_k
        let mut sigma = 0.0;
        for k in 0..self.blocks {
            let xk = &mut x[k * n..(k + 1) * n];
            let (qk, bk) = (&self.q[k * n..(k + 1) * n], &self.bw[k * n..(k + 1) * n]);
            let [beta, c, omega] = self.sm[k];
            let (s1, s2) = (dot(bk, xk), dot(qk, xk));
            cholesky_solve::<N>(n, &self.f[k * nn..(k + 1) * nn], xk);
            let t = sigma + c * (s1 + sigma * beta);
            for (xi, bi) in xk.iter_mut().zip(bk) {
                *xi += t * bi;
            }
            sigma = sigma * (1.0 + omega) + s2;
        }
        // backward: x_m = y_m + rho_m q_m,
        // rho_{m-1} = rho_m + w_m^T x_m = rho_m (1 + omega_m) + w_m^T y_m
        let mut rho = 0.0;
        for m in (0..self.blocks).rev() {
            let xm = &mut x[m * n..(m + 1) * n];
            let (qm, wm) = (&self.q[m * n..(m + 1) * n], &self.w[m * n..(m + 1) * n]);
            let wy = dot(wm, xm);
            for (xi, qi) in xm.iter_mut().zip(qm) {
                *xi += rho * qi;
            }
            rho = rho * (1.0 + self.sm[m][2]) + wy;
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// In-place square-root-free Cholesky factorisation `A = L D L^T` of a
/// column-major symmetric `N x N` matrix (0: `n x n`; the callers pass the
/// common block sizes at compile time, which unrolls the loops), reading
/// the lower triangle: afterwards the strict lower triangle holds the unit
/// lower `L`, the diagonal `1 / D_jj` (the solves multiply by it), and the
/// strict upper triangle `D_kk L_jk` at `(k, j)` (the products the later
/// columns need). No square roots, and one division per column: the
/// column-to-column dependency that sets the time of such small
/// factorisations is half that of `L L^T` with `1 / sqrt`. `A` is
/// positive definite exactly when every `D_jj > 0`; the index of the first
/// that is not (or is not finite) on failure.
#[inline]
fn cholesky<const N: usize>(n: usize, a: &mut [f64]) -> Result<(), usize> {
    let n = if N > 0 { N } else { n };
    let a = &mut a[..n * n];
    for j in 0..n {
        let mut d = a[j + n * j];
        for k in 0..j {
            d -= a[j + n * k] * a[k + n * j];
        }
        if !(d > 0.0 && d.is_finite()) {
            return Err(j);
        }
        let r = 1.0 / d;
        a[j + n * j] = r;
        for i in j + 1..n {
            let mut v = a[i + n * j];
            for k in 0..j {
                v -= a[i + n * k] * a[k + n * j];
            }
            a[j + n * i] = v;
            a[i + n * j] = v * r;
        }
    }
    Ok(())
}

/// Solves `L D L^T x = b` in place with a factor from [`cholesky`] (`N` as
/// there).
#[inline]
fn cholesky_solve<const N: usize>(n: usize, l: &[f64], b: &mut [f64]) {
    let n = if N > 0 { N } else { n };
    let (l, b) = (&l[..n * n], &mut b[..n]);
    for i in 0..n {
        let mut v = b[i];
        for k in 0..i {
            v -= l[i + n * k] * b[k];
        }
        b[i] = v;
    }
    for i in 0..n {
        b[i] *= l[i + n * i];
    }
    for i in (0..n).rev() {
        let mut v = b[i];
        for k in i + 1..n {
            v -= l[k + n * i] * b[k];
        }
        b[i] = v;
    }
}

/// How far above its largest eigenvalue's `1e-14` (the symmetric pivots'
/// singularity threshold) a pivot's smallest must provably lie for
/// [`Semiseparable::inertia`] to count it positive definite without its
/// eigenvalues: the margin covers the rounding of both ways of deciding.
const CERTIFIED_RATIO: f64 = 1e-12;

/// True when the symmetric `p` (`n x n`) is positive definite with its
/// smallest eigenvalue above [`CERTIFIED_RATIO`] times its largest; then
/// `scratch[..n * n]` holds its [`cholesky`] factor. For a positive
/// definite matrix `lambda_max <= trace(P)` and `1 / lambda_min <=
/// trace(P^-1)`, and `trace(P^-1) = sum_j |L^-1 e_j|^2_(D^-1)` comes from
/// the factor. False proves nothing (the caller takes the eigenvalues).
fn certified_positive<const N: usize>(n: usize, p: &[f64], scratch: &mut [f64]) -> bool {
    let n = if N > 0 { N } else { n };
    let (c, rest) = scratch.split_at_mut(n * n);
    c.copy_from_slice(&p[..n * n]);
    if cholesky::<N>(n, c).is_err() {
        return false;
    }
    let trace: f64 = (0..n).map(|i| p[i + n * i]).sum();
    let y = &mut rest[..n];
    let mut trace_inv = 0.0;
    for j in 0..n {
        // y = L^-1 e_j (zero above j); D^-1 is on the factor's diagonal
        for i in j..n {
            let mut v = if i == j { 1.0 } else { 0.0 };
            for k in j..i {
                v -= c[i + n * k] * y[k];
            }
            y[i] = v;
            trace_inv += v * v * c[i + n * i];
        }
    }
    trace_inv.is_finite() && trace_inv * trace * CERTIFIED_RATIO < 1.0
}

/// Cyclic Jacobi eigendecomposition of a symmetric `n x n` matrix: on
/// return `a` holds the eigenvectors (columns) and `lam` the eigenvalues.
/// `None` if it does not converge or meets a non-finite entry.
fn jacobi(n: usize, a: &mut [f64], lam: &mut [f64], scratch: &mut [f64]) -> Option<()> {
    // the matrix is rotated in `s` (scratch); `a` accumulates the rotations
    let s = &mut scratch[..n * n];
    s.copy_from_slice(&a[..n * n]);
    for v in a.iter_mut() {
        *v = 0.0;
    }
    for i in 0..n {
        a[i + n * i] = 1.0;
    }
    if !s.iter().all(|v| v.is_finite()) {
        return None;
    }
    for _ in 0..MAX_SWEEPS {
        let off: f64 = (0..n)
            .flat_map(|j| (0..j).map(move |i| (i, j)))
            .map(|(i, j)| s[i + n * j] * s[i + n * j])
            .sum();
        let diag: f64 = (0..n).map(|i| s[i + n * i] * s[i + n * i]).sum();
        if off <= 1e-30 * diag.max(f64::MIN_POSITIVE) {
            for i in 0..n {
                lam[i] = s[i + n * i];
            }
            return Some(());
        }
        for p in 0..n {
            for q in p + 1..n {
                let apq = s[p + n * q];
                if apq == 0.0 {
                    continue;
                }
                let theta = (s[q + n * q] - s[p + n * p]) / (2.0 * apq);
                let t = theta.signum() / (theta.abs() + (theta * theta + 1.0).sqrt());
                let t = if theta == 0.0 { 1.0 } else { t };
                let c = 1.0 / (t * t + 1.0).sqrt();
                let sn = t * c;
                for k in 0..n {
                    let (skp, skq) = (s[k + n * p], s[k + n * q]);
                    s[k + n * p] = c * skp - sn * skq;
                    s[k + n * q] = sn * skp + c * skq;
                }
                for k in 0..n {
                    let (spk, sqk) = (s[p + n * k], s[q + n * k]);
                    s[p + n * k] = c * spk - sn * sqk;
                    s[q + n * k] = sn * spk + c * sqk;
                }
                for k in 0..n {
                    let (vkp, vkq) = (a[k + n * p], a[k + n * q]);
                    a[k + n * p] = c * vkp - sn * vkq;
                    a[k + n * q] = sn * vkp + c * vkq;
                }
            }
        }
    }
    None
}

/// `b <- V diag(1/lam) V^T b` for eigenvectors `v` (columns).
fn eigen_solve(n: usize, v: &[f64], lam: &[f64], b: &mut [f64], scratch: &mut [f64]) {
    let t = &mut scratch[..n];
    for j in 0..n {
        let mut s = 0.0;
        for i in 0..n {
            s += v[i + n * j] * b[i];
        }
        t[j] = s / lam[j];
    }
    for i in 0..n {
        let mut s = 0.0;
        for j in 0..n {
            s += v[i + n * j] * t[j];
        }
        b[i] = s;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A random structured matrix, its dense form, and a right-hand side.
    fn random(n: usize, nb: usize, seed: u64, shift: f64) -> (Semiseparable, Vec<f64>) {
        let mut rng = fastrand::Rng::with_seed(seed);
        let mut m = Semiseparable::new(n, nb);
        for k in 0..nb {
            let blk = m.block_mut(k);
            // a symmetric block with a diagonal shift (sign picks the definiteness)
            let mut a = vec![0.0; n * n];
            for c in 0..n {
                for r in 0..=c {
                    let v = rng.f64() - 0.5;
                    a[r + n * c] = v;
                    a[c + n * r] = v;
                }
                a[c + n * c] += shift;
            }
            blk.copy_from_slice(&a);
            let (u, w) = m.coupling_mut(k);
            for i in 0..n {
                u[i] = 0.3 * (rng.f64() - 0.5);
                w[i] = 0.3 * (rng.f64() - 0.5);
            }
        }
        let dim = n * nb;
        let mut h = vec![0.0; dim * dim];
        m.dense(&mut h);
        (m, h)
    }

    fn dense_solve(dim: usize, h: &[f64], b: &[f64]) -> Vec<f64> {
        // Gaussian elimination with partial pivoting, written here
        let mut a = h.to_vec();
        let mut x = b.to_vec();
        for c in 0..dim {
            let p = (c..dim)
                .max_by(|&i, &j| a[i + dim * c].abs().total_cmp(&a[j + dim * c].abs()))
                .unwrap();
            for k in 0..dim {
                a.swap(c + dim * k, p + dim * k);
            }
            x.swap(c, p);
            for r in c + 1..dim {
                let f = a[r + dim * c] / a[c + dim * c];
                for k in c..dim {
                    a[r + dim * k] -= f * a[c + dim * k];
                }
                x[r] -= f * x[c];
            }
        }
        for r in (0..dim).rev() {
            let mut v = x[r];
            for k in r + 1..dim {
                v -= a[r + dim * k] * x[k];
            }
            x[r] = v / a[r + dim * r];
        }
        x
    }

    #[test]
    fn structured_solves_match_a_dense_elimination() {
        for (n, nb, seed) in [(1, 1, 1), (4, 1, 2), (4, 3, 3), (5, 8, 4), (3, 40, 5)] {
            for (shift, kind) in [(4.0, PivotKind::Cholesky), (0.3, PivotKind::Symmetric)] {
                let (mut m, h) = random(n, nb, seed, shift);
                let dim = n * nb;
                let b: Vec<f64> = (0..dim).map(|i| (i as f64 * 0.7).sin()).collect();
                // apply against the dense product
                let mut hb = vec![0.0; dim];
                m.apply(&b, &mut hb);
                for i in 0..dim {
                    let d: f64 = (0..dim).map(|j| h[i + dim * j] * b[j]).sum();
                    assert!((d - hb[i]).abs() <= 1e-13 * (1.0 + d.abs()), "apply {i}");
                }
                let inertia = match m.factor(0.0, kind) {
                    Ok(i) => i,
                    Err(FactorError::NotPositiveDefinite { .. }) if kind == PivotKind::Cholesky => {
                        continue
                    }
                    Err(e) => panic!("{e:?}"),
                };
                assert_eq!(inertia.positive + inertia.negative, dim);
                let mut x = b.clone();
                m.solve(&mut x);
                let want = dense_solve(dim, &h, &b);
                let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                for i in 0..dim {
                    assert!((x[i] - want[i]).abs() <= 1e-10 * scale, "n {n} N {nb}: {i}");
                }
            }
        }
    }

    /// The Cholesky path decides definiteness from the blocks and the
    /// chain's scalars (module docs): it must say yes exactly when the
    /// whole matrix is positive definite, also when every block is
    /// positive definite and the coupling alone makes it indefinite, and
    /// then solve like a dense elimination.
    #[test]
    fn cholesky_succeeds_exactly_when_positive_definite() {
        let (mut checked, mut by_coupling) = (0, 0);
        for seed in 0..60u64 {
            let (n, nb) = [(2, 3), (4, 8), (5, 4), (3, 12)][seed as usize % 4];
            // definite blocks (shift 1.5 > the random part's reach for
            // small n), coupling from weak to dominant
            let (mut m, _) = random(n, nb, 100 + seed, 1.5 + 0.5 * n as f64);
            let grow = [1.0, 4.0, 8.0, 16.0][(seed / 4) as usize % 4];
            for k in 0..nb {
                let (u, w) = m.coupling_mut(k);
                u.iter_mut().for_each(|v| *v *= grow);
                w.iter_mut().for_each(|v| *v *= grow);
            }
            let dim = n * nb;
            let mut h = vec![0.0; dim * dim];
            m.dense(&mut h);
            let mut v = h.clone();
            let mut lam = vec![0.0; dim];
            let mut scratch = vec![0.0; dim * dim + 4 * dim];
            jacobi(dim, &mut v, &mut lam, &mut scratch).unwrap();
            let lo = lam.iter().fold(f64::INFINITY, |a, &l| a.min(l));
            let hi = lam.iter().fold(0.0f64, |a, &l| a.max(l.abs()));
            if lo.abs() <= 1e-9 * hi {
                continue; // too close to call
            }
            checked += 1;
            let blocks_definite = (0..nb).all(|k| {
                let mut b = m.b[k * n * n..(k + 1) * n * n].to_vec();
                cholesky::<0>(n, &mut b).is_ok()
            });
            assert!(
                blocks_definite,
                "seed {seed}: the blocks are meant to be definite"
            );
            match m.factor(0.0, PivotKind::Cholesky) {
                Ok(inertia) => {
                    assert!(lo > 0.0, "seed {seed}: accepted with eigenvalue {lo}");
                    assert_eq!(inertia.positive, dim);
                    let b: Vec<f64> = (0..dim).map(|i| (i as f64 * 0.3).cos()).collect();
                    let mut x = b.clone();
                    m.solve(&mut x);
                    let want = dense_solve(dim, &h, &b);
                    let scale = want.iter().fold(0.0f64, |a, v| a.max(v.abs()));
                    for i in 0..dim {
                        assert!((x[i] - want[i]).abs() <= 1e-10 * scale, "seed {seed}: {i}");
                    }
                }
                Err(FactorError::NotPositiveDefinite { index }) => {
                    assert!(lo < 0.0, "seed {seed}: refused with eigenvalue {lo}");
                    assert!(index < dim);
                    by_coupling += 1;
                }
                Err(e) => panic!("seed {seed}: {e:?}"),
            }
        }
        assert!(checked >= 40, "{checked}");
        assert!(
            by_coupling >= 5,
            "only {by_coupling} indefinite by the coupling"
        );
    }

    /// A symmetric `n x n` matrix with the given eigenvalues: `Q diag(lam)
    /// Q^T` with `Q` a product of `n` random Householder reflections.
    fn with_eigenvalues(lam: &[f64], rng: &mut fastrand::Rng) -> Vec<f64> {
        let n = lam.len();
        let mut q: Vec<f64> = (0..n * n)
            .map(|k| if k % (n + 1) == 0 { 1.0 } else { 0.0 })
            .collect();
        for _ in 0..n {
            let v: Vec<f64> = (0..n).map(|_| rng.f64() - 0.5).collect();
            let vv = dot(&v, &v);
            for c in 0..n {
                let col = &mut q[c * n..(c + 1) * n];
                let f = 2.0 * dot(&v, col) / vv;
                col.iter_mut().zip(&v).for_each(|(x, vi)| *x -= f * vi);
            }
        }
        let mut a = vec![0.0; n * n];
        for r in 0..n {
            for c in 0..n {
                a[r + n * c] = (0..n).map(|k| q[r + n * k] * lam[k] * q[c + n * k]).sum();
            }
        }
        a
    }

    /// The certificate is sound (it never passes a matrix whose known
    /// smallest eigenvalue is not above CERTIFIED_RATIO times its largest,
    /// nor an indefinite one) and useful (it passes every matrix of
    /// condition up to 1e8).
    #[test]
    fn certified_pivots_are_clearly_positive_definite() {
        let mut rng = fastrand::Rng::with_seed(7);
        let (mut passed, mut refused) = (0, 0);
        for trial in 0..600 {
            let n = [1, 2, 4, 5, 6, 9][trial % 6];
            // condition 10^0 .. 10^16, some indefinite
            let cond = 10f64.powf(16.0 * rng.f64());
            let scale = 10f64.powf(6.0 * rng.f64() - 3.0);
            let mut lam: Vec<f64> = (0..n).map(|_| scale * cond.powf(-rng.f64())).collect();
            lam[0] = scale;
            if n > 1 {
                lam[n - 1] = scale / cond;
            }
            let indefinite = trial % 5 == 0 && n > 1;
            if indefinite {
                lam[n - 1] = -lam[n - 1];
            }
            let p = with_eigenvalues(&lam, &mut rng);
            let mut scratch = vec![0.0; n * n + 4 * n];
            let ok = certified_positive::<0>(n, &p, &mut scratch);
            let ratio = lam.iter().fold(f64::INFINITY, |a, &l| a.min(l)) / scale;
            if ok {
                assert!(!indefinite, "trial {trial}: an indefinite matrix passed");
                // the construction's own rounding is about 1e-15 of the scale
                assert!(
                    ratio > CERTIFIED_RATIO - 1e-14,
                    "trial {trial}: ratio {ratio:e}"
                );
                passed += 1;
            } else {
                if !indefinite {
                    assert!(cond > 1e8, "trial {trial}: refused at condition {cond:e}");
                }
                refused += 1;
            }
        }
        assert!(
            passed > 100 && refused > 100,
            "{passed} passed, {refused} refused"
        );
    }

    /// `inertia` counts as the symmetric factorisation does, with the same
    /// errors, and as a dense eigenvalue count of the whole matrix: on
    /// random chains from definite to indefinite (by the blocks or by the
    /// coupling) and on a chain with a singular pivot.
    #[test]
    fn inertia_alone_matches_the_symmetric_factorisation() {
        let mut compared = [0usize; 2]; // [definite, indefinite]
        for seed in 0..80u64 {
            let (n, nb) = [(4, 6), (5, 8), (6, 3), (3, 12)][seed as usize % 4];
            let shift = [-0.5, 0.2, 0.6, 1.5, 4.0][(seed / 4) as usize % 5];
            let (mut m, h) = random(n, nb, 300 + seed, shift);
            let want = m.factor(0.0, PivotKind::Symmetric);
            let got = m.inertia(0.0);
            assert_eq!(got, want, "seed {seed}");
            let Ok(inertia) = got else { continue };
            let dim = n * nb;
            let (mut v, mut lam) = (h.clone(), vec![0.0; dim]);
            let mut scratch = vec![0.0; dim * dim + 4 * dim];
            jacobi(dim, &mut v, &mut lam, &mut scratch).unwrap();
            let hi = lam.iter().fold(0.0f64, |a, &l| a.max(l.abs()));
            if lam.iter().any(|l| l.abs() <= 1e-9 * hi) {
                continue; // too close to call
            }
            let neg = lam.iter().filter(|&&l| l < 0.0).count();
            assert_eq!(
                (inertia.negative, inertia.positive),
                (neg, dim - neg),
                "seed {seed}"
            );
            compared[usize::from(neg > 0)] += 1;
        }
        assert!(compared[0] >= 10 && compared[1] >= 10, "{compared:?}");
        // a rank-one pivot: singular both ways
        let (mut m, _) = random(4, 3, 5, 2.0);
        let blk = m.block_mut(1);
        for c in 0..4 {
            for r in 0..4 {
                blk[r + 4 * c] = (r + 1) as f64 * (c + 1) as f64;
            }
        }
        let want = m.factor(0.0, PivotKind::Symmetric);
        assert!(
            matches!(want, Err(FactorError::Singular { block: 1 })),
            "{want:?}"
        );
        assert_eq!(m.inertia(0.0), want);
    }

    #[test]
    fn inertia_counts_negative_eigenvalues() {
        // a block diagonal with known signs, then a coupled one against the
        // count from a dense symmetric eigen solve by Jacobi on the whole
        let (mut m, h) = random(3, 5, 9, 0.1);
        let dim = 15;
        let mut v = h.clone();
        let mut lam = vec![0.0; dim];
        let mut scratch = vec![0.0; dim * dim + 4 * dim];
        jacobi(dim, &mut v, &mut lam, &mut scratch).unwrap();
        let neg = lam.iter().filter(|&&l| l < 0.0).count();
        let inertia = m.factor(0.0, PivotKind::Symmetric).unwrap();
        assert_eq!(inertia.negative, neg, "{lam:?}");
        // positive definite exactly when Cholesky succeeds
        let ok = m.factor(0.0, PivotKind::Cholesky).is_ok();
        assert_eq!(ok, neg == 0);
        let shift = 1.0 - lam.iter().fold(f64::INFINITY, |a, &l| a.min(l));
        assert!(m.factor(shift, PivotKind::Cholesky).is_ok());
    }
}

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

use crate::linear::{dot, FactorError, Inertia};

mod lanes;
mod pivot;

use lanes::Store;
use pivot::{certified_positive, cholesky, cholesky_solve, eigen_solve, jacobi};

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

/// Blocks per group of the lane-major storage ([`Semiseparable::set_group`]).
pub const GROUP: usize = lanes::LANES;

/// Relative floor on the modified pivots' eigenvalues
/// ([`PivotKind::Modified`]).
pub const MODIFIED_FLOOR: f64 = 1e-6;

/// A block-diagonal plus rank-one semiseparable symmetric matrix (module
/// docs) with its factorisation.
///
/// The blocks are stored lane-major, eight blocks to a group (see
/// [`Semiseparable::set_block`]), so that blocks of size 4 (the CCM's)
/// factorise and solve eight at a time in vector registers; other sizes
/// and the symmetric pivots go block by block.
#[derive(Debug, Clone)]
pub struct Semiseparable {
    n: usize,
    blocks: usize,
    /// `B_k`, column-major `n x n` each (the full symmetric block).
    b: Store,
    u: Store,
    w: Store,
    // factorisation
    kind: PivotKind,
    /// `L D L^T` factor of `B_k + tau I` (see [`cholesky`]) or the
    /// eigenvectors of the pivot `P_k`, per block.
    f: Store,
    /// Cholesky pivots: `(B_k + tau I)^-1 w_k` per block.
    bw: Store,
    /// Cholesky pivots: `[beta_k, c_k, omega_k]` per block (module docs).
    sm: Store,
    /// Eigenvalues per block (symmetric pivots).
    lambda: Store,
    q: Store,
    factored: bool,
    /// False while every coupling vector is zero (block diagonal: the
    /// recurrences are skipped).
    coupled: bool,
    /// One block's worth of contiguous workspace for the block-by-block
    /// paths.
    scratch: Vec<f64>,
    /// The lane solve's workspace: six lanes per group, used as one flat
    /// run of lanes (a `Store` for its cache-line alignment).
    lane_work: Store,
}

impl Semiseparable {
    /// `blocks` blocks of size `n`, all zero (nothing allocated for no
    /// blocks).
    pub fn new(n: usize, blocks: usize) -> Semiseparable {
        let nn = n * n;
        let scratch = if blocks > 0 { 2 * nn + 10 * n } else { 0 };
        let in_lanes = Self::runs_in_lanes(n, blocks);
        let mut b = Store::new(nn, blocks);
        // the lanes past the last block hold the identity, which the lane
        // factorisation passes through harmlessly
        if in_lanes {
            for k in blocks..blocks.next_multiple_of(lanes::LANES) {
                for i in 0..n {
                    *b.at_mut(k, i * (n + 1)) = 1.0;
                }
            }
        }
        Semiseparable {
            n,
            blocks,
            b,
            u: Store::new(n, blocks),
            w: Store::new(n, blocks),
            kind: PivotKind::Cholesky,
            f: Store::new(nn, blocks),
            bw: Store::new(n, blocks),
            sm: Store::new(3, blocks),
            lambda: Store::new(n, blocks),
            q: Store::new(n, blocks),
            factored: false,
            coupled: false,
            scratch: vec![0.0; scratch],
            lane_work: Store::new(6, if in_lanes { blocks } else { 0 }),
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

    /// Sets block `k`'s `B_k` from `b` (column-major `n x n`, full);
    /// invalidates the factorisation.
    #[inline]
    pub fn set_block(&mut self, k: usize, b: &[f64]) {
        assert!(k < self.blocks, "block {k} of {}", self.blocks);
        self.factored = false;
        self.b.scatter(k, b);
    }

    /// Sets block `k`'s `B_k` to what `fill` writes into a workspace of
    /// `n x n` entries (column-major, full; every entry is to be written,
    /// the workspace holds leftovers), so that a caller assembling a
    /// block needs no buffer of its own; invalidates the factorisation.
    #[inline]
    pub fn fill_block(&mut self, k: usize, fill: impl FnOnce(&mut [f64])) {
        assert!(k < self.blocks, "block {k} of {}", self.blocks);
        self.factored = false;
        let block = &mut self.scratch[..self.n * self.n];
        fill(block);
        self.b.scatter(k, block);
    }

    /// Sets the blocks of group `g`, blocks `GROUP g` to `GROUP g +
    /// GROUP - 1`, from entries that hold one number per block (lane `l`
    /// of an entry is block `GROUP g + l`'s, as the matrix stores them):
    /// `block` their `n x n` entries (column-major, full) and, unless
    /// `None`, `coupling` their vectors `u` and `w` (`n` entries each). The
    /// lanes past the last block are not read. So an assembly that
    /// computes several blocks at once stores them with no transposition.
    /// Invalidates the factorisation.
    #[inline(always)]
    pub fn set_group<T: AsRef<[f64; GROUP]>>(
        &mut self,
        g: usize,
        block: &[T],
        coupling: Option<(&[T], &[T])>,
    ) {
        assert!(
            g * GROUP < self.blocks,
            "group {g} of {} blocks",
            self.blocks
        );
        let (n, count) = (self.n, GROUP.min(self.blocks - g * GROUP));
        assert!(
            block.len() == n * n,
            "a group's blocks need {} entries",
            n * n
        );
        self.factored = false;
        put(self.b.group_mut(g), block, count);
        if let Some((u, w)) = coupling {
            assert!(
                u.len() == n && w.len() == n,
                "coupling vectors of {n} entries"
            );
            self.coupled = true;
            put(self.u.group_mut(g), u, count);
            put(self.w.group_mut(g), w, count);
        }
    }

    /// Block `k`'s `B_k` into `out` (column-major `n x n`).
    pub fn block(&self, k: usize, out: &mut [f64]) {
        assert!(k < self.blocks, "block {k} of {}", self.blocks);
        self.b.gather(k, out);
    }

    /// Sets block `k`'s coupling vectors `(u_k, w_k)`; invalidates the
    /// factorisation.
    #[inline]
    pub fn set_coupling(&mut self, k: usize, u: &[f64], w: &[f64]) {
        assert!(k < self.blocks, "block {k} of {}", self.blocks);
        self.factored = false;
        self.coupled = true;
        self.u.scatter(k, u);
        self.w.scatter(k, w);
    }

    /// Block `k`'s coupling vectors into `(u, w)`.
    pub fn coupling(&self, k: usize, u: &mut [f64], w: &mut [f64]) {
        assert!(k < self.blocks, "block {k} of {}", self.blocks);
        self.u.gather(k, u);
        self.w.gather(k, w);
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
                let d = self.b.at(k, i * (n + 1));
                lo = lo.min(d);
                hi = hi.max(d.abs());
            }
        }
        (lo, hi)
    }

    /// `out = H x` in linear time.
    pub fn apply(&self, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        let nb = self.blocks;
        let row = |k: usize, i: usize, start: f64| {
            (0..n).fold(start, |v, j| v + self.b.at(k, i + n * j) * x[k * n + j])
        };
        let dot = |v: &Store, k: usize| (0..n).fold(-0.0, |s, i| s + v.at(k, i) * x[k * n + i]);
        if !self.coupled {
            for k in 0..nb {
                for i in 0..n {
                    out[k * n + i] = row(k, i, -0.0);
                }
            }
            return;
        }
        // sum_{j<k} u_j^T x_j, running forward
        let mut s = 0.0;
        for k in 0..nb {
            for i in 0..n {
                out[k * n + i] = row(k, i, 0.0) - self.w.at(k, i) * s;
            }
            s += dot(&self.u, k);
        }
        // sum_{j>k} w_j^T x_j, running backward
        let mut t = 0.0;
        for k in (0..nb).rev() {
            for i in 0..n {
                out[k * n + i] -= self.u.at(k, i) * t;
            }
            t += dot(&self.w, k);
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
                    h[(k * n + r) + dim * (k * n + c)] = self.b.at(k, r + n * c);
                }
            }
            for j in 0..k {
                for c in 0..n {
                    for r in 0..n {
                        let v = -self.w.at(k, r) * self.u.at(j, c);
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
        (0..self.blocks).find(|&m| {
            !(self.b.block_finite(m) && self.u.block_finite(m) && self.w.block_finite(m))
        })
    }

    /// Whether a Cholesky factorisation runs eight blocks at a time
    /// (`lanes`): for blocks of size 4, and more than one of them. A single
    /// block (the decoupled element solves) goes block by block, where the
    /// lane pass would carry seven padding lanes and cost about twice as
    /// much (docs/performance.md, "Lane-major storage of the blocks").
    fn in_lanes(&self) -> bool {
        Self::runs_in_lanes(self.n, self.blocks)
    }

    /// [`Semiseparable::in_lanes`] of a matrix of `blocks` blocks of size
    /// `n`.
    fn runs_in_lanes(n: usize, blocks: usize) -> bool {
        n == 4 && blocks > 1
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
            if self.in_lanes() {
                self.factor_cholesky4(tau)?;
            } else {
                self.factor_cholesky::<N>(tau)?;
            }
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
        let coupled = self.coupled;
        let mut inertia = Inertia::default();
        if self.blocks == 0 {
            return Ok(inertia); // (no workspace either)
        }
        let (p, rest) = self.scratch.split_at_mut(n * n);
        let (lam, rest) = rest.split_at_mut(n);
        let (um, rest) = rest.split_at_mut(n);
        let (wm, rest) = rest.split_at_mut(n);
        let (qm, rest) = rest.split_at_mut(n);
        let (s, work) = rest.split_at_mut(n);
        let mut gamma = 0.0;
        for m in 0..self.blocks {
            self.b.gather(m, p);
            self.u.gather(m, um);
            self.w.gather(m, wm);
            for c in 0..n {
                for r in 0..n {
                    p[r + n * c] -= gamma * wm[r] * wm[c];
                }
                p[c + n * c] += tau;
            }
            if coupled {
                for i in 0..n {
                    qm[i] = um[i] + gamma * wm[i];
                }
            }
            // a certified pivot leaves its Cholesky factor at the front of
            // the workspace; any other is counted from its eigenvalues
            let certified = count_only && certified_positive::<N>(n, p, work);
            if certified {
                inertia.positive += n;
            } else {
                jacobi(n, p, lam, work).ok_or(FactorError::NoConvergence { block: m })?;
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
                self.f.scatter(m, p);
                self.lambda.scatter(m, lam);
            }
            if coupled {
                s.copy_from_slice(qm);
                if certified {
                    cholesky_solve::<N>(n, &work[..n * n], qm);
                } else {
                    eigen_solve(n, p, lam, qm, work);
                }
                gamma += dot(s, qm);
                self.q.scatter(m, qm);
            }
            if !gamma.is_finite() {
                return Err(FactorError::NonFinite { block: m });
            }
        }
        Ok(inertia)
    }

    /// The Cholesky factorisation of `H + tau I` in the reordered form of
    /// the module docs, block by block: block `m` fails with the index of
    /// its first non-positive pivot when `B'_m` is not positive definite,
    /// and with its last row when the chain's update makes `P_m` indefinite
    /// (`d_m <= 0`).
    fn factor_cholesky<const N: usize>(&mut self, tau: f64) -> Result<(), FactorError> {
        let n = if N > 0 { N } else { self.n };
        let coupled = self.coupled;
        if self.blocks == 0 {
            return Ok(()); // (no workspace either)
        }
        let (f, rest) = self.scratch.split_at_mut(n * n);
        let (um, rest) = rest.split_at_mut(n);
        let (wm, rest) = rest.split_at_mut(n);
        let (a, rest) = rest.split_at_mut(n);
        let b = &mut rest[..n];
        let mut gamma = 0.0;
        for m in 0..self.blocks {
            self.b.gather(m, f);
            for c in 0..n {
                f[c + n * c] += tau;
            }
            cholesky::<N>(n, f).map_err(|index| FactorError::NotPositiveDefinite {
                index: m * n + index,
            })?;
            self.f.scatter(m, f);
            if !coupled {
                continue;
            }
            self.u.gather(m, um);
            self.w.gather(m, wm);
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
            self.q.scatter(m, a);
            self.bw.scatter(m, b);
            self.sm.scatter(m, &[beta, c, alpha + kappa * beta]);
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

    /// `x <- P_k^-1 x` with block `k`'s factorised pivot (`N` as in
    /// [`Semiseparable::solve_sized`]).
    fn solve_pivot<const N: usize>(&mut self, k: usize, x: &mut [f64]) {
        let n = if N > 0 { N } else { self.n };
        let (fk, rest) = self.scratch.split_at_mut(n * n);
        let (lam, work) = rest.split_at_mut(n);
        self.f.gather(k, fk);
        match self.kind {
            PivotKind::Cholesky => cholesky_solve::<N>(n, fk, x),
            PivotKind::Symmetric | PivotKind::Modified => {
                self.lambda.gather(k, lam);
                eigen_solve(n, fk, lam, x, work)
            }
        }
    }

    /// [`Semiseparable::solve`] for blocks of size `N` (0: `self.n`).
    fn solve_sized<const N: usize>(&mut self, b: &mut [f64]) {
        let n = if N > 0 { N } else { self.n };
        let nb = self.blocks;
        if self.kind == PivotKind::Cholesky && self.in_lanes() {
            self.solve_cholesky4(b);
            return;
        }
        if !self.coupled {
            for k in 0..nb {
                self.solve_pivot::<N>(k, &mut b[k * n..(k + 1) * n]);
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
            let zk = &mut b[k * n..(k + 1) * n];
            let mut qz = -0.0;
            for (i, zi) in zk.iter_mut().enumerate() {
                *zi += self.w.at(k, i) * sigma;
            }
            for (i, zi) in zk.iter().enumerate() {
                qz += self.q.at(k, i) * zi;
            }
            sigma += qz;
            self.solve_pivot::<N>(k, zk);
        }
        // backward sweep
        let mut rho = 0.0;
        for m in (0..nb).rev() {
            let xm = &mut b[m * n..(m + 1) * n];
            let mut wx = -0.0;
            for (i, xi) in xm.iter_mut().enumerate() {
                *xi += self.q.at(m, i) * rho;
                wx += self.w.at(m, i) * *xi;
            }
            rho += wx;
        }
    }

    /// [`Semiseparable::solve`] of a coupled Cholesky factorisation, block
    /// by block: the sweeps of the module docs with `P_k^-1 = B'_k^-1 + c_k
    /// b_k b_k^T`, so that each block's solve is independent of the running
    /// sums.
    fn solve_cholesky<const N: usize>(&mut self, x: &mut [f64]) {
        let n = if N > 0 { N } else { self.n };
        if self.blocks == 0 {
            return; // (no workspace either)
        }
        let (fk, rest) = self.scratch.split_at_mut(n * n);
        let (qk, rest) = rest.split_at_mut(n);
        let bk = &mut rest[..n];
        // forward: z_k = b_k + sigma_k w_k, y_k = P_k^-1 z_k,
        // sigma_{k+1} = sigma_k + q_k^T z_k = sigma_k (1 + omega_k) + q_k^T b_k
        let mut sigma = 0.0;
        for k in 0..self.blocks {
            let xk = &mut x[k * n..(k + 1) * n];
            self.f.gather(k, fk);
            self.q.gather(k, qk);
            self.bw.gather(k, bk);
            let (beta, c, omega) = (self.sm.at(k, 0), self.sm.at(k, 1), self.sm.at(k, 2));
            let (s1, s2) = (dot(bk, xk), dot(qk, xk));
            cholesky_solve::<N>(n, fk, xk);
            let t = sigma + c * (s1 + sigma * beta);
            for (xi, bi) in xk.iter_mut().zip(bk.iter()) {
                *xi += t * bi;
            }
            sigma = sigma * (1.0 + omega) + s2;
        }
        self.backward_sweep(x);
    }

    /// The coupled Cholesky solve's backward sweep: `x_m = y_m + rho_m
    /// q_m`, `rho_{m-1} = rho_m + w_m^T x_m = rho_m (1 + omega_m) + w_m^T
    /// y_m`.
    fn backward_sweep(&self, x: &mut [f64]) {
        let n = self.n;
        let mut rho = 0.0;
        for m in (0..self.blocks).rev() {
            let xm = &mut x[m * n..(m + 1) * n];
            // summed in the order of `linear::dot`
            let mut wy = -0.0;
            for (i, xi) in xm.iter().enumerate() {
                wy += self.w.at(m, i) * xi;
            }
            for (i, xi) in xm.iter_mut().enumerate() {
                *xi += rho * self.q.at(m, i);
            }
            rho = rho * (1.0 + self.sm.at(m, 2)) + wy;
        }
    }
}

/// The first `count` lanes of every entry of `src` into `dst`.
#[inline(always)]
fn put<T: AsRef<[f64; GROUP]>>(dst: &mut [lanes::Lane], src: &[T], count: usize) {
    for (d, s) in dst.iter_mut().zip(src) {
        if count == GROUP {
            *d = *s.as_ref();
        } else {
            d[..count].copy_from_slice(&s.as_ref()[..count]);
        }
    }
}

#[cfg(test)]
mod tests;

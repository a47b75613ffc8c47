//! Lane-major storage of the blocks, and the Cholesky pivots of 4 x 4
//! blocks eight at a time.
//!
//! Every per-block quantity (a block, a coupling vector, a factor) is kept
//! in groups of [`LANES`] blocks, entry by entry: entry `e` of block `k`
//! is lane `k % LANES` of the group's `e`-th `[f64; LANES]`. A vector
//! instruction then reads one entry of eight blocks at once, with nothing
//! to transpose, and the blocks' independent Cholesky factorisations
//! (module docs of `semiseparable`) run one block per lane.
//!
//! The 4 x 4 kernels below are [`cholesky`](super::pivot::cholesky) and
//! [`cholesky_solve`](super::pivot::cholesky_solve) written out, statement
//! for statement in the same order, lane by lane: each lane's numbers are
//! bit for bit the scalar kernels' (nothing is fused or reordered; the
//! dot products sum in the order of `linear::dot`). The compiler turns
//! the lane operations into vector instructions for the instruction set
//! chosen at run time (AVX-512, AVX2, or the baseline).

use super::Semiseparable;
use crate::linear::FactorError;

/// Blocks per group.
pub(super) const LANES: usize = 8;

/// One number per block of a group.
pub(super) type Lane = [f64; LANES];

/// A [`Lane`] on a 64-byte boundary, so that a vector load of it never
/// straddles two cache lines (the heap aligns to 16 bytes only).
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
struct Aligned(Lane);

// (the slices of `Store::group` rely on it: no padding after the lane)
const _: () = assert!(std::mem::size_of::<Aligned>() == std::mem::size_of::<Lane>());

/// Per-block quantities of `per` entries each, lane-major (module docs).
#[derive(Debug, Clone)]
pub(super) struct Store {
    per: usize,
    data: Vec<Aligned>,
}

impl Store {
    /// `per` entries for each of `blocks` blocks, all zero (nothing
    /// allocated for no blocks).
    pub(super) fn new(per: usize, blocks: usize) -> Store {
        Store {
            per,
            data: vec![Aligned([0.0; LANES]); per * blocks.div_ceil(LANES)],
        }
    }

    #[inline(always)]
    fn slot(&self, k: usize, e: usize) -> (usize, usize) {
        debug_assert!(e < self.per);
        ((k / LANES) * self.per + e, k % LANES)
    }

    /// Entry `e` of block `k`.
    #[inline(always)]
    pub(super) fn at(&self, k: usize, e: usize) -> f64 {
        let (i, l) = self.slot(k, e);
        self.data[i].0[l]
    }

    /// Entry `e` of block `k`, to write.
    #[inline(always)]
    pub(super) fn at_mut(&mut self, k: usize, e: usize) -> &mut f64 {
        let (i, l) = self.slot(k, e);
        &mut self.data[i].0[l]
    }

    /// Block `k`'s entries into `out[..per]`.
    #[inline]
    pub(super) fn gather(&self, k: usize, out: &mut [f64]) {
        let l = k % LANES;
        for (o, lane) in out[..self.per].iter_mut().zip(self.group(k / LANES)) {
            *o = lane[l];
        }
    }

    /// `src[..per]` into block `k`'s entries.
    #[inline]
    pub(super) fn scatter(&mut self, k: usize, src: &[f64]) {
        let (l, per) = (k % LANES, self.per);
        for (lane, &v) in self.group_mut(k / LANES).iter_mut().zip(&src[..per]) {
            lane[l] = v;
        }
    }

    /// Group `g`'s entries.
    #[inline(always)]
    pub(super) fn group(&self, g: usize) -> &[Lane] {
        &self.all()[g * self.per..(g + 1) * self.per]
    }

    /// Every group's entries, group after group.
    #[inline(always)]
    fn all(&self) -> &[Lane] {
        // SAFETY: `Aligned` is `repr(C)` around one `Lane` and as large
        // as it (64 bytes, a multiple of its alignment: no padding)
        unsafe { std::slice::from_raw_parts(self.data.as_ptr().cast::<Lane>(), self.data.len()) }
    }

    /// Every group's entries, group after group, to write.
    #[inline(always)]
    pub(super) fn all_mut(&mut self) -> &mut [Lane] {
        let (ptr, len) = (self.data.as_mut_ptr(), self.data.len());
        // SAFETY: as in `all`
        unsafe { std::slice::from_raw_parts_mut(ptr.cast::<Lane>(), len) }
    }

    /// Group `g`'s entries, to write.
    #[inline(always)]
    pub(super) fn group_mut(&mut self, g: usize) -> &mut [Lane] {
        let per = self.per;
        &mut self.all_mut()[g * per..(g + 1) * per]
    }

    pub(super) fn fill(&mut self, v: f64) {
        self.data.fill(Aligned([v; LANES]));
    }

    /// Every entry of block `k` is finite.
    pub(super) fn block_finite(&self, k: usize) -> bool {
        (0..self.per).all(|e| self.at(k, e).is_finite())
    }

    #[cfg(test)]
    pub(super) fn capacity(&self) -> usize {
        self.data.capacity()
    }
}

/// `a - b c`, lane by lane.
#[inline(always)]
fn msub(a: Lane, b: Lane, c: Lane) -> Lane {
    let mut o = a;
    for l in 0..LANES {
        o[l] = a[l] - b[l] * c[l];
    }
    o
}

#[inline(always)]
fn add(a: Lane, b: Lane) -> Lane {
    let mut o = a;
    for l in 0..LANES {
        o[l] = a[l] + b[l];
    }
    o
}

#[inline(always)]
fn mul(a: Lane, b: Lane) -> Lane {
    let mut o = a;
    for l in 0..LANES {
        o[l] = a[l] * b[l];
    }
    o
}

/// `1 / d`; `d` is kept in `pivots[j]` for [`first_failure`].
#[inline(always)]
fn pivot(d: Lane, j: usize, pivots: &mut [Lane; 4]) -> Lane {
    pivots[j] = d;
    let mut r = d;
    for l in 0..LANES {
        r[l] = 1.0 / d[l];
    }
    r
}

/// The first lane among the first `count` whose pivots are not all
/// positive and finite, with its first failing column.
#[inline(always)]
fn first_failure(pivots: &[Lane; 4], count: usize) -> Option<(usize, usize)> {
    // branch-free over the lanes (NaN fails both comparisons)
    let mut bad = false;
    for d in pivots {
        for &x in &d[..count] {
            bad |= !(x > 0.0 && x <= f64::MAX);
        }
    }
    if !bad {
        return None;
    }
    (0..count).find_map(|l| {
        (0..4)
            .find(|&j| !(pivots[j][l] > 0.0 && pivots[j][l].is_finite()))
            .map(|j| (l, j))
    })
}

/// [`cholesky`](super::pivot::cholesky) of every lane's 4 x 4 block in
/// place (`a[c][r]` is entry `(r, c)`; the lower triangle is read): the
/// diagonal becomes `1 / D_jj`, the strict lower triangle `L`, the strict
/// upper `D_jj L_ij` at `(j, i)`; `pivots` the `D_jj`.
#[inline(always)]
fn cholesky4(a: &mut [[Lane; 4]; 4], pivots: &mut [Lane; 4]) {
    // column 0
    let r0 = pivot(a[0][0], 0, pivots);
    let (v1, v2, v3) = (a[0][1], a[0][2], a[0][3]);
    (a[1][0], a[2][0], a[3][0]) = (v1, v2, v3);
    (a[0][1], a[0][2], a[0][3]) = (mul(v1, r0), mul(v2, r0), mul(v3, r0));
    a[0][0] = r0;
    // column 1
    let d = msub(a[1][1], a[0][1], a[1][0]);
    let r1 = pivot(d, 1, pivots);
    let v2 = msub(a[1][2], a[0][2], a[1][0]);
    let v3 = msub(a[1][3], a[0][3], a[1][0]);
    (a[2][1], a[3][1]) = (v2, v3);
    (a[1][2], a[1][3]) = (mul(v2, r1), mul(v3, r1));
    a[1][1] = r1;
    // column 2
    let d = msub(msub(a[2][2], a[0][2], a[2][0]), a[1][2], a[2][1]);
    let r2 = pivot(d, 2, pivots);
    let v3 = msub(msub(a[2][3], a[0][3], a[2][0]), a[1][3], a[2][1]);
    a[3][2] = v3;
    a[2][3] = mul(v3, r2);
    a[2][2] = r2;
    // column 3
    let d = msub(
        msub(msub(a[3][3], a[0][3], a[3][0]), a[1][3], a[3][1]),
        a[2][3],
        a[3][2],
    );
    a[3][3] = pivot(d, 3, pivots);
}

/// [`cholesky_solve`](super::pivot::cholesky_solve) of every lane.
#[inline(always)]
fn solve4(a: &[[Lane; 4]; 4], b: [Lane; 4]) -> [Lane; 4] {
    let y0 = b[0];
    let y1 = msub(b[1], a[0][1], y0);
    let y2 = msub(msub(b[2], a[0][2], y0), a[1][2], y1);
    let y3 = msub(msub(msub(b[3], a[0][3], y0), a[1][3], y1), a[2][3], y2);
    let (y0, y1, y2, y3) = (
        mul(y0, a[0][0]),
        mul(y1, a[1][1]),
        mul(y2, a[2][2]),
        mul(y3, a[3][3]),
    );
    let x3 = y3;
    let x2 = msub(y2, a[2][3], x3);
    let x1 = msub(msub(y1, a[1][2], x2), a[1][3], x3);
    let x0 = msub(msub(msub(y0, a[0][1], x1), a[0][2], x2), a[0][3], x3);
    [x0, x1, x2, x3]
}

/// `x_i += s v_i` for a group's four-entry vectors, lane by lane.
#[inline(always)]
fn add_scaled(x: &mut [Lane], s: Lane, v: &[Lane]) {
    for (xi, &vi) in x[..4].iter_mut().zip(&v[..4]) {
        *xi = add(*xi, mul(s, vi));
    }
}

/// Every lane's dot product, summed in the order of `linear::dot`.
#[inline(always)]
fn dot4(x: &[Lane; 4], y: &[Lane; 4]) -> Lane {
    let mut s = [-0.0; LANES];
    for i in 0..4 {
        for l in 0..LANES {
            s[l] += x[i][l] * y[i][l];
        }
    }
    s
}

/// A group's factor as the kernels take it (`a[c][r]`, entry `(r, c)`).
#[inline(always)]
fn factor_of(f: &[Lane]) -> [[Lane; 4]; 4] {
    std::array::from_fn(|c| std::array::from_fn(|r| f[r + 4 * c]))
}

/// A group's four-entry vectors.
#[inline(always)]
fn vector_of(v: &[Lane]) -> [Lane; 4] {
    std::array::from_fn(|i| v[i])
}

/// Runs `$body` (an expression over `self`) compiled for the widest
/// vector instructions the processor has: the lane code is inlined into a
/// function per instruction set, chosen at run time.
macro_rules! widest {
    ($self:ident, $avx512:ident, $avx2:ident, $inner:ident ( $($arg:expr),* )) => {{
        #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
        {
            if std::arch::is_x86_feature_detected!("avx512f") {
                // SAFETY: the processor has AVX-512F (checked above)
                return unsafe { $self.$avx512($($arg),*) };
            }
            if std::arch::is_x86_feature_detected!("avx2") {
                // SAFETY: the processor has AVX2 (checked above)
                return unsafe { $self.$avx2($($arg),*) };
            }
        }
        $self.$inner($($arg),*)
    }};
}

impl Semiseparable {
    /// The Cholesky factorisation of `H + tau I` for blocks of size 4,
    /// eight blocks per vector: every block's pivots first, then the
    /// chain's scalars. Values and errors are those of the block-by-block
    /// factorisation, bit for bit (an error names the block the
    /// block-by-block order meets first).
    pub(super) fn factor_cholesky4(&mut self, tau: f64) -> Result<(), FactorError> {
        widest!(
            self,
            factor_cholesky4_avx512,
            factor_cholesky4_avx2,
            factor_cholesky4_in(tau)
        )
    }

    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    #[target_feature(enable = "avx512f,avx2")]
    fn factor_cholesky4_avx512(&mut self, tau: f64) -> Result<(), FactorError> {
        self.factor_cholesky4_in(tau)
    }

    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    #[target_feature(enable = "avx2")]
    fn factor_cholesky4_avx2(&mut self, tau: f64) -> Result<(), FactorError> {
        self.factor_cholesky4_in(tau)
    }

    #[inline(always)]
    fn factor_cholesky4_in(&mut self, tau: f64) -> Result<(), FactorError> {
        let coupled = self.coupled;
        // the blocks: factor, and (coupled) a = B'^-1 u, b = B'^-1 w with
        // the dot products [w.b, u.b, u.a] in `sm` for the chain
        let mut failed = None;
        for g in 0..self.blocks.div_ceil(LANES) {
            let count = LANES.min(self.blocks - g * LANES);
            let bg = self.b.group(g);
            let mut a = factor_of(bg);
            for (c, column) in a.iter_mut().enumerate() {
                for entry in column[c].iter_mut() {
                    *entry += tau;
                }
            }
            let mut pivots = [[0.0; LANES]; 4];
            cholesky4(&mut a, &mut pivots);
            let fg = self.f.group_mut(g);
            for c in 0..4 {
                for r in 0..4 {
                    fg[r + 4 * c] = a[c][r];
                }
            }
            if coupled {
                let (u, w) = (vector_of(self.u.group(g)), vector_of(self.w.group(g)));
                let (av, bv) = (solve4(&a, u), solve4(&a, w));
                self.q.group_mut(g).copy_from_slice(&av);
                self.bw.group_mut(g).copy_from_slice(&bv);
                let sm = self.sm.group_mut(g);
                sm[0] = dot4(&w, &bv);
                sm[1] = dot4(&u, &bv);
                sm[2] = dot4(&u, &av);
            }
            if let Some((l, j)) = first_failure(&pivots, count) {
                failed = Some((g * LANES + l, j));
                break;
            }
        }
        // the chain, up to the first block whose own pivots failed
        let end = failed.map_or(self.blocks, |(m, _)| m);
        if coupled {
            let mut gamma = 0.0;
            for m in 0..end {
                let (beta, alpha, uu) = (self.sm.at(m, 0), self.sm.at(m, 1), self.sm.at(m, 2));
                let d = 1.0 - gamma * beta;
                // (a NaN fails too)
                if d.is_nan() || d <= 0.0 {
                    return Err(FactorError::NotPositiveDefinite { index: m * 4 + 3 });
                }
                let c = gamma / d;
                let kappa = gamma + c * (alpha + gamma * beta);
                for i in 0..4 {
                    let bi = self.bw.at(m, i);
                    *self.q.at_mut(m, i) += kappa * bi;
                }
                *self.sm.at_mut(m, 1) = c;
                *self.sm.at_mut(m, 2) = alpha + kappa * beta;
                gamma += uu + (kappa + gamma) * alpha + gamma * kappa * beta;
                if !gamma.is_finite() {
                    return Err(FactorError::NonFinite { block: m });
                }
            }
        }
        match failed {
            Some((m, j)) => Err(FactorError::NotPositiveDefinite { index: m * 4 + j }),
            None => Ok(()),
        }
    }

    /// `x <- (H + tau I)^-1 x` with a Cholesky factorisation of blocks of
    /// size 4 (coupled or not). The sweeps of the module docs, split into
    /// passes over the groups in lanes (the block solves, the dot products
    /// and the vector updates, on `x` held lane-major in the workspace)
    /// and the two running sums block by block between them; every value
    /// as the block-by-block solve computes it.
    pub(super) fn solve_cholesky4(&mut self, x: &mut [f64]) {
        widest!(
            self,
            solve_cholesky4_avx512,
            solve_cholesky4_avx2,
            solve_cholesky4_in(x)
        )
    }

    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    #[target_feature(enable = "avx512f,avx2")]
    fn solve_cholesky4_avx512(&mut self, x: &mut [f64]) {
        self.solve_cholesky4_in(x)
    }

    #[cfg(any(target_arch = "x86", target_arch = "x86_64"))]
    #[target_feature(enable = "avx2")]
    fn solve_cholesky4_avx2(&mut self, x: &mut [f64]) {
        self.solve_cholesky4_in(x)
    }

    #[inline(always)]
    fn solve_cholesky4_in(&mut self, x: &mut [f64]) {
        let groups = self.blocks.div_ceil(LANES);
        // per group: x (4 lanes), then two scalars per block
        let work = &mut self.lane_work.all_mut()[..groups * 6];
        let (xs, sums) = work.split_at_mut(groups * 4);
        // the block solves y_k = B'_k^-1 x_k, with (coupled) b_k^T x_k and
        // q_k^T x_k
        for g in 0..groups {
            let v = load(x, g, LANES.min(self.blocks - g * LANES));
            let y = solve4(&factor_of(self.f.group(g)), v);
            xs[g * 4..g * 4 + 4].copy_from_slice(&y);
            if self.coupled {
                let (bw, q) = (vector_of(self.bw.group(g)), vector_of(self.q.group(g)));
                sums[g * 2] = dot4(&bw, &v);
                sums[g * 2 + 1] = dot4(&q, &v);
            }
        }
        if self.coupled {
            // forward: z_k = b_k + sigma_k w_k, P_k^-1 = B'_k^-1 + c_k b_k
            // b_k^T, so x_k = y_k + t_k b_k with t_k (in place of b_k^T x_k)
            let mut sigma = 0.0;
            for g in 0..groups {
                let [beta, c, omega]: [Lane; 3] = self.sm.group(g).try_into().unwrap();
                let [s1, s2]: &mut [Lane; 2] = (&mut sums[g * 2..g * 2 + 2]).try_into().unwrap();
                for l in 0..LANES.min(self.blocks - g * LANES) {
                    let t = sigma + c[l] * (s1[l] + sigma * beta[l]);
                    sigma = sigma * (1.0 + omega[l]) + s2[l];
                    s1[l] = t;
                }
            }
            // x_k += t_k b_k; w_k^T x_k (in place of q_k^T x_k)
            for g in 0..groups {
                let xg = &mut xs[g * 4..g * 4 + 4];
                add_scaled(xg, sums[g * 2], self.bw.group(g));
                sums[g * 2 + 1] = dot4(&vector_of(self.w.group(g)), &vector_of(xg));
            }
            // backward: x_m += rho_m q_m,
            // rho_{m-1} = rho_m (1 + omega_m) + w_m^T x_m
            let mut rho = 0.0;
            for g in (0..groups).rev() {
                let omega = self.sm.group(g)[2];
                let [r, wx]: &mut [Lane; 2] = (&mut sums[g * 2..g * 2 + 2]).try_into().unwrap();
                for l in (0..LANES.min(self.blocks - g * LANES)).rev() {
                    r[l] = rho;
                    rho = rho * (1.0 + omega[l]) + wx[l];
                }
            }
            for g in 0..groups {
                add_scaled(&mut xs[g * 4..g * 4 + 4], sums[g * 2], self.q.group(g));
            }
        }
        for g in 0..groups {
            store(
                x,
                g,
                LANES.min(self.blocks - g * LANES),
                &vector_of(&xs[g * 4..]),
            );
        }
    }
}

/// Group `g`'s blocks of the block-major vector `x` (size 4), a lane per
/// block (zero past the first `count`).
#[inline(always)]
fn load(x: &[f64], g: usize, count: usize) -> [Lane; 4] {
    let x = &x[g * LANES * 4..(g * LANES + count) * 4];
    let mut v = [[0.0; LANES]; 4];
    for (l, xk) in x.chunks_exact(4).enumerate() {
        for i in 0..4 {
            v[i][l] = xk[i];
        }
    }
    v
}

/// The inverse of [`load`].
#[inline(always)]
fn store(x: &mut [f64], g: usize, count: usize, v: &[Lane; 4]) {
    let x = &mut x[g * LANES * 4..(g * LANES + count) * 4];
    for (l, xk) in x.chunks_exact_mut(4).enumerate() {
        for i in 0..4 {
            xk[i] = v[i][l];
        }
    }
}

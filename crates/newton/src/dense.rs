//! Small dense linear algebra on column-major `f64` slices: Cholesky, LU
//! with partial pivoting, and the smallest eigenvalue of a symmetric matrix.
//!
//! All matrices are `n * n` slices in column-major order (entry `(i, j)` at
//! `a[i + j * n]`). The factorisations work in place and never allocate, so
//! they can run inside solver iterations. Dimension mismatches are
//! programmer errors and panic with a message naming the argument.

use faer::dyn_stack::{MemBuffer, MemStack};

/// Why a dense factorisation stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum DenseError {
    /// A Cholesky pivot was not strictly positive and finite: the matrix is
    /// not (numerically) positive definite, or holds NaN/inf.
    #[error("Cholesky pivot {index} is not positive")]
    NonPositivePivot {
        /// Row of the pivot (0-based).
        index: usize,
    },
    /// An LU pivot was zero or non-finite: the matrix is singular to
    /// working precision, or holds NaN/inf.
    #[error("LU pivot {index} is zero or not finite")]
    ZeroPivot {
        /// Elimination step (0-based).
        index: usize,
    },
}

impl DenseError {
    /// The row or step where the factorisation stopped.
    pub fn index(&self) -> usize {
        match *self {
            DenseError::NonPositivePivot { index } | DenseError::ZeroPivot { index } => index,
        }
    }
}
use faer::linalg::cholesky::{lblt, llt};
use faer::{MatMut, MatRef, Par, Side};

/// Cholesky factorisation `A = L L^T` in place (lower triangle).
///
/// Reads only the lower triangle (diagonal included) of the column-major
/// `n * n` matrix `a` and overwrites it with `L`. The strict upper
/// triangle is never read for the result, but the vectorised kernel may
/// use it as scratch: its contents are unspecified on return.
///
/// On x86-64 CPUs with AVX2 and FMA (detected at run time, once) a
/// blocked left-looking kernel is used: panels of four columns are
/// updated with register-blocked AVX2/FMA code from the finished columns,
/// then factorised. Elsewhere a plain left-looking column algorithm runs.
/// Both start the updates of a row at its first nonzero (the envelope of
/// `A`, which Cholesky preserves), so banded matrices are cheap.
///
/// Returns [`DenseError::NonPositivePivot`] with the index of the first
/// pivot that is not strictly positive and finite (the matrix is not
/// numerically positive definite, or holds NaN/inf); `a` is then partially
/// overwritten.
///
/// # Panics
/// If `a.len() != n * n`.
pub fn cholesky_in_place(n: usize, a: &mut [f64]) -> Result<(), DenseError> {
    assert_eq!(
        a.len(),
        n * n,
        "cholesky_in_place: a.len() must equal n * n"
    );
    #[cfg(target_arch = "x86_64")]
    {
        if crate::simd::has_avx2_fma() {
            // SAFETY: the CPU supports AVX2 and FMA (checked just above) and
            // a.len() == n * n.
            return unsafe { crate::simd::cholesky_avx2_fma(n, a) }
                .map_err(|index| DenseError::NonPositivePivot { index });
        }
    }
    cholesky_portable(n, a).map_err(|index| DenseError::NonPositivePivot { index })
}

/// Portable left-looking column Cholesky (the fallback kernel).
pub(crate) fn cholesky_portable(n: usize, a: &mut [f64]) -> Result<(), usize> {
    for j in 0..n {
        let (done, rest) = a.split_at_mut(j * n);
        let colj = &mut rest[j..n];
        // First nonzero of row j among the finished columns.
        let mut k = 0;
        while k < j && done[k * n + j] == 0.0 {
            k += 1;
        }
        for k in k..j {
            let ck = &done[k * n + j..k * n + n];
            let m = ck[0];
            for (c, &l) in colj.iter_mut().zip(ck) {
                *c -= m * l;
            }
        }
        let d = colj[0];
        if !(d > 0.0 && d.is_finite()) {
            return Err(j);
        }
        let sd = d.sqrt();
        colj[0] = sd;
        let inv = 1.0 / sd;
        for c in &mut colj[1..] {
            *c *= inv;
        }
    }
    Ok(())
}

/// Solves `L L^T x = b` in place (`b` becomes `x`), with `l` the output of
/// [`cholesky_in_place`] (only its lower triangle is read).
///
/// # Panics
/// If `l.len() != n * n` or `b.len() != n`.
pub fn cholesky_solve(n: usize, l: &[f64], b: &mut [f64]) {
    assert_eq!(l.len(), n * n, "cholesky_solve: l.len() must equal n * n");
    assert_eq!(b.len(), n, "cholesky_solve: b.len() must equal n");
    #[cfg(target_arch = "x86_64")]
    {
        if crate::simd::has_avx2_fma() {
            // SAFETY: the CPU supports AVX2 and FMA (checked just above) and
            // the lengths were checked.
            unsafe { crate::simd::cholesky_solve_avx2_fma(n, l, b) };
            return;
        }
    }
    cholesky_solve_portable(n, l, b)
}

/// Portable forward/backward substitution (the fallback kernel).
pub(crate) fn cholesky_solve_portable(n: usize, l: &[f64], b: &mut [f64]) {
    // Forward: L y = b, column-oriented (axpy).
    for j in 0..n {
        let col = &l[j * n + j..j * n + n];
        let yj = b[j] / col[0];
        b[j] = yj;
        for (bi, &lij) in b[j + 1..].iter_mut().zip(&col[1..]) {
            *bi -= yj * lij;
        }
    }
    // Backward: L^T x = y; row j of L^T is column j of L.
    for j in (0..n).rev() {
        let col = &l[j * n + j + 1..j * n + n];
        let s: f64 = col.iter().zip(&b[j + 1..n]).map(|(c, x)| c * x).sum();
        b[j] = (b[j] - s) / l[j * n + j];
    }
}

/// LU factorisation with partial (row) pivoting in place: `P A = L U`.
///
/// `a` is column-major `n * n`; on success it holds the unit lower factor
/// `L` (below the diagonal) and `U` (diagonal and above), and `perm[k]` is
/// the row swapped with row `k` at elimination step `k` (LAPACK-style
/// interchange record). Right-looking elimination with contiguous column
/// updates.
///
/// Returns [`DenseError::ZeroPivot`] if the pivot at step `k` is zero or
/// non-finite (the matrix is singular to working precision or holds
/// NaN/inf).
///
/// # Panics
/// If `a.len() != n * n` or `perm.len() != n`.
pub fn lu_in_place(n: usize, a: &mut [f64], perm: &mut [usize]) -> Result<(), DenseError> {
    assert_eq!(a.len(), n * n, "lu_in_place: a.len() must equal n * n");
    assert_eq!(perm.len(), n, "lu_in_place: perm.len() must equal n");
    for k in 0..n {
        // Pivot search in column k, rows k..n.
        let col = &a[k * n..k * n + n];
        let mut p = k;
        let mut best = col[k].abs();
        for (i, v) in col.iter().enumerate().skip(k + 1) {
            let av = v.abs();
            if av > best || av.is_nan() {
                best = av;
                p = i;
            }
        }
        if !(best > 0.0 && best.is_finite()) {
            return Err(DenseError::ZeroPivot { index: k });
        }
        perm[k] = p;
        if p != k {
            for j in 0..n {
                a.swap(j * n + k, j * n + p);
            }
        }
        let (left, right) = a.split_at_mut((k + 1) * n);
        let colk = &mut left[k * n..];
        let inv = 1.0 / colk[k];
        for v in &mut colk[k + 1..n] {
            *v *= inv;
        }
        let lcol = &colk[k + 1..n];
        for j in 0..n - k - 1 {
            let colj = &mut right[j * n..j * n + n];
            let ukj = colj[k];
            if ukj != 0.0 {
                for (c, &l) in colj[k + 1..].iter_mut().zip(lcol) {
                    *c -= ukj * l;
                }
            }
        }
    }
    Ok(())
}

/// Solves `A x = b` in place using the output of [`lu_in_place`].
///
/// # Panics
/// If `lu.len() != n * n`, `perm.len() != n` or `b.len() != n`.
pub fn lu_solve(n: usize, lu: &[f64], perm: &[usize], b: &mut [f64]) {
    assert_eq!(lu.len(), n * n, "lu_solve: lu.len() must equal n * n");
    assert_eq!(perm.len(), n, "lu_solve: perm.len() must equal n");
    assert_eq!(b.len(), n, "lu_solve: b.len() must equal n");
    for (k, &p) in perm.iter().enumerate() {
        b.swap(k, p);
    }
    // L y = P b (unit diagonal), column-oriented.
    for j in 0..n {
        let yj = b[j];
        if yj != 0.0 {
            let col = &lu[j * n + j + 1..j * n + n];
            for (bi, &lij) in b[j + 1..].iter_mut().zip(col) {
                *bi -= yj * lij;
            }
        }
    }
    // U x = y, column-oriented from the back.
    for j in (0..n).rev() {
        let col = &lu[j * n..j * n + j + 1];
        let xj = b[j] / col[j];
        b[j] = xj;
        if xj != 0.0 {
            for (bi, &uij) in b[..j].iter_mut().zip(&col[..j]) {
                *bi -= xj * uij;
            }
        }
    }
}

/// Number of negative eigenvalues of the symmetric column-major `n * n`
/// matrix `h` (faer's self-adjoint eigenvalues of `(h + h^T) / 2`); `None`
/// for a non-finite entry or no convergence. Allocates `O(n^2)`.
pub fn negative_eigenvalues(n: usize, h: &[f64]) -> Option<usize> {
    if n == 0 {
        return Some(0);
    }
    if !all_finite(h) {
        return None;
    }
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (h[i + j * n] + h[j + i * n]));
    m.self_adjoint_eigenvalues(Side::Lower)
        .ok()
        .map(|v| v.iter().filter(|&&l| l < 0.0).count())
}

/// Smallest eigenvalue of the symmetric column-major `n * n` matrix `h`.
///
/// Uses faer's self-adjoint eigenvalue solver (Householder
/// tridiagonalisation followed by a tridiagonal eigensolver, eigenvalues
/// only), chosen over
/// nalgebra's `SymmetricEigen` because faer skips the eigenvectors when
/// they are not wanted and reports non-convergence instead of iterating
/// without bound. The matrix is symmetrised as `(h + h^T) / 2` first, so
/// a slightly unsymmetric Hessian is treated consistently.
///
/// Returns NaN if `h` holds a non-finite entry or the solver does not
/// converge, and `+inf` for `n == 0`. This allocates `O(n^2)`; it is a
/// diagnostic (stability of an equilibrium), not meant for inner loops.
///
/// # Panics
/// If `h.len() != n * n`.
pub fn min_eigenvalue(n: usize, h: &[f64]) -> f64 {
    assert_eq!(h.len(), n * n, "min_eigenvalue: h.len() must equal n * n");
    if n == 0 {
        return f64::INFINITY;
    }
    if !all_finite(h) {
        return f64::NAN;
    }
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (h[i + j * n] + h[j + i * n]));
    match m.self_adjoint_eigenvalues(Side::Lower) {
        Ok(vals) => vals.iter().copied().fold(f64::INFINITY, f64::min),
        Err(_) => f64::NAN,
    }
}

/// faer's Cholesky with its scratch memory preallocated, so factorising
/// and solving do not allocate.
pub(crate) struct FaerCholesky {
    n: usize,
    mem: MemBuffer,
}

impl FaerCholesky {
    pub(crate) fn new(n: usize) -> Self {
        let req = llt::factor::cholesky_in_place_scratch::<f64>(n, Par::Seq, Default::default())
            .or(llt::solve::solve_in_place_scratch::<f64>(n, 1, Par::Seq));
        Self {
            n,
            mem: MemBuffer::new(req),
        }
    }

    /// Factorises the lower triangle of `a` in place; `Err(j)` for the
    /// failing pivot.
    pub(crate) fn factor(&mut self, a: &mut [f64]) -> Result<(), usize> {
        let n = self.n;
        let m = MatMut::from_column_major_slice_mut(a, n, n);
        llt::factor::cholesky_in_place(
            m,
            Default::default(),
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        )
        .map(|_| ())
        .map_err(|e| match e {
            llt::factor::LltError::NonPositivePivot { index } => index,
        })
    }

    /// Solves with the factor produced by [`Self::factor`].
    pub(crate) fn solve(&mut self, l: &[f64], b: &mut [f64]) {
        let n = self.n;
        let lm = MatRef::from_column_major_slice(l, n, n);
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        llt::solve::solve_in_place(lm, rhs, Par::Seq, MemStack::new(&mut self.mem));
    }
}

/// A dense symmetric-indefinite factorisation `P A Pᵀ = L B Lᵀ`
/// (faer's Bunch-Kaufman, `B` block diagonal with 1x1 and 2x2 blocks)
/// whose scratch and pivots are allocated once: factorising gives the
/// inertia (Sylvester's law: that of `B`), and neither factorising nor
/// solving allocates.
pub(crate) struct FaerLblt {
    n: usize,
    subdiag: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
}

impl FaerLblt {
    pub(crate) fn new(n: usize) -> Self {
        let req =
            lblt::factor::cholesky_in_place_scratch::<usize, f64>(n, Par::Seq, Default::default())
                .or(lblt::solve::solve_in_place_scratch::<usize, f64>(
                    n,
                    1,
                    Par::Seq,
                ));
        Self {
            n,
            subdiag: vec![0.0; n],
            perm: vec![0; n],
            perm_inv: vec![0; n],
            mem: MemBuffer::new(req),
        }
    }

    /// Factorises the symmetric matrix `a` (column-major, lower triangle
    /// read) in place; returns the number of negative eigenvalues, or
    /// `Err(i)` for the first exactly singular (or non-finite) pivot block.
    pub(crate) fn factor(&mut self, a: &mut [f64]) -> Result<usize, usize> {
        let n = self.n;
        let m = MatMut::from_column_major_slice_mut(a, n, n);
        let sub = faer::diag::DiagMut::from_slice_mut(&mut self.subdiag);
        lblt::factor::cholesky_in_place(
            m,
            sub,
            &mut self.perm,
            &mut self.perm_inv,
            Par::Seq,
            MemStack::new(&mut self.mem),
            Default::default(),
        );
        let d = |i: usize| a[i * (n + 1)];
        let mut negative = 0;
        let mut i = 0;
        while i < n {
            let s = self.subdiag[i];
            if s != 0.0 && i + 1 < n {
                // a 2x2 block [d_i s; s d_i+1]
                let det = d(i) * d(i + 1) - s * s;
                if !(det.is_finite() && det != 0.0) {
                    return Err(i);
                }
                negative += if det < 0.0 {
                    1
                } else if d(i) + d(i + 1) < 0.0 {
                    2
                } else {
                    0
                };
                i += 2;
            } else {
                let di = d(i);
                if !(di.is_finite() && di != 0.0) {
                    return Err(i);
                }
                negative += usize::from(di < 0.0);
                i += 1;
            }
        }
        Ok(negative)
    }

    /// Solves with the factor produced by [`Self::factor`].
    pub(crate) fn solve(&mut self, l: &[f64], b: &mut [f64]) {
        let n = self.n;
        let lm = MatRef::from_column_major_slice(l, n, n);
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        let perm = faer::perm::PermRef::new_checked(&self.perm, &self.perm_inv, n);
        lblt::solve::solve_in_place_with_conj(
            lm,
            lm.diagonal(),
            faer::diag::DiagRef::from_slice(&self.subdiag),
            faer::Conj::No,
            perm,
            rhs,
            Par::Seq,
            MemStack::new(&mut self.mem),
        );
    }
}

/// `max_i |v_i|` (0 for an empty slice; NaN entries propagate as NaN).
pub(crate) fn norm_inf(v: &[f64]) -> f64 {
    let mut m = 0.0f64;
    for &x in v {
        let a = x.abs();
        if a.is_nan() {
            return f64::NAN;
        }
        if a > m {
            m = a;
        }
    }
    m
}

pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

pub(crate) fn all_finite(v: &[f64]) -> bool {
    #[cfg(target_arch = "x86_64")]
    {
        if crate::simd::has_avx2_fma() {
            // SAFETY: the CPU supports AVX2 and FMA (checked just above).
            return unsafe { crate::simd::all_finite_avx2(v) };
        }
    }
    // Branch-free OR of per-element tests: vectorises (an integer
    // reduction), unlike a short-circuiting `all` or a float sum.
    let mut bad = false;
    for &x in v {
        bad |= !x.is_finite();
    }
    !bad
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Lcg;

    fn random_spd(n: usize, rng: &mut Lcg) -> Vec<f64> {
        // A = B B^T + n I
        let b: Vec<f64> = (0..n * n).map(|_| rng.sym()).collect();
        let mut a = vec![0.0; n * n];
        for j in 0..n {
            for i in 0..n {
                let mut s = 0.0;
                for k in 0..n {
                    s += b[i + k * n] * b[j + k * n];
                }
                a[i + j * n] = s + if i == j { n as f64 } else { 0.0 };
            }
        }
        a
    }

    fn matvec(n: usize, a: &[f64], x: &[f64]) -> Vec<f64> {
        let mut y = vec![0.0; n];
        for j in 0..n {
            for i in 0..n {
                y[i] += a[i + j * n] * x[j];
            }
        }
        y
    }

    /// Relative residual `||A x - b||_inf / (||A||_max ||x||_inf n)`.
    fn rel_residual(n: usize, a: &[f64], x: &[f64], b: &[f64]) -> f64 {
        let ax = matvec(n, a, x);
        let r = ax
            .iter()
            .zip(b)
            .map(|(p, q)| (p - q).abs())
            .fold(0.0, f64::max);
        r / (norm_inf(a) * norm_inf(x) * n as f64).max(f64::MIN_POSITIVE)
    }

    #[test]
    fn cholesky_solves_random_spd() {
        let mut rng = Lcg::new(7);
        for &n in &[1usize, 2, 3, 5, 8, 17, 32, 64, 100] {
            let a = random_spd(n, &mut rng);
            let b: Vec<f64> = (0..n).map(|_| rng.sym()).collect();
            let mut l = a.clone();
            cholesky_in_place(n, &mut l).unwrap();
            let mut x = b.clone();
            cholesky_solve(n, &l, &mut x);
            let r = rel_residual(n, &a, &x, &b);
            assert!(r < 1e-14, "n = {n}: relative residual {r}");
            // The faer backend gives the same solution.
            let mut fl = a.clone();
            let mut fc = FaerCholesky::new(n);
            fc.factor(&mut fl).unwrap();
            let mut fx = b.clone();
            fc.solve(&fl, &mut fx);
            let d = x
                .iter()
                .zip(&fx)
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            assert!(
                d <= 1e-12 * (1.0 + norm_inf(&x)),
                "n = {n}: backends differ by {d}"
            );
        }
    }

    /// Both kernels: the dispatched one (AVX2/FMA on capable CPUs) and the
    /// portable fallback.
    type Kernel = fn(usize, &mut [f64]) -> Result<(), usize>;

    fn dispatched(n: usize, a: &mut [f64]) -> Result<(), usize> {
        cholesky_in_place(n, a).map_err(|e| e.index())
    }

    fn kernels() -> [(&'static str, Kernel); 2] {
        [("dispatched", dispatched), ("portable", cholesky_portable)]
    }

    #[test]
    fn cholesky_reads_and_writes_only_lower_triangle() {
        let mut rng = Lcg::new(3);
        for &n in &[1usize, 3, 4, 5, 6, 8, 9, 13, 16, 33, 40] {
            let a = random_spd(n, &mut rng);
            for (name, kernel) in kernels() {
                let mut clean = a.clone();
                kernel(n, &mut clean).unwrap();
                let mut garbage = a.clone();
                for j in 0..n {
                    for i in 0..j {
                        garbage[i + j * n] = f64::NAN;
                    }
                }
                kernel(n, &mut garbage).unwrap();
                for j in 0..n {
                    for i in 0..n {
                        let (c, g) = (clean[i + j * n], garbage[i + j * n]);
                        if i >= j {
                            assert_eq!(
                                c, g,
                                "{name} n = {n}: L[{i},{j}] depends on the upper triangle"
                            );
                        } else {
                            assert!(
                                g.is_nan() && c == a[i + j * n],
                                "{name} n = {n}: upper ({i},{j}) written"
                            );
                        }
                    }
                }
                // L L^T reproduces A.
                for j in 0..n {
                    for i in j..n {
                        let s: f64 = (0..=j).map(|k| clean[i + k * n] * clean[j + k * n]).sum();
                        let r = (s - a[i + j * n]).abs();
                        assert!(
                            r <= 1e-13 * n as f64 * norm_inf(&a),
                            "{name} n = {n}: |LL^T - A| = {r}"
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn cholesky_reports_failing_pivot() {
        for (name, kernel) in kernels() {
            // diag(1, 2, -1, 3): the third pivot (index 2) fails.
            let n = 4;
            let mut a = vec![0.0; 16];
            for (i, d) in [1.0, 2.0, -1.0, 3.0].iter().enumerate() {
                a[i + i * n] = *d;
            }
            assert_eq!(kernel(n, &mut a), Err(2), "{name}");
            // [[1, 2], [2, 1]] is indefinite: pivot 1 fails (1 - 4 < 0).
            let mut b = vec![1.0, 2.0, 2.0, 1.0];
            assert_eq!(kernel(2, &mut b), Err(1), "{name}");
            // SPD except for the trailing block: shift an SPD matrix's
            // entry (9, 9) down until it is indefinite; the pivot of
            // index 9 (in the third panel of four) fails first.
            let mut rng = Lcg::new(17);
            let n = 11;
            let mut m = random_spd(n, &mut rng);
            m[9 + 9 * n] -= 100.0 * n as f64;
            assert_eq!(kernel(n, &mut m), Err(9), "{name}");
            // NaN is reported, not propagated.
            let mut c = vec![f64::NAN];
            assert_eq!(kernel(1, &mut c), Err(0), "{name}");
            let mut m = random_spd(n, &mut rng);
            m[7 + 2 * n] = f64::NAN;
            assert_eq!(kernel(n, &mut m), Err(7), "{name}");
            // Empty matrix is trivially fine.
            assert_eq!(kernel(0, &mut []), Ok(()), "{name}");
        }
        let mut fc = FaerCholesky::new(2);
        let mut b = vec![1.0, 2.0, 2.0, 1.0];
        assert_eq!(fc.factor(&mut b), Err(1));
    }

    #[test]
    fn lu_solves_random_systems() {
        let mut rng = Lcg::new(11);
        for &n in &[1usize, 2, 3, 4, 9, 33, 65, 129] {
            let a: Vec<f64> = (0..n * n).map(|_| rng.sym()).collect();
            let b: Vec<f64> = (0..n).map(|_| rng.sym()).collect();
            let mut lu = a.clone();
            let mut perm = vec![0; n];
            lu_in_place(n, &mut lu, &mut perm).unwrap();
            let mut x = b.clone();
            lu_solve(n, &lu, &perm, &mut x);
            let r = rel_residual(n, &a, &x, &b);
            assert!(r < 1e-13, "n = {n}: relative residual {r}");
            // Independent check: nalgebra's LU gives the same solution.
            let na = nalgebra::DMatrix::from_column_slice(n, n, &a);
            let nb = nalgebra::DVector::from_column_slice(&b);
            let nx = na.lu().solve(&nb).unwrap();
            let d = x
                .iter()
                .zip(nx.iter())
                .map(|(p, q)| (p - q).abs())
                .fold(0.0, f64::max);
            assert!(
                d <= 1e-9 * (1.0 + norm_inf(&x)),
                "n = {n}: differs from nalgebra by {d}"
            );
        }
    }

    #[test]
    fn lu_needs_pivoting_and_detects_singularity() {
        // [[0, 1], [1, 0]] needs a row swap.
        let mut a = vec![0.0, 1.0, 1.0, 0.0];
        let mut perm = [0; 2];
        lu_in_place(2, &mut a, &mut perm).unwrap();
        let mut b = [2.0, 3.0];
        lu_solve(2, &a, &perm, &mut b);
        assert_eq!(b, [3.0, 2.0]);
        // Rank-deficient.
        let mut s = vec![1.0, 2.0, 2.0, 4.0];
        assert_eq!(
            lu_in_place(2, &mut s, &mut perm),
            Err(DenseError::ZeroPivot { index: 1 })
        );
        let mut z = vec![f64::NAN, 0.0, 0.0, 1.0];
        assert!(lu_in_place(2, &mut z, &mut perm).is_err());
    }

    /// Random orthogonal matrix from Gram-Schmidt on a seeded random matrix.
    fn random_orthogonal(n: usize, rng: &mut Lcg) -> Vec<f64> {
        let mut q: Vec<f64> = (0..n * n).map(|_| rng.sym()).collect();
        for j in 0..n {
            for _pass in 0..2 {
                for k in 0..j {
                    let d: f64 = (0..n).map(|i| q[i + j * n] * q[i + k * n]).sum();
                    for i in 0..n {
                        q[i + j * n] -= d * q[i + k * n];
                    }
                }
            }
            let nrm: f64 = (0..n).map(|i| q[i + j * n].powi(2)).sum::<f64>().sqrt();
            for i in 0..n {
                q[i + j * n] /= nrm;
            }
        }
        q
    }

    #[test]
    fn min_eigenvalue_of_known_spectrum() {
        let mut rng = Lcg::new(5);
        for &n in &[1usize, 2, 5, 16, 40] {
            let q = random_orthogonal(n, &mut rng);
            let lam: Vec<f64> = (0..n)
                .map(|i| -3.0 + 0.37 * i as f64 + 0.1 * rng.unit())
                .collect();
            let mut h = vec![0.0; n * n];
            for j in 0..n {
                for i in 0..n {
                    h[i + j * n] = (0..n).map(|k| q[i + k * n] * lam[k] * q[j + k * n]).sum();
                }
            }
            let expected = lam.iter().copied().fold(f64::INFINITY, f64::min);
            let got = min_eigenvalue(n, &h);
            assert!(
                (got - expected).abs() < 1e-12 * n as f64,
                "n = {n}: {got} vs {expected}"
            );
        }
        assert_eq!(min_eigenvalue(0, &[]), f64::INFINITY);
        assert!(min_eigenvalue(1, &[f64::NAN]).is_nan());
    }

    #[test]
    fn helpers() {
        assert_eq!(norm_inf(&[1.0, -3.0, 2.0]), 3.0);
        assert!(norm_inf(&[1.0, f64::NAN]).is_nan());
        assert!(norm_inf(&[f64::NAN, 1.0]).is_nan());
        assert!(all_finite(&[1.0, 2.0]));
        assert!(!all_finite(&[1.0, f64::INFINITY]));
        assert!(!all_finite(&[f64::NAN]));
    }

    /// Timing of the in-house Cholesky against faer. Run with
    /// `cargo test -p fpc-newton --release -- --ignored --nocapture cholesky_timing`.
    #[test]
    #[ignore]
    fn cholesky_timing() {
        use std::time::Instant;
        let mut rng = Lcg::new(1);
        println!("n, dense_us, faer_inplace_us, faer_llt_us");
        for &n in &[8usize, 16, 32, 64, 96, 128, 160, 192, 224, 256, 384, 512] {
            let a = random_spd(n, &mut rng);
            let b: Vec<f64> = (0..n).map(|_| rng.sym()).collect();
            let reps = (20_000_000 / (n * n * n)).clamp(5, 200_000);
            let mut work = a.clone();
            let mut x = b.clone();
            let time = |f: &mut dyn FnMut()| {
                let mut best = f64::INFINITY;
                for _ in 0..7 {
                    let t = Instant::now();
                    for _ in 0..reps {
                        f();
                    }
                    best = best.min(t.elapsed().as_secs_f64() / reps as f64);
                }
                best * 1e6
            };
            let dense = time(&mut || {
                work.copy_from_slice(&a);
                cholesky_in_place(n, &mut work).unwrap();
                x.copy_from_slice(&b);
                cholesky_solve(n, &work, &mut x);
                std::hint::black_box(&x);
            });
            let mut fc = FaerCholesky::new(n);
            let faer_inplace = time(&mut || {
                work.copy_from_slice(&a);
                fc.factor(&mut work).unwrap();
                x.copy_from_slice(&b);
                fc.solve(&work, &mut x);
                std::hint::black_box(&x);
            });
            let fa = faer::Mat::<f64>::from_fn(n, n, |i, j| a[i + j * n]);
            let fb = faer::Mat::<f64>::from_fn(n, 1, |i, _| b[i]);
            let faer_llt = time(&mut || {
                let llt = fa.llt(Side::Lower).unwrap();
                let s = faer::linalg::solvers::Solve::solve(&llt, &fb);
                std::hint::black_box(&s);
            });
            println!("{n}, {dense:.3}, {faer_inplace:.3}, {faer_llt:.3}");
        }
    }
}

//! The small dense kernels on one pivot block of the structured
//! factorisation: the square-root-free Cholesky factorisation and its
//! solve, the certificate that a pivot is clearly positive definite, and
//! the symmetric eigendecomposition (cyclic Jacobi) with its solve.

/// Jacobi sweeps before the eigenvalue iteration of a pivot gives up.
const MAX_SWEEPS: usize = 60;

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
pub(super) fn cholesky<const N: usize>(n: usize, a: &mut [f64]) -> Result<(), usize> {
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
pub(super) fn cholesky_solve<const N: usize>(n: usize, l: &[f64], b: &mut [f64]) {
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
pub(super) const CERTIFIED_RATIO: f64 = 1e-12;

/// True when the symmetric `p` (`n x n`) is positive definite with its
/// smallest eigenvalue above [`CERTIFIED_RATIO`] times its largest; then
/// `scratch[..n * n]` holds its [`cholesky`] factor. For a positive
/// definite matrix `lambda_max <= trace(P)` and `1 / lambda_min <=
/// trace(P^-1)`, and `trace(P^-1) = sum_j |L^-1 e_j|^2_(D^-1)` comes from
/// the factor. False proves nothing (the caller takes the eigenvalues).
pub(super) fn certified_positive<const N: usize>(n: usize, p: &[f64], scratch: &mut [f64]) -> bool {
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
pub(super) fn jacobi(n: usize, a: &mut [f64], lam: &mut [f64], scratch: &mut [f64]) -> Option<()> {
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
pub(super) fn eigen_solve(n: usize, v: &[f64], lam: &[f64], b: &mut [f64], scratch: &mut [f64]) {
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

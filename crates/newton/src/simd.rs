//! AVX2/FMA kernels for the dense Cholesky factorisation and solve
//! (x86-64 only, selected at run time by [`has_avx2_fma`]).
//!
//! Small matrices are dominated by loop overhead and dependency chains
//! rather than flops, so these kernels work on panels of four columns and
//! chunks of four or eight rows held in registers: every vector load and
//! store hits a fixed 4-row grid (no partially overlapping store/load
//! pairs), and the inner loops carry 4-8 independent accumulators.
//! Masked loads/stores keep the strict upper triangle untouched and handle
//! row counts that are not multiples of four.

// Index loops over the small fixed-size blocks read more clearly than
// iterator chains here, and stay inlined inside `target_feature` code.
#![allow(clippy::needless_range_loop)]

use core::arch::x86_64::*;
use std::sync::atomic::{AtomicU8, Ordering};

static DETECTED: AtomicU8 = AtomicU8::new(0);

/// Cached run-time detection of AVX2 + FMA.
#[inline]
pub(crate) fn has_avx2_fma() -> bool {
    match DETECTED.load(Ordering::Relaxed) {
        1 => true,
        2 => false,
        _ => {
            let yes = std::arch::is_x86_feature_detected!("avx2")
                && std::arch::is_x86_feature_detected!("fma");
            DETECTED.store(if yes { 1 } else { 2 }, Ordering::Relaxed);
            yes
        }
    }
}

/// Lane mask with lanes `lo..hi` (of 0..4) active.
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn lanes(lo: usize, hi: usize) -> __m256i {
    let f = |l: usize| if l >= lo && l < hi { -1i64 } else { 0 };
    _mm256_setr_epi64x(f(0), f(1), f(2), f(3))
}

#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn hsum(v: __m256d) -> f64 {
    let lo = _mm256_castpd256_pd128(v);
    let hi = _mm256_extractf128_pd::<1>(v);
    let s = _mm_add_pd(lo, hi);
    let h = _mm_unpackhi_pd(s, s);
    _mm_cvtsd_f64(_mm_add_sd(s, h))
}

/// Blocked left-looking Cholesky; same contract as
/// [`crate::cholesky_in_place`].
///
/// # Safety
/// The CPU must support AVX2 and FMA, and `a.len() == n * n`.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn cholesky_avx2_fma(n: usize, a: &mut [f64]) -> Result<(), usize> {
    debug_assert_eq!(a.len(), n * n);
    let mut jb = 0;
    while jb < n {
        let w = (n - jb).min(4);
        {
            let p = a.as_mut_ptr();
            // Envelope: first column k < jb with a nonzero in any panel row.
            let mut kstart = jb;
            for r in jb..jb + w {
                let mut k = 0;
                while k < kstart && *p.add(r + k * n) == 0.0 {
                    k += 1;
                }
                kstart = k;
            }
            if kstart < jb {
                if w == 4 {
                    panel_update4(p, n, jb, kstart);
                } else {
                    panel_update_narrow(p, n, jb, w, kstart);
                }
            }
        }
        // Factorise the panel itself (columns jb..jb+w, rows j..n).
        for c in 0..w {
            let j = jb + c;
            let (done, rest) = a.split_at_mut(j * n);
            let colj = &mut rest[j..n];
            for cc in 0..c {
                let kc = &done[(jb + cc) * n + j..(jb + cc) * n + n];
                let m = kc[0];
                if m != 0.0 {
                    for (x, &l) in colj.iter_mut().zip(kc) {
                        *x = (-m).mul_add(l, *x);
                    }
                }
            }
            let d = colj[0];
            if !(d > 0.0 && d.is_finite()) {
                return Err(j);
            }
            // sqrt(d) and 1/d are independent: shorter dependency chain.
            let r = 1.0 / d;
            let sd = d.sqrt();
            colj[0] = sd;
            let inv = sd * r;
            for x in &mut colj[1..] {
                *x *= inv;
            }
        }
        jb += w;
    }
    Ok(())
}

/// `A[i, jb+c] -= sum_{k in kstart..jb} L[i, k] L[jb+c, k]` for the four
/// panel columns `c` and rows `i >= jb + c`.
#[target_feature(enable = "avx2,fma")]
unsafe fn panel_update4(p: *mut f64, n: usize, jb: usize, kstart: usize) {
    let colp = |c: usize| p.add((jb + c) * n);

    // Diagonal chunk (rows jb..jb+4): column c keeps rows >= jb + c.
    // The k-column load uses all four lanes (rows jb.. are below the
    // diagonal of every finished column k < jb).
    chunk4(
        p,
        n,
        jb,
        kstart,
        jb,
        [lanes(0, 4), lanes(1, 4), lanes(2, 4), lanes(3, 4)],
    );

    let mut i0 = jb + 4;
    while i0 + 8 <= n {
        let mut acc0 = [_mm256_setzero_pd(); 4];
        let mut acc1 = [_mm256_setzero_pd(); 4];
        for c in 0..4 {
            acc0[c] = _mm256_loadu_pd(colp(c).add(i0));
            acc1[c] = _mm256_loadu_pd(colp(c).add(i0 + 4));
        }
        for k in kstart..jb {
            let lk = p.add(k * n + i0);
            let v0 = _mm256_loadu_pd(lk);
            let v1 = _mm256_loadu_pd(lk.add(4));
            for c in 0..4 {
                let m = _mm256_broadcast_sd(&*p.add(jb + c + k * n));
                acc0[c] = _mm256_fnmadd_pd(m, v0, acc0[c]);
                acc1[c] = _mm256_fnmadd_pd(m, v1, acc1[c]);
            }
        }
        for c in 0..4 {
            _mm256_storeu_pd(colp(c).add(i0), acc0[c]);
            _mm256_storeu_pd(colp(c).add(i0 + 4), acc1[c]);
        }
        i0 += 8;
    }
    if i0 < n {
        let m = lanes(0, (n - i0).min(4));
        chunk4(p, n, jb, kstart, i0, [m, m, m, m]);
        i0 += 4;
        if i0 < n {
            let m = lanes(0, n - i0);
            chunk4(p, n, jb, kstart, i0, [m, m, m, m]);
        }
    }
}

/// Masked 4-row chunk of [`panel_update4`] at row `i0`; panel column `c`
/// loads and stores with `masks[c]`, the finished columns with `masks[0]`.
#[inline]
#[target_feature(enable = "avx2,fma")]
unsafe fn chunk4(p: *mut f64, n: usize, jb: usize, kstart: usize, i0: usize, masks: [__m256i; 4]) {
    let mut acc = [_mm256_setzero_pd(); 4];
    for c in 0..4 {
        acc[c] = _mm256_maskload_pd(p.add((jb + c) * n + i0), masks[c]);
    }
    for k in kstart..jb {
        let v = _mm256_maskload_pd(p.add(k * n + i0), masks[0]);
        for (c, a) in acc.iter_mut().enumerate() {
            *a = _mm256_fnmadd_pd(_mm256_broadcast_sd(&*p.add(jb + c + k * n)), v, *a);
        }
    }
    for (c, a) in acc.iter().enumerate() {
        _mm256_maskstore_pd(p.add((jb + c) * n + i0), masks[c], *a);
    }
}

/// Scalar panel update for a last panel narrower than four columns.
#[target_feature(enable = "avx2,fma")]
unsafe fn panel_update_narrow(p: *mut f64, n: usize, jb: usize, w: usize, kstart: usize) {
    for c in 0..w {
        let j = jb + c;
        let colj = p.add(j * n);
        for k in kstart..jb {
            let colk = p.add(k * n);
            let m = *colk.add(j);
            if m != 0.0 {
                for i in j..n {
                    *colj.add(i) = (-m).mul_add(*colk.add(i), *colj.add(i));
                }
            }
        }
    }
}

/// Forward and backward substitution with a Cholesky factor; same
/// contract as [`crate::cholesky_solve`].
///
/// # Safety
/// The CPU must support AVX2 and FMA, `l.len() == n * n`, `b.len() == n`.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn cholesky_solve_avx2_fma(n: usize, l: &[f64], b: &mut [f64]) {
    debug_assert_eq!(l.len(), n * n);
    debug_assert_eq!(b.len(), n);
    let lp = l.as_ptr();
    let bp = b.as_mut_ptr();
    let lij = |i: usize, j: usize| *lp.add(i + j * n);

    // Forward: L y = b, in blocks of four rows.
    let mut jb = 0;
    while jb < n {
        let w = (n - jb).min(4);
        let mut rinv = [0.0; 4];
        for c in 0..w {
            rinv[c] = 1.0 / lij(jb + c, jb + c);
        }
        let mut y = [0.0; 4];
        for c in 0..w {
            let j = jb + c;
            let mut s = *bp.add(j);
            for cc in 0..c {
                s = (-lij(j, jb + cc)).mul_add(y[cc], s);
            }
            y[c] = s * rinv[c];
            *bp.add(j) = y[c];
        }
        if w == 4 {
            let yv = [
                _mm256_set1_pd(y[0]),
                _mm256_set1_pd(y[1]),
                _mm256_set1_pd(y[2]),
                _mm256_set1_pd(y[3]),
            ];
            let cols = [
                lp.add(jb * n),
                lp.add((jb + 1) * n),
                lp.add((jb + 2) * n),
                lp.add((jb + 3) * n),
            ];
            let mut i = jb + 4;
            while i + 4 <= n {
                let mut acc = _mm256_loadu_pd(bp.add(i));
                for c in 0..4 {
                    acc = _mm256_fnmadd_pd(yv[c], _mm256_loadu_pd(cols[c].add(i)), acc);
                }
                _mm256_storeu_pd(bp.add(i), acc);
                i += 4;
            }
            if i < n {
                let m = lanes(0, n - i);
                let mut acc = _mm256_maskload_pd(bp.add(i), m);
                for c in 0..4 {
                    acc = _mm256_fnmadd_pd(yv[c], _mm256_maskload_pd(cols[c].add(i), m), acc);
                }
                _mm256_maskstore_pd(bp.add(i), m, acc);
            }
        }
        jb += w;
    }

    // Backward: L^T x = y, blocks in reverse.
    let nblocks = n.div_ceil(4);
    for blk in (0..nblocks).rev() {
        let jb = 4 * blk;
        let w = (n - jb).min(4);
        let mut s = [0.0; 4];
        for c in 0..w {
            s[c] = *bp.add(jb + c);
        }
        if w == 4 && jb + 4 < n {
            let cols = [
                lp.add(jb * n),
                lp.add((jb + 1) * n),
                lp.add((jb + 2) * n),
                lp.add((jb + 3) * n),
            ];
            let mut acc = [_mm256_setzero_pd(); 4];
            let mut i = jb + 4;
            while i + 4 <= n {
                let xv = _mm256_loadu_pd(bp.add(i));
                for c in 0..4 {
                    acc[c] = _mm256_fmadd_pd(_mm256_loadu_pd(cols[c].add(i)), xv, acc[c]);
                }
                i += 4;
            }
            if i < n {
                let m = lanes(0, n - i);
                let xv = _mm256_maskload_pd(bp.add(i), m);
                for c in 0..4 {
                    acc[c] = _mm256_fmadd_pd(_mm256_maskload_pd(cols[c].add(i), m), xv, acc[c]);
                }
            }
            for c in 0..4 {
                s[c] -= hsum(acc[c]);
            }
        }
        let mut rinv = [0.0; 4];
        for c in 0..w {
            rinv[c] = 1.0 / lij(jb + c, jb + c);
        }
        let mut x = [0.0; 4];
        for c in (0..w).rev() {
            let j = jb + c;
            let mut t = s[c];
            for cc in c + 1..w {
                t = (-lij(jb + cc, j)).mul_add(x[cc], t);
            }
            x[c] = t * rinv[c];
            *bp.add(j) = x[c];
        }
    }
}

/// [`crate::dense::all_finite`] compiled for AVX2 (4-wide compares).
///
/// # Safety
/// The CPU must support AVX2 and FMA.
#[target_feature(enable = "avx2,fma")]
pub(crate) unsafe fn all_finite_avx2(v: &[f64]) -> bool {
    let mut bad = false;
    for &x in v {
        bad |= !x.is_finite();
    }
    !bad
}

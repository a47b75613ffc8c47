//! Tests of the dense reference path: its errors and inertia count.

use super::*;

#[test]
fn dense_errors_name_the_pivot_and_count_the_spectrum() {
    let mut m = DenseMatrix::new(2);
    m.matrix_mut().copy_from_slice(&[1.0, 0.0, 0.0, -1.0]);
    assert_eq!(
        m.factor(0.0, PivotKind::Cholesky),
        Err(FactorError::NotPositiveDefinite { index: 1 })
    );
    let inertia = m.factor(0.0, PivotKind::Symmetric).unwrap();
    assert_eq!((inertia.positive, inertia.negative), (1, 1));
    m.matrix_mut().copy_from_slice(&[1.0, 2.0, 2.0, 4.0]);
    assert!(matches!(
        m.factor(0.0, PivotKind::Symmetric),
        Err(FactorError::Singular { .. })
    ));
    m.matrix_mut()[0] = f64::NAN;
    assert!(matches!(
        m.factor(0.0, PivotKind::Cholesky),
        Err(FactorError::NonFinite { .. })
    ));
    // L diag(d) L^T with L unit lower triangular: Sylvester's law of
    // inertia says its negative eigenvalues are d's negative entries
    let mut rng = Lcg::new(2);
    let n = 9;
    let d: Vec<f64> = (0..n).map(|i| i as f64 - 3.5 + 0.2 * rng.sym()).collect();
    let mut l = vec![0.0; n * n];
    for j in 0..n {
        l[j + j * n] = 1.0;
        for i in j + 1..n {
            l[i + j * n] = rng.sym();
        }
    }
    let mut h = vec![0.0; n * n];
    for j in 0..n {
        for i in 0..n {
            h[i + j * n] = (0..n).map(|k| l[i + k * n] * d[k] * l[j + k * n]).sum();
        }
    }
    assert_eq!(negative_eigenvalues(n, &h), Some(4));
    // the symmetric factorisation's inertia says the same
    let mut m = DenseMatrix::new(n);
    m.matrix_mut().copy_from_slice(&h);
    assert_eq!(m.factor(0.0, PivotKind::Symmetric).unwrap().negative, 4);
    // the smallest eigenvalue of [a b; b c] in closed form
    let (a, b, c) = (0.3f64, -1.7, 2.2);
    let want = 0.5 * (a + c) - (0.25 * (a - c) * (a - c) + b * b).sqrt();
    let got = min_eigenvalue(2, &[a, b, b, c]);
    assert!((got - want).abs() < 1e-14, "{got} vs {want}");
    assert_eq!(negative_eigenvalues(0, &[]), Some(0));
    assert_eq!(min_eigenvalue(0, &[]), f64::INFINITY);
    assert_eq!(negative_eigenvalues(1, &[f64::NAN]), None);
    assert!(min_eigenvalue(1, &[f64::NAN]).is_nan());
}

/// The dense modified factorisation (`L |D| L^T` of faer's `L D L^T`
/// with symmetric pivoting): on a diagonal matrix it is the absolute
/// values; on random indefinite matrices `M - H` is positive semidefinite
/// and `M` positive definite; a positive definite `H` is left as it is.
/// `M` is the matrix the solves invert, checked with faer's LU and
/// eigenvalues.
#[test]
fn dense_modified_pivots_turn_negative_curvature_positive() {
    let solved = |m: &mut DenseMatrix, n: usize| {
        let mut inv = vec![0.0; n * n];
        for j in 0..n {
            inv[j * (n + 1)] = 1.0;
            m.solve(&mut inv[j * n..(j + 1) * n]);
        }
        let mut out = vec![0.0; n * n];
        for j in 0..n {
            let mut e = vec![0.0; n];
            e[j] = 1.0;
            out[j * n..(j + 1) * n].copy_from_slice(&lu_solve(n, &inv, &e));
        }
        out
    };
    let mut m = DenseMatrix::new(3);
    m.matrix_mut()
        .copy_from_slice(&[3.0, 0.0, 0.0, 0.0, -2.0, 0.0, 0.0, 0.0, 0.5]);
    let inertia = m.factor(0.0, PivotKind::Modified).unwrap();
    assert_eq!((inertia.positive, inertia.negative), (3, 0));
    let mm = solved(&mut m, 3);
    let want = [3.0, 0.0, 0.0, 0.0, 2.0, 0.0, 0.0, 0.0, 0.5];
    assert!(max_abs_diff(&mm, &want) <= 1e-14, "{mm:?}");
    let mut rng = Lcg::new(5);
    for n in [2usize, 5, 9, 14] {
        for shift in [-1.0, 0.0, 4.0 * n as f64] {
            let r: Vec<f64> = (0..n * n).map(|_| rng.sym()).collect();
            let mut h = vec![0.0; n * n];
            for j in 0..n {
                for i in 0..n {
                    h[i + j * n] = r[i + j * n] + r[j + i * n] + if i == j { shift } else { 0.0 };
                }
            }
            let mut m = DenseMatrix::new(n);
            m.matrix_mut().copy_from_slice(&h);
            assert_eq!(m.factor(0.0, PivotKind::Modified).unwrap().negative, 0);
            let mm = solved(&mut m, n);
            let scale = norm_inf_of(&h);
            let mut e = mm.clone();
            for (ei, hi) in e.iter_mut().zip(&h) {
                *ei -= hi;
            }
            let definite = negative_eigenvalues(n, &h) == Some(0);
            assert_eq!(
                negative_eigenvalues(n, &mm),
                Some(0),
                "n {n}, shift {shift}"
            );
            assert!(
                min_eigenvalue(n, &e) >= -1e-9 * scale,
                "n {n}: M - H semidefinite"
            );
            if definite {
                assert!(norm_inf_of(&e) <= 1e-9 * scale, "n {n}: unchanged");
            } else {
                assert!(norm_inf_of(&e) > 1e-3 * scale, "n {n}: modified");
            }
        }
    }
}

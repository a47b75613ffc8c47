//! Tests of the dense kernels' errors and inertia count.

use super::*;

#[test]
fn dense_errors_name_the_pivot() {
    let mut a = vec![1.0, 0.0, 0.0, -1.0];
    let e = cholesky_in_place(2, &mut a).unwrap_err();
    assert_eq!(e, DenseError::NonPositivePivot { index: 1 });
    assert_eq!(e.index(), 1);
    let mut s = vec![1.0, 2.0, 2.0, 4.0];
    let e = lu_in_place(2, &mut s, &mut [0; 2]).unwrap_err();
    assert_eq!((e, e.index()), (DenseError::ZeroPivot { index: 1 }, 1));
    // negative_eigenvalues of Q diag(lam) Q^T against a known count
    let mut rng = Lcg::new(2);
    let n = 9;
    let m: Vec<f64> = (0..n * n).map(|_| rng.sym()).collect();
    // a symmetric matrix and its spectrum, by nalgebra
    let mut h = vec![0.0; n * n];
    for j in 0..n {
        for i in 0..n {
            h[i + j * n] = m[i + j * n] + m[j + i * n];
        }
    }
    let eig = nalgebra::DMatrix::from_column_slice(n, n, &h).symmetric_eigenvalues();
    let want = eig.iter().filter(|&&l| l < 0.0).count();
    assert!(want > 0 && want < n);
    assert_eq!(negative_eigenvalues(n, &h), Some(want));
    assert_eq!(negative_eigenvalues(0, &[]), Some(0));
    assert_eq!(negative_eigenvalues(1, &[f64::NAN]), None);
}

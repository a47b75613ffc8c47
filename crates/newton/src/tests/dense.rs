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

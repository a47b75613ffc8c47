//! The Hessian restricted to a constraint's tangent space, `Z^T A Z`, the
//! reference the restricted inertia is checked against (by dense
//! eigenvalues of it). Shared by the crate's unit tests and the palc test
//! crate (`#[path]`-included).

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Orthonormal basis (column-major `n x (n-1)`) of `{v : c . v = 0}`: the
/// last `n - 1` columns of the Householder reflector mapping `c` to a
/// multiple of `e_1`.
pub fn null_basis(c: &[f64]) -> Vec<f64> {
    let n = c.len();
    let norm = dot(c, c).sqrt();
    let mut v = c.to_vec();
    v[0] += norm.copysign(c[0]);
    let vv = dot(&v, &v);
    let mut z = vec![0.0; n * (n - 1)];
    for j in 1..n {
        for i in 0..n {
            let e = if i == j { 1.0 } else { 0.0 };
            z[i + n * (j - 1)] = e - 2.0 * v[i] * v[j] / vv;
        }
    }
    z
}

/// `Z^T A Z` for the column-major `n x n` `a` and `n x (n-1)` `z`.
pub fn reduce(n: usize, a: &[f64], z: &[f64]) -> Vec<f64> {
    let m = n - 1;
    let mut az = vec![0.0; n * m];
    for q in 0..m {
        for i in 0..n {
            az[i + n * q] = (0..n).map(|j| a[i + n * j] * z[j + n * q]).sum();
        }
    }
    let mut red = vec![0.0; m * m];
    for q in 0..m {
        for p in 0..m {
            red[p + m * q] = (0..n).map(|i| z[i + n * p] * az[i + n * q]).sum();
        }
    }
    red
}

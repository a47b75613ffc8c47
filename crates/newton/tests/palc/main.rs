//! Pseudo-arclength continuation ([`Palc`]) and the restricted inertia:
//!
//! * the 1-D snap-through `g = x^3 - x - lambda`, followed through both
//!   folds (located to 1e-10) and its unstable middle part;
//! * the same snap-through rotated into `n` dimensions with stiff (and one
//!   unstable) decoupled directions: folds to 1e-9, inertia at every point
//!   against dense eigenvalue counts;
//! * a chain whose Hessian is a [`Semiseparable`], past a fold, against the
//!   same chain through the dense reference path ([`Dense`]);
//! * step control: landing on the target, a stop predicate, non-finite
//!   evaluations, the step limit, a failed start;
//! * [`restricted_inertia`] against eigenvalues of `Z^T H Z`, and
//!   [`BorderedNewton::last_restricted_inertia`];
//! * accepted steps (events included) do not allocate.

use fpc_newton::{
    factor_restricted_inertia, negative_eigenvalues, restricted_inertia, Bordered, BorderedEval,
    BorderedNewton, BorderedPath, Control, Dense, DenseBorderedProblem, DenseMatrix,
    DensePathProblem, Direction, EventKind, FactorError, Inertia, LinearSystem, NewtonOptions,
    Palc, PalcOptions, Path, PathEvent, PathObserver, PathPoint, PathTermination, PivotKind,
    RestrictedInertiaError, Semiseparable,
};
#[path = "../common/counting.rs"]
mod counting;
use counting::allocations_in;

// ------------------------------------------------------------- helpers

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

fn max_abs_diff(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
}

/// Random orthogonal `n x n` matrix (column-major), by modified
/// Gram-Schmidt on a random matrix.
fn random_orthogonal(n: usize, rng: &mut fastrand::Rng) -> Vec<f64> {
    let mut q: Vec<f64> = (0..n * n).map(|_| 2.0 * rng.f64() - 1.0).collect();
    for j in 0..n {
        for k in 0..j {
            let d: f64 = (0..n).map(|i| q[i + n * j] * q[i + n * k]).sum();
            for i in 0..n {
                q[i + n * j] -= d * q[i + n * k];
            }
        }
        let norm = (0..n).map(|i| q[i + n * j].powi(2)).sum::<f64>().sqrt();
        for i in 0..n {
            q[i + n * j] /= norm;
        }
    }
    q
}

/// Orthonormal basis (column-major `n x (n-1)`) of `{v : c . v = 0}`: the
/// last `n - 1` columns of the Householder reflector mapping `c` to a
/// multiple of `e_1`.
fn null_basis(c: &[f64]) -> Vec<f64> {
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
fn reduce(n: usize, a: &[f64], z: &[f64]) -> Vec<f64> {
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

/// An observer that counts points and checks nothing (allocation tests).
struct Tally {
    points: usize,
    events: usize,
    folds: usize,
}

impl PathObserver for Tally {
    fn point(&mut self, _: &PathPoint<'_>) -> Control {
        self.points += 1;
        Control::Continue
    }
    fn event(&mut self, e: &PathEvent<'_>) {
        self.events += 1;
        if e.kind == EventKind::Fold && e.located {
            self.folds += 1;
        }
    }
}

mod allocations;
mod chain;
mod inertia;
mod rotated;
mod snap;

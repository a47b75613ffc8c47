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
#[path = "../common/reduced.rs"]
mod reduced;
use reduced::{null_basis, reduce};

// ------------------------------------------------------------- helpers

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

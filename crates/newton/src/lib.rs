//! Newton-type solvers for smooth minimisation and equation problems.
//!
//! This crate knows nothing about the physics it serves: it minimises an
//! objective given through the [`Energy`] / [`Gradient`] / [`Hessian`]
//! traits, and solves bordered systems (an equilibrium plus one scalar
//! target equation with the load as an extra unknown) given through
//! [`Bordered`]. It is built for many small, repeated, warm-started solves:
//! a [`Newton`] workspace is allocated once and reused, iterations do not
//! allocate, and the problem factorises its own Hessian ([`LinearSystem`]),
//! so the solvers never hold an `n x n` matrix.
//!
//! * [`Newton`] — Newton with a shifted Cholesky (descent even where the
//!   Hessian is indefinite) and Armijo backtracking (with one cubic step
//!   towards the minimum along the direction), on the problem's own
//!   linear algebra ([`Hessian`], [`LinearSystem`]).
//! * [`BorderedNewton`] — an equilibrium plus one target equation with the
//!   load as an extra unknown, by block elimination.
//! * [`Semiseparable`] — block-diagonal plus rank-one semiseparable
//!   symmetric matrices (chains), factorised and solved in linear time, with
//!   their inertia.
//! * [`continuation()`] — adaptive parameter stepping with a secant predictor.
//! * [`Palc`] — pseudo-arclength continuation of an equilibrium path
//!   ([`Path`]) through limit points, with fold and stability (inertia)
//!   events located along the way; [`restricted_inertia`] — the inertia of
//!   a Hessian on a constraint's tangent space (stability of target
//!   solves, also [`BorderedNewton::last_restricted_inertia`]).
//!
//! The feature `dense` (for tests and benches only) adds the dense
//! reference path: `Dense` wraps problems that write a dense Hessian, with
//! faer's factorisations, and `negative_eigenvalues` / `min_eigenvalue`
//! count a dense symmetric matrix's spectrum.
//!
//! Solvers report why they stopped as data ([`Report`], [`Termination`]);
//! non-finite objective values are detected and never returned as
//! iterates. Option values are validated ([`OptionsError`]) and never
//! cause panics; mismatched dimensions are programmer errors and panic
//! with a message naming the argument.

#![warn(missing_docs)]

mod bordered;
mod continuation;
#[cfg(feature = "dense")]
mod dense;
mod linear;
mod newton;
mod options;
mod palc;
mod problem;
mod report;
mod semiseparable;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod testutil;

pub use bordered::{Bordered, BorderedEval, BorderedNewton, TargetTangent};
pub use continuation::{continuation, ContinuationReport};
#[cfg(feature = "dense")]
pub use dense::{
    min_eigenvalue, negative_eigenvalues, Dense, DenseBorderedProblem, DenseHessian, DenseMatrix,
    DensePathProblem,
};
pub use linear::{FactorError, Inertia};
pub use newton::Newton;
pub use options::{ContinuationOptions, NewtonOptions, OptionsError, PalcOptions};
pub use palc::{
    factor_restricted_inertia, restricted_inertia, BorderedPath, Branch, BranchEvent, BranchPoint,
    Control, Direction, EventKind, Palc, Path, PathEvent, PathObserver, PathPoint, PathReport,
    PathTermination, RestrictedInertiaError,
};
pub use problem::{Energy, Gradient, Hessian, LinearSystem};
pub use report::{Report, Termination};
pub use semiseparable::{PivotKind, Semiseparable, GROUP, MODIFIED_FLOOR};

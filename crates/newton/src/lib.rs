//! Newton-type solvers for smooth minimisation and equation problems.
//!
//! This crate knows nothing about the physics it serves: it minimises an
//! objective given through the [`Energy`] / [`Gradient`] / [`Hessian`]
//! traits, and solves bordered systems (an equilibrium plus one scalar
//! target equation with the load as an extra unknown) given through
//! [`Bordered`]. It is built for many small, repeated, warm-started solves
//! (dimensions of tens to a few hundred): a [`Newton`] workspace is
//! allocated once and reused, iterations do not allocate, and small
//! systems use an in-house dense Cholesky that beats general-purpose
//! libraries at that size (faer takes over for larger ones, see
//! [`LinearBackend`]).
//!
//! * [`Newton`] — Newton with a shifted Cholesky (descent even where the
//!   Hessian is indefinite) and Armijo backtracking, on the problem's own
//!   linear algebra ([`Hessian`], [`LinearSystem`]); [`Dense`] supplies it
//!   for problems that write a dense Hessian ([`DenseHessian`]).
//! * [`BorderedNewton`] — an equilibrium plus one target equation with the
//!   load as an extra unknown, by block elimination.
//! * [`Semiseparable`] — block-diagonal plus rank-one semiseparable
//!   symmetric matrices (chains), factorised and solved in linear time, with
//!   their inertia.
//! * [`Bfgs`] — gradient-only quasi-Newton, an independent cross-check.
//! * [`continuation()`] — adaptive parameter stepping with a secant predictor.
//! * [`Palc`] — pseudo-arclength continuation of an equilibrium path
//!   ([`Path`]) through limit points, with fold and stability (inertia)
//!   events located along the way; [`restricted_inertia`] — the inertia of
//!   a Hessian on a constraint's tangent space (stability of target
//!   solves, also [`BorderedNewton::last_restricted_inertia`]).
//! * [`cholesky_in_place`], [`lu_in_place`], [`min_eigenvalue`] — the
//!   dense kernels.
//!
//! Solvers report why they stopped as data ([`Report`], [`Termination`]);
//! non-finite objective values are detected and never returned as
//! iterates. Option values are validated ([`OptionsError`]) and never
//! cause panics; mismatched dimensions are programmer errors and panic
//! with a message naming the argument.

#![warn(missing_docs)]

mod bfgs;
mod bordered;
mod continuation;
mod dense;
mod linear;
mod newton;
mod options;
mod palc;
mod problem;
mod report;
mod semiseparable;
#[cfg(target_arch = "x86_64")]
mod simd;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod testutil;

pub use bfgs::Bfgs;
pub use bordered::{Bordered, BorderedEval, BorderedNewton, DenseBordered, DenseBorderedProblem};
pub use continuation::{continuation, ContinuationReport};
pub use dense::{
    cholesky_in_place, cholesky_solve, lu_in_place, lu_solve, min_eigenvalue, negative_eigenvalues,
    DenseError,
};
pub use linear::{FactorError, Inertia};
pub use newton::Newton;
pub use options::{
    BfgsOptions, ContinuationOptions, LinearBackend, NewtonOptions, OptionsError, PalcOptions,
    AUTO_DENSE_MAX_DIM,
};
pub use palc::{
    factor_restricted_inertia, restricted_inertia, BorderedPath, Branch, BranchEvent, BranchPoint,
    Control, DensePath, DensePathProblem, Direction, EventKind, Palc, Path, PathEvent,
    PathObserver, PathPoint, PathReport, PathTermination, RestrictedInertiaError,
};
pub use problem::{Dense, DenseHessian, DenseMatrix, Energy, Gradient, Hessian, LinearSystem};
pub use report::{Report, Termination};
pub use semiseparable::{PivotKind, Semiseparable};

//! The objective traits the solvers minimise.
//!
//! All vectors are `&[f64]` of length [`Energy::dim`]. A [`Hessian`]
//! problem keeps its Hessian in whatever form it likes (dense, banded,
//! [`Semiseparable`](crate::Semiseparable)...) and factorises and solves
//! with it itself, so the solvers never hold an `n x n` matrix: Newton's
//! work and storage are what the problem's structure allows.
//!
//! An objective signals a point where it cannot be evaluated by returning
//! a non-finite value (or writing one into `g`); the solvers detect this
//! and report [`Termination::NonFinite`](crate::Termination::NonFinite) or
//! backtrack, they never return a non-finite iterate.

use crate::linear::{FactorError, Inertia};
use crate::semiseparable::PivotKind;

/// An objective: value only.
pub trait Energy {
    /// Number of unknowns `n`.
    fn dim(&self) -> usize;
    /// The objective value at `x` (`x.len() == dim()`).
    fn energy(&mut self, x: &[f64]) -> f64;
}

/// Value and gradient.
pub trait Gradient: Energy {
    /// Writes the gradient at `x` into `g` (`g.len() == dim()`) and returns
    /// the value.
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64;
}

/// A symmetric matrix the problem holds, factorises and solves with.
pub trait LinearSystem {
    /// `(min_i H_ii, max_i |H_ii|)` of the matrix (for shift heuristics;
    /// Newton asks only after an unshifted factorisation has failed, so
    /// [`factor`](LinearSystem::factor) must leave the matrix as it was,
    /// as a shift to try again with requires anyway).
    fn diagonal_range(&self) -> (f64, f64);
    /// Factorises `H + tau I`, returning its inertia. With
    /// [`PivotKind::Cholesky`] it fails unless `H + tau I` is positive
    /// definite; with [`PivotKind::Symmetric`] unless it is nonsingular.
    /// [`FactorError::NonFinite`] when the matrix holds a non-finite entry.
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError>;
    /// Solves `(H + tau I) x = b` in place with the last successful
    /// factorisation.
    fn solve(&mut self, b: &mut [f64]);
    /// `out = H x` (no shift).
    fn apply(&self, x: &[f64], out: &mut [f64]);
}

/// Factorises `p` with no shift, Cholesky first (a positive definite
/// matrix, the common case, costs no symmetric pivoting) and symmetric
/// pivots where it is not positive definite; the inertia either way (a
/// successful Cholesky factorisation has no negative eigenvalue).
pub(crate) fn factor_cholesky_first<P: LinearSystem + ?Sized>(
    p: &mut P,
) -> Result<Inertia, FactorError> {
    match p.factor(0.0, PivotKind::Cholesky) {
        Ok(i) => Ok(i),
        Err(e @ FactorError::NonFinite { .. }) => Err(e),
        Err(_) => p.factor(0.0, PivotKind::Symmetric),
    }
}

/// Value, gradient and the Hessian, which the problem keeps (see
/// [`LinearSystem`]) until the next `hessian` call: `energy` and
/// `gradient` calls leave the Hessian and its factorisation alone (Newton's
/// chord steps solve with it at later points,
/// [`NewtonOptions::chord_steps`](crate::NewtonOptions::chord_steps)).
pub trait Hessian: Gradient + LinearSystem {
    /// Writes the gradient into `g`, keeps the Hessian at `x`, and returns
    /// the value.
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64;
    /// True when the problem keeps a new Hessian beside the last
    /// factorisation until the next [`factor`](LinearSystem::factor):
    /// after a `hessian` call, [`solve`](LinearSystem::solve) still solves
    /// with the factorisation made before it, while
    /// [`apply`](LinearSystem::apply) and
    /// [`diagonal_range`](LinearSystem::diagonal_range) act on the new
    /// Hessian. Newton then evaluates where a full step lands with its
    /// Hessian at once (instead of an energy first and the Hessian once
    /// the step is accepted) and can still take chord steps with the
    /// factorisation the step came from. False unless the problem says so.
    fn stages_hessian(&self) -> bool {
        false
    }
}

impl<P: Energy + ?Sized> Energy for &mut P {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        (**self).energy(x)
    }
}

impl<P: Gradient + ?Sized> Gradient for &mut P {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        (**self).gradient(x, g)
    }
}

impl<P: LinearSystem + ?Sized> LinearSystem for &mut P {
    fn diagonal_range(&self) -> (f64, f64) {
        (**self).diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        (**self).factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        (**self).solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        (**self).apply(x, out)
    }
}

impl<P: Hessian + ?Sized> Hessian for &mut P {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        (**self).hessian(x, g)
    }
    fn stages_hessian(&self) -> bool {
        (**self).stages_hessian()
    }
}

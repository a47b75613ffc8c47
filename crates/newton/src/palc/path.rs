//! The problems a [`Palc`](super::Palc) follows: the [`Path`] trait and its
//! [`Bordered`] adapter.

use crate::bordered::{Bordered, BorderedEval};
use crate::linear::{FactorError, Inertia};
use crate::problem::LinearSystem;
use crate::semiseparable::PivotKind;

/// A parametrised equilibrium `g(x, lambda) = 0` to follow: the Hessian
/// `H = d g / d x` of the last [`Path::eval`] is the problem's
/// [`LinearSystem`] (symmetric, possibly indefinite; the driver factorises
/// it with [`PivotKind::Symmetric`] and needs `apply` at the same point).
///
/// Evaluations should not allocate: the driver's own workspace is
/// allocated once, in [`Palc::new`](super::Palc::new).
pub trait Path: LinearSystem {
    /// Number of state unknowns `n` (the load `lambda` is extra).
    fn dim(&self) -> usize;
    /// Writes `g(x, lambda)` into `g` and `d g / d lambda` into `g_lambda`
    /// (both of length `n`) and keeps `H` at `(x, lambda)`. Returns `false`
    /// when the point cannot be evaluated; non-finite entries are detected
    /// by the driver. Either way the step is shortened and retried.
    fn eval(&mut self, x: &[f64], lambda: f64, g: &mut [f64], g_lambda: &mut [f64]) -> bool;

    /// The gradient `c_x` of a scalar constraint at the last evaluation,
    /// if the problem has one: the driver then reports, at every accepted
    /// point, the inertia of `H` on `{v : c_x . v = 0}` (the stability of
    /// the equilibrium with the constraint held, [`crate::restricted_inertia`]).
    /// None by default.
    fn constraint(&self) -> Option<&[f64]> {
        None
    }
}

impl<P: Path + ?Sized> Path for &mut P {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, g: &mut [f64], g_lambda: &mut [f64]) -> bool {
        (**self).eval(x, lambda, g, g_lambda)
    }
    fn constraint(&self) -> Option<&[f64]> {
        (**self).constraint()
    }
}

/// A [`Bordered`] problem as a [`Path`]: its `g`, `g_lambda` and `H` are
/// used, its target equation (`c`, `c_x`, `c_lambda`) is not imposed (the
/// arclength equation replaces it); its `c_x` is the path's constraint, so
/// every point reports its stability with the target held. Holds one [`BorderedEval`] (allocated
/// once).
pub struct BorderedPath<P> {
    /// The wrapped problem.
    pub problem: P,
    eval: BorderedEval,
}

impl<P: Bordered> BorderedPath<P> {
    /// Wraps `problem` (its `dim()` fixes the size).
    pub fn new(problem: P) -> BorderedPath<P> {
        let n = problem.dim();
        BorderedPath {
            problem,
            eval: BorderedEval::new(n),
        }
    }

    /// The last evaluation of the wrapped problem (its target equation
    /// included).
    pub fn last(&self) -> &BorderedEval {
        &self.eval
    }
}

impl<P: Bordered> Path for BorderedPath<P> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, g: &mut [f64], g_lambda: &mut [f64]) -> bool {
        let ok = self.problem.eval(x, lambda, &mut self.eval);
        g.copy_from_slice(&self.eval.g);
        g_lambda.copy_from_slice(&self.eval.g_lambda);
        ok
    }

    /// The target equation's `c_x`: the stability with the target held.
    fn constraint(&self) -> Option<&[f64]> {
        Some(&self.eval.c_x)
    }
}

impl<P: LinearSystem> LinearSystem for BorderedPath<P> {
    fn diagonal_range(&self) -> (f64, f64) {
        self.problem.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.problem.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.problem.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.problem.apply(x, out)
    }
}

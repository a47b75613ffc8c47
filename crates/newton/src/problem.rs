//! The objective traits the solvers minimise.
//!
//! All vectors are `&[f64]` of length [`Energy::dim`]; Hessians are dense,
//! column-major `n * n`. [`Newton::minimize`](crate::Newton::minimize) reads
//! only the lower triangle (diagonal included), so an objective may leave the
//! upper triangle unwritten; [`Newton::solve_bordered`](crate::Newton::solve_bordered)
//! and [`min_eigenvalue`](crate::min_eigenvalue) read the whole matrix. An objective signals a
//! point where it cannot be evaluated by returning a non-finite value (or
//! writing one into `g`/`h`); the solvers detect this and report
//! [`Termination::NonFinite`](crate::Termination::NonFinite) or backtrack,
//! they never return a non-finite iterate.

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

/// Value, gradient and the dense symmetric Hessian.
pub trait Hessian: Gradient {
    /// Writes the gradient into `g` and the Hessian, column-major `n * n`,
    /// into `h` (at least the lower triangle; see the module docs); returns
    /// the value.
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64;

    /// Optionally solves `(h + tau I) p = -g` with structure the problem
    /// knows (for example unknowns that couple only within small blocks and
    /// can be condensed out). `h` and `g` are the last values this problem
    /// wrote. Return `None` to let [`Newton`](crate::Newton) use its dense
    /// Cholesky, `Some(true)` when `p` holds the solution and `h + tau I`
    /// is positive definite, `Some(false)` when it is not (Newton then tries
    /// a larger shift).
    fn solve_shifted(&mut self, h: &[f64], g: &[f64], tau: f64, p: &mut [f64]) -> Option<bool> {
        let _ = (h, g, tau, p);
        None
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

impl<P: Hessian + ?Sized> Hessian for &mut P {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        (**self).hessian(x, g, h)
    }
    fn solve_shifted(&mut self, h: &[f64], g: &[f64], tau: f64, p: &mut [f64]) -> Option<bool> {
        (**self).solve_shifted(h, g, tau, p)
    }
}

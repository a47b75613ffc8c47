//! The objective traits the solvers minimise.
//!
//! All vectors are `&[f64]` of length [`Energy::dim`]. A [`Hessian`]
//! problem keeps its Hessian in whatever form it likes (dense, banded,
//! [`Semiseparable`](crate::Semiseparable)...) and factorises and solves
//! with it itself, so the solvers never hold an `n x n` matrix: Newton's
//! work and storage are what the problem's structure allows. [`Dense`]
//! turns a problem that writes a dense Hessian ([`DenseHessian`]) into a
//! [`Hessian`] with an in-house dense Cholesky (faer above
//! [`AUTO_DENSE_MAX_DIM`](crate::AUTO_DENSE_MAX_DIM)).
//!
//! An objective signals a point where it cannot be evaluated by returning
//! a non-finite value (or writing one into `g`); the solvers detect this
//! and report [`Termination::NonFinite`](crate::Termination::NonFinite) or
//! backtrack, they never return a non-finite iterate.

use crate::dense::{cholesky_in_place, cholesky_solve, FaerCholesky, FaerLblt};
use crate::linear::{FactorError, Inertia};
use crate::options::LinearBackend;
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
    /// `(min_i H_ii, max_i |H_ii|)` of the matrix (for shift heuristics).
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

/// Value, gradient and the Hessian, which the problem keeps (see
/// [`LinearSystem`]) until the next `hessian` call: `energy` and
/// `gradient` calls leave the Hessian and its factorisation alone (Newton's
/// chord steps solve with it at later points,
/// [`NewtonOptions::chord_steps`](crate::NewtonOptions::chord_steps)).
pub trait Hessian: Gradient + LinearSystem {
    /// Writes the gradient into `g`, keeps the Hessian at `x`, and returns
    /// the value.
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64;
}

/// A problem that writes its Hessian as a dense matrix (wrap it in
/// [`Dense`] to minimise it).
pub trait DenseHessian: Gradient {
    /// Writes the gradient into `g` and the Hessian, column-major `n * n`,
    /// into `h` (at least the lower triangle, diagonal included); returns
    /// the value.
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64;
}

/// A dense symmetric matrix with its factorisation: the linear algebra of
/// [`Dense`] and [`DenseBordered`](crate::DenseBordered) (allocated once).
pub struct DenseMatrix {
    n: usize,
    backend: LinearBackend,
    h: Vec<f64>,
    l: Vec<f64>,
    /// `L B Lᵀ` (not Cholesky) in `l` after a symmetric factorisation.
    indefinite: bool,
    faer: FaerCholesky,
    lblt: FaerLblt,
}

impl DenseMatrix {
    /// An `n x n` zero matrix with the given Cholesky backend.
    pub fn new(n: usize, backend: LinearBackend) -> DenseMatrix {
        let backend = backend.resolve(n);
        DenseMatrix {
            n,
            backend,
            h: vec![0.0; n * n],
            l: vec![0.0; n * n],
            indefinite: false,
            faer: FaerCholesky::new(if backend == LinearBackend::Faer { n } else { 0 }),
            lblt: FaerLblt::new(n),
        }
    }

    /// The concrete backend (`Dense` or `Faer`) for this dimension.
    pub fn backend(&self) -> LinearBackend {
        self.backend
    }

    /// The matrix, column-major, to write (at least the lower triangle).
    pub fn matrix_mut(&mut self) -> &mut [f64] {
        &mut self.h
    }

    /// The matrix, column-major (the upper triangle completed from the
    /// lower).
    pub fn matrix(&mut self) -> &[f64] {
        let n = self.n;
        for j in 0..n {
            for i in j + 1..n {
                self.h[j + n * i] = self.h[i + n * j];
            }
        }
        &self.h
    }
}

impl LinearSystem for DenseMatrix {
    fn diagonal_range(&self) -> (f64, f64) {
        let n = self.n;
        (0..n).fold((f64::INFINITY, 0.0f64), |(lo, hi), i| {
            let d = self.h[i * (n + 1)];
            (lo.min(d), hi.max(d.abs()))
        })
    }

    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        let n = self.n;
        match kind {
            PivotKind::Cholesky => {
                // lower triangle only
                for j in 0..n {
                    let r = j * n + j..j * n + n;
                    self.l[r.clone()].copy_from_slice(&self.h[r]);
                    self.l[j * (n + 1)] += tau;
                }
                self.indefinite = false;
                let ok = match self.backend {
                    LinearBackend::Faer => self.faer.factor(&mut self.l).is_ok(),
                    _ => cholesky_in_place(n, &mut self.l).is_ok(),
                };
                if ok {
                    Ok(Inertia {
                        positive: n,
                        negative: 0,
                    })
                } else if (0..n)
                    .any(|j| self.h[j * n + j..j * n + n].iter().any(|v| !v.is_finite()))
                {
                    Err(FactorError::NonFinite { block: 0 })
                } else {
                    Err(FactorError::NotPositiveDefinite { index: 0 })
                }
            }
            PivotKind::Symmetric => {
                self.matrix();
                self.l.copy_from_slice(&self.h);
                for i in 0..n {
                    self.l[i * (n + 1)] += tau;
                }
                if self.l.iter().any(|v| !v.is_finite()) {
                    return Err(FactorError::NonFinite { block: 0 });
                }
                // Bunch-Kaufman: the inertia without an eigenvalue solve
                let negative = self
                    .lblt
                    .factor(&mut self.l)
                    .map_err(|block| FactorError::Singular { block })?;
                self.indefinite = true;
                Ok(Inertia {
                    positive: n - negative,
                    negative,
                })
            }
        }
    }

    fn solve(&mut self, b: &mut [f64]) {
        let n = self.n;
        if self.indefinite {
            self.lblt.solve(&self.l, b);
            return;
        }
        match self.backend {
            LinearBackend::Faer => self.faer.solve(&self.l, b),
            _ => cholesky_solve(n, &self.l, b),
        }
    }

    fn apply(&self, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        // the lower triangle is authoritative
        for (i, o) in out.iter_mut().enumerate().take(n) {
            *o = x
                .iter()
                .enumerate()
                .map(|(j, xj)| {
                    let v = if i >= j {
                        self.h[i + n * j]
                    } else {
                        self.h[j + n * i]
                    };
                    v * xj
                })
                .sum();
        }
    }
}

/// A [`DenseHessian`] problem as a [`Hessian`]: holds the `n x n` matrix
/// and its factor (allocated once).
pub struct Dense<P> {
    /// The wrapped problem.
    pub problem: P,
    /// Its Hessian and factorisation.
    pub matrix: DenseMatrix,
}

impl<P: DenseHessian> Dense<P> {
    /// Wraps `problem` (its `dim()` fixes the size), with the
    /// [`LinearBackend::Auto`] choice of dense Cholesky.
    pub fn new(problem: P) -> Dense<P> {
        Dense::with_backend(problem, LinearBackend::Auto)
    }

    /// Wraps `problem` with a given dense Cholesky backend.
    pub fn with_backend(problem: P, backend: LinearBackend) -> Dense<P> {
        let n = problem.dim();
        Dense {
            problem,
            matrix: DenseMatrix::new(n, backend),
        }
    }
}

impl<P: DenseHessian> Energy for Dense<P> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.problem.energy(x)
    }
}

impl<P: DenseHessian> Gradient for Dense<P> {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.problem.gradient(x, g)
    }
}

impl<P: DenseHessian> Hessian for Dense<P> {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.problem.hessian(x, g, &mut self.matrix.h)
    }
}

impl<P> LinearSystem for Dense<P> {
    fn diagonal_range(&self) -> (f64, f64) {
        self.matrix.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.matrix.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.matrix.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.matrix.apply(x, out)
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
}

impl<P: DenseHessian + ?Sized> DenseHessian for &mut P {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        (**self).hessian(x, g, h)
    }
}

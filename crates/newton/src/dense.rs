//! The dense reference path of the tests and benches (feature `dense`):
//! problems that write their Hessian as a dense matrix, wrapped in
//! [`Dense`] to be minimised, followed or solved with a target, with faer
//! factorising the matrix (Cholesky; Bunch-Kaufman for the inertia of an
//! indefinite one), and the eigenvalues of dense symmetric matrices. The
//! solve path never uses it: its problems factorise their own structured
//! Hessians.
//!
//! Matrices are `n * n` column-major slices (entry `(i, j)` at
//! `h[i + j * n]`); a Hessian writes at least its lower triangle.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::{lblt, llt};
use faer::{MatMut, MatRef, Par, Side};

use crate::bordered::{Bordered, BorderedEval};
use crate::linear::{all_finite, FactorError, Inertia};
use crate::palc::Path;
use crate::problem::{Energy, Gradient, Hessian, LinearSystem};
use crate::semiseparable::{PivotKind, MODIFIED_FLOOR};

/// A problem that writes its Hessian as a dense matrix ([`Dense::new`]
/// makes it a [`Hessian`]).
pub trait DenseHessian: Gradient {
    /// Writes the gradient into `g` and the Hessian into `h`; returns the
    /// value.
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64;
}

impl<P: DenseHessian + ?Sized> DenseHessian for &mut P {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        (**self).hessian(x, g, h)
    }
}

/// A path problem that writes its Hessian densely ([`Dense::path`] makes
/// it a [`Path`]).
pub trait DensePathProblem {
    /// Number of state unknowns `n`.
    fn dim(&self) -> usize;
    /// As [`Path::eval`], with `H` written into `h`.
    fn eval(
        &mut self,
        x: &[f64],
        lambda: f64,
        g: &mut [f64],
        g_lambda: &mut [f64],
        h: &mut [f64],
    ) -> bool;
}

/// A bordered problem that writes its Hessian densely ([`Dense::bordered`]
/// makes it a [`Bordered`] problem).
pub trait DenseBorderedProblem {
    /// Number of state unknowns `n`.
    fn dim(&self) -> usize;
    /// As [`Bordered::eval`], with `H` written into `h`.
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval, h: &mut [f64]) -> bool;
}

/// A dense symmetric matrix and its faer factorisation, with every buffer
/// allocated once: factorising and solving do not allocate.
pub struct DenseMatrix {
    n: usize,
    h: Vec<f64>,
    /// The factor: `L Lᵀ`, or `P (H + tau I) Pᵀ = L B Lᵀ` when `indefinite`.
    l: Vec<f64>,
    indefinite: bool,
    /// `B`'s subdiagonal (its 2x2 blocks) and the permutation `P`.
    subdiag: Vec<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    mem: MemBuffer,
}

impl DenseMatrix {
    /// An `n x n` zero matrix.
    pub fn new(n: usize) -> DenseMatrix {
        let scratch = [
            llt::factor::cholesky_in_place_scratch::<f64>(n, Par::Seq, Default::default()),
            llt::solve::solve_in_place_scratch::<f64>(n, 1, Par::Seq),
            lblt::factor::cholesky_in_place_scratch::<usize, f64>(n, Par::Seq, Default::default()),
            lblt::solve::solve_in_place_scratch::<usize, f64>(n, 1, Par::Seq),
        ];
        DenseMatrix {
            n,
            h: vec![0.0; n * n],
            l: vec![0.0; n * n],
            indefinite: false,
            subdiag: vec![0.0; n],
            perm: vec![0; n],
            perm_inv: vec![0; n],
            mem: MemBuffer::new(scratch.into_iter().fold(Default::default(), |a, b| a.or(b))),
        }
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

    /// Whether the Bunch-Kaufman `D` (in `self.l`'s diagonal and
    /// `self.subdiag`) has a 2 x 2 block at row `i` (else 1 x 1).
    fn two_by_two(&self, i: usize) -> bool {
        i + 1 < self.n && self.subdiag[i] != 0.0
    }

    /// `D`'s block at row `i`: the eigenvalues `m +- r` of `[a s; s c]` and
    /// the angle of the first one's eigenvector (a 1 x 1 block: `a`, 0, 0).
    fn d_eigen(&self, i: usize) -> (f64, f64, f64) {
        let at = |i: usize| i * (self.n + 1);
        let a = self.l[at(i)];
        if !self.two_by_two(i) {
            return (a, 0.0, 0.0);
        }
        let (s, c) = (self.subdiag[i], self.l[at(i + 1)]);
        let r = (0.25 * (a - c) * (a - c) + s * s).sqrt();
        (0.5 * (a + c), r, 0.5 * (2.0 * s).atan2(a - c))
    }

    /// The `D` of `P H P^T = L D L^T` with every 1x1 and 2x2 block's
    /// eigenvalues replaced by their absolute values, floored at
    /// [`MODIFIED_FLOOR`] times the largest: the modified factorisation of
    /// [`PivotKind::Modified`] (Cheng and Higham's form, with `L` and `P`
    /// kept). Two passes over the blocks, no allocation.
    fn modify_d(&mut self) {
        let n = self.n;
        let at = |i: usize| i * (n + 1);
        let (mut scale, mut i) = (0.0f64, 0);
        while i < n {
            let (m, r, _) = self.d_eigen(i);
            scale = scale.max(m.abs() + r);
            i += 1 + usize::from(self.two_by_two(i));
        }
        let fix = |l: f64| l.abs().max(MODIFIED_FLOOR * scale);
        let mut i = 0;
        while i < n {
            let (m, r, theta) = self.d_eigen(i);
            if !self.two_by_two(i) {
                self.l[at(i)] = fix(m);
                i += 1;
                continue;
            }
            // Q diag(l1, l2) Q^T with Q the rotation by theta
            let (sn, cs) = theta.sin_cos();
            let (l1, l2) = (fix(m + r), fix(m - r));
            self.l[at(i)] = cs * cs * l1 + sn * sn * l2;
            self.l[at(i + 1)] = sn * sn * l1 + cs * cs * l2;
            self.subdiag[i] = sn * cs * (l1 - l2);
            // (a block whose two values came out equal is now diagonal)
            i += 2;
        }
    }

    /// The number of negative pivots of the Bunch-Kaufman factor `B`
    /// (Sylvester: `H + tau I`'s negative eigenvalues), or the first
    /// singular (or non-finite) pivot block.
    fn lblt_negative(&self) -> Result<usize, usize> {
        let d = |i: usize| self.l[i * (self.n + 1)];
        let (mut negative, mut i) = (0, 0);
        while i < self.n {
            if self.two_by_two(i) {
                // a 2x2 block [d_i s; s d_i+1]
                let s = self.subdiag[i];
                let det = d(i) * d(i + 1) - s * s;
                if !(det.is_finite() && det != 0.0) {
                    return Err(i);
                }
                negative += match (det < 0.0, d(i) + d(i + 1) < 0.0) {
                    (true, _) => 1,
                    (false, true) => 2,
                    (false, false) => 0,
                };
                i += 2;
            } else {
                if !(d(i).is_finite() && d(i) != 0.0) {
                    return Err(i);
                }
                negative += usize::from(d(i) < 0.0);
                i += 1;
            }
        }
        Ok(negative)
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
        self.matrix();
        self.l.copy_from_slice(&self.h);
        for i in 0..n {
            self.l[i * (n + 1)] += tau;
        }
        if !all_finite(&self.l) {
            return Err(FactorError::NonFinite { block: 0 });
        }
        let stack = MemStack::new(&mut self.mem);
        let l = MatMut::from_column_major_slice_mut(&mut self.l, n, n);
        self.indefinite = kind != PivotKind::Cholesky;
        let negative = match kind {
            PivotKind::Cholesky => {
                llt::factor::cholesky_in_place(
                    l,
                    Default::default(),
                    Par::Seq,
                    stack,
                    Default::default(),
                )
                .map_err(|llt::factor::LltError::NonPositivePivot { index }| {
                    FactorError::NotPositiveDefinite { index }
                })?;
                0
            }
            PivotKind::Symmetric | PivotKind::Modified => {
                let sub = faer::diag::DiagMut::from_slice_mut(&mut self.subdiag);
                lblt::factor::cholesky_in_place(
                    l,
                    sub,
                    &mut self.perm,
                    &mut self.perm_inv,
                    Par::Seq,
                    stack,
                    Default::default(),
                );
                if kind == PivotKind::Modified {
                    self.modify_d();
                }
                self.lblt_negative()
                    .map_err(|block| FactorError::Singular { block })?
            }
        };
        Ok(Inertia {
            positive: n - negative,
            negative,
        })
    }

    fn solve(&mut self, b: &mut [f64]) {
        let n = self.n;
        let l = MatRef::from_column_major_slice(&self.l, n, n);
        let rhs = MatMut::from_column_major_slice_mut(b, n, 1);
        let stack = MemStack::new(&mut self.mem);
        if !self.indefinite {
            llt::solve::solve_in_place(l, rhs, Par::Seq, stack);
            return;
        }
        lblt::solve::solve_in_place_with_conj(
            l,
            l.diagonal(),
            faer::diag::DiagRef::from_slice(&self.subdiag),
            faer::Conj::No,
            faer::perm::PermRef::new_checked(&self.perm, &self.perm_inv, n),
            rhs,
            Par::Seq,
            stack,
        );
    }

    fn apply(&self, x: &[f64], out: &mut [f64]) {
        let n = self.n;
        // the lower triangle is authoritative
        for (i, o) in out.iter_mut().enumerate().take(n) {
            *o = (0..n).map(|j| self.h[i.max(j) + n * i.min(j)] * x[j]).sum();
        }
    }
}

/// A problem that writes its Hessian densely, with that matrix: a
/// [`Hessian`] ([`DenseHessian`] problems, [`Dense::new`]), a [`Path`]
/// ([`DensePathProblem`]s, [`Dense::path`]) or a [`Bordered`] problem
/// ([`DenseBorderedProblem`]s, [`Dense::bordered`]).
pub struct Dense<P> {
    /// The wrapped problem.
    pub problem: P,
    /// Its Hessian and factorisation.
    pub matrix: DenseMatrix,
}

impl<P> Dense<P> {
    fn with_dim(n: usize, problem: P) -> Dense<P> {
        Dense {
            problem,
            matrix: DenseMatrix::new(n),
        }
    }
}

impl<P: DenseHessian> Dense<P> {
    /// Wraps a minimisation problem (its `dim()` fixes the size).
    pub fn new(problem: P) -> Dense<P> {
        Dense::with_dim(problem.dim(), problem)
    }
}

impl<P: DensePathProblem> Dense<P> {
    /// Wraps a path problem.
    pub fn path(problem: P) -> Dense<P> {
        Dense::with_dim(problem.dim(), problem)
    }
}

impl<P: DenseBorderedProblem> Dense<P> {
    /// Wraps a bordered problem.
    pub fn bordered(problem: P) -> Dense<P> {
        Dense::with_dim(problem.dim(), problem)
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

impl<P: DensePathProblem> Path for Dense<P> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, g: &mut [f64], g_lambda: &mut [f64]) -> bool {
        self.problem
            .eval(x, lambda, g, g_lambda, &mut self.matrix.h)
    }
}

impl<P: DenseBorderedProblem> Bordered for Dense<P> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval) -> bool {
        self.problem.eval(x, lambda, out, &mut self.matrix.h)
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

/// The eigenvalues of `(h + hᵀ) / 2` (faer's self-adjoint solver,
/// eigenvalues only), or `None` for a non-finite entry or no convergence.
/// Allocates `O(n^2)`.
fn eigenvalues(n: usize, h: &[f64]) -> Option<Vec<f64>> {
    assert_eq!(h.len(), n * n, "eigenvalues: h.len() must equal n * n");
    if !all_finite(h) {
        return None;
    }
    let m = faer::Mat::<f64>::from_fn(n, n, |i, j| 0.5 * (h[i + j * n] + h[j + i * n]));
    m.self_adjoint_eigenvalues(Side::Lower).ok()
}

/// The number of negative eigenvalues of the symmetric matrix `h`; `None`
/// for a non-finite entry or no convergence.
///
/// # Panics
/// If `h.len() != n * n`.
pub fn negative_eigenvalues(n: usize, h: &[f64]) -> Option<usize> {
    eigenvalues(n, h).map(|v| v.iter().filter(|&&l| l < 0.0).count())
}

/// The smallest eigenvalue of the symmetric matrix `h`: `+inf` for
/// `n == 0`, NaN for a non-finite entry or no convergence.
///
/// # Panics
/// If `h.len() != n * n`.
pub fn min_eigenvalue(n: usize, h: &[f64]) -> f64 {
    eigenvalues(n, h).map_or(f64::NAN, |v| v.into_iter().fold(f64::INFINITY, f64::min))
}

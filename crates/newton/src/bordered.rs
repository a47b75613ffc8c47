//! Bordered Newton solve: equilibrium plus one target equation, with the
//! load parameter `lambda` as an extra unknown.
//!
//! Solves `F(x, lambda) = (g(x, lambda), c(x, lambda)) = 0`, where `g` is
//! the energy gradient with respect to `x` and `c` a scalar target
//! residual (e.g. "tip displacement minus its target"). Each Newton step
//! solves the `(n+1) x (n+1)` bordered system
//!
//! ```text
//! [ H      g_lambda ] [dx     ]     [ g ]
//! [ c_x^T  c_lambda ] [dlambda] = - [ c ]
//! ```
//!
//! with an LU factorisation with partial pivoting ([`crate::lu_in_place`]),
//! because the matrix is unsymmetric and `H` may be indefinite (e.g. past a
//! limit point in load, which a displacement target passes smoothly).

use crate::dense::{all_finite, lu_in_place, lu_solve, norm_inf};
use crate::newton::Newton;
use crate::report::{Report, Termination};

/// One evaluation of a [`Bordered`] problem at `(x, lambda)`; reused
/// across evaluations (the solver preallocates two of them).
#[derive(Clone, Debug, PartialEq)]
pub struct BorderedEval {
    /// `n`: gradient of the energy with respect to `x` at `(x, lambda)`.
    pub g: Vec<f64>,
    /// `n * n`, column-major: Hessian of the energy with respect to `x`.
    pub h: Vec<f64>,
    /// `n`: `d g / d lambda`.
    pub g_lambda: Vec<f64>,
    /// Target residual, 0 at the solution.
    pub c: f64,
    /// `n`: `d c / d x`.
    pub c_x: Vec<f64>,
    /// `d c / d lambda`.
    pub c_lambda: f64,
}

impl BorderedEval {
    /// Zero-filled buffers for dimension `n`.
    pub fn new(n: usize) -> Self {
        Self {
            g: vec![0.0; n],
            h: vec![0.0; n * n],
            g_lambda: vec![0.0; n],
            c: 0.0,
            c_x: vec![0.0; n],
            c_lambda: 0.0,
        }
    }

    /// Dimension `n` (length of `g`).
    pub fn dim(&self) -> usize {
        self.g.len()
    }

    /// True when every entry is finite.
    pub fn is_finite(&self) -> bool {
        self.c.is_finite()
            && self.c_lambda.is_finite()
            && all_finite(&self.g)
            && all_finite(&self.g_lambda)
            && all_finite(&self.c_x)
            && all_finite(&self.h)
    }

    fn merit(&self) -> f64 {
        0.5 * (self.g.iter().map(|v| v * v).sum::<f64>() + self.c * self.c)
    }
}

/// A parametrised equilibrium problem with one target equation.
pub trait Bordered {
    /// Number of state unknowns `n` (the load `lambda` is extra).
    fn dim(&self) -> usize;
    /// Fills every field of `out` (whose buffers already have the right
    /// sizes) at `(x, lambda)`. Returns `false` if the point cannot be
    /// evaluated; non-finite entries are also detected by the solver.
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval) -> bool;
}

impl<P: Bordered + ?Sized> Bordered for &mut P {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, out: &mut BorderedEval) -> bool {
        (**self).eval(x, lambda, out)
    }
}

/// Preallocated buffers of [`Newton::solve_bordered`].
pub(crate) struct BorderedWork {
    jac: Vec<f64>,
    perm: Vec<usize>,
    rhs: Vec<f64>,
    xt: Vec<f64>,
    cur: BorderedEval,
    trial: BorderedEval,
}

impl BorderedWork {
    fn new(n: usize) -> Self {
        let m = n + 1;
        Self {
            jac: vec![0.0; m * m],
            perm: vec![0; m],
            rhs: vec![0.0; m],
            xt: vec![0.0; n],
            cur: BorderedEval::new(n),
            trial: BorderedEval::new(n),
        }
    }
}

fn evaluate<P: Bordered + ?Sized>(
    p: &mut P,
    x: &[f64],
    lambda: f64,
    out: &mut BorderedEval,
) -> bool {
    p.eval(x, lambda, out) && out.is_finite()
}

impl Newton {
    /// Solves `g(x, lambda) = 0, c(x, lambda) = 0` for `x` and `lambda`
    /// by Newton's method on the bordered Jacobian, globalised by
    /// backtracking on the merit `phi = ||F||^2 / 2` (Armijo test
    /// `phi_t <= (1 - 2 c1 alpha) phi`, safeguarded quadratic
    /// interpolation; each trial point costs a full [`Bordered::eval`]).
    ///
    /// `x` and `lambda` are the start on input and the result on output (on
    /// failure: the last accepted iterate). Uses the same options as
    /// [`Newton::minimize`]: converged when `||g||_inf <= gtol` and `|c| <=
    /// ctol`; `max_iter`, `xtol` (on the step in `(x, lambda)`), `c1` and
    /// `min_step_fraction` as there. `Singular` is reported when an LU pivot
    /// is exactly zero or non-finite, or the Newton step is non-finite. No
    /// relative pivot threshold is applied (it would depend on the units of
    /// `x`, `lambda` and `c`): a nearly singular Jacobian gives a huge step,
    /// which backtracking shortens or rejects (`LineSearchFailed`).
    ///
    /// Like any Newton method for equations, this converges from starts
    /// near a solution (warm starts along a branch); from far away it can
    /// stall in a local minimum of the merit (`LineSearchFailed`).
    ///
    /// In the [`Report`], `energy` holds the final merit `phi`,
    /// `residual_norm` is `max(||g||_inf, |c|)`, `hessian_evals` counts
    /// `eval` calls, `factorizations` LU factorisations, and `energy_evals`,
    /// `gradient_evals`, `max_shift` are 0.
    ///
    /// The `(n+1)^2` workspace is allocated on the first call and reused.
    ///
    /// # Panics
    /// If `x.len()` or `p.dim()` differ from the dimension given to
    /// [`Newton::new`] (programmer error).
    pub fn solve_bordered<P: Bordered + ?Sized>(
        &mut self,
        p: &mut P,
        x: &mut [f64],
        lambda: &mut f64,
    ) -> Report {
        let (n, opts, valid, slot) = self.parts();
        assert_eq!(
            x.len(),
            n,
            "Newton::solve_bordered: x.len() must equal the dimension given to Newton::new"
        );
        assert_eq!(
            p.dim(),
            n,
            "Newton::solve_bordered: problem dim() must equal the dimension given to Newton::new"
        );
        if !valid {
            return Report::empty(Termination::InvalidInput);
        }
        let o = *opts;
        let w = slot.get_or_insert_with(|| BorderedWork::new(n));
        let m = n + 1;
        let mut rep = Report::empty(Termination::Converged);

        rep.hessian_evals += 1;
        if !lambda.is_finite() || !evaluate(p, x, *lambda, &mut w.cur) {
            rep.reason = Termination::NonFinite;
            return rep;
        }
        let mut phi = w.cur.merit();

        loop {
            let gnorm = norm_inf(&w.cur.g);
            let cabs = w.cur.c.abs();
            rep.energy = phi;
            rep.residual_norm = gnorm.max(cabs);
            if gnorm <= o.gtol && cabs <= o.ctol {
                rep.reason = Termination::Converged;
                break;
            }
            if rep.iterations >= o.max_iter {
                rep.reason = Termination::MaxIterations;
                break;
            }
            // Assemble J = [[H, g_lambda], [c_x^T, c_lambda]] column-major.
            for j in 0..n {
                let col = &mut w.jac[j * m..j * m + m];
                col[..n].copy_from_slice(&w.cur.h[j * n..j * n + n]);
                col[n] = w.cur.c_x[j];
            }
            {
                let col = &mut w.jac[n * m..n * m + m];
                col[..n].copy_from_slice(&w.cur.g_lambda);
                col[n] = w.cur.c_lambda;
            }
            rep.factorizations += 1;
            if lu_in_place(m, &mut w.jac, &mut w.perm).is_err() {
                rep.reason = Termination::Singular;
                break;
            }
            for (r, gi) in w.rhs.iter_mut().zip(&w.cur.g) {
                *r = -gi;
            }
            w.rhs[n] = -w.cur.c;
            lu_solve(m, &w.jac, &w.perm, &mut w.rhs);
            if !all_finite(&w.rhs) {
                rep.reason = Termination::Singular;
                break;
            }

            // Backtracking on phi along the Newton direction (phi'(0) = -2 phi).
            let dphi0 = -2.0 * phi;
            let mut alpha = 1.0f64;
            let mut any_finite = false;
            let accepted = loop {
                for ((xt, xi), di) in w.xt.iter_mut().zip(x.iter()).zip(&w.rhs) {
                    *xt = xi + alpha * di;
                }
                let lt = *lambda + alpha * w.rhs[n];
                rep.hessian_evals += 1;
                if lt.is_finite() && evaluate(p, &w.xt, lt, &mut w.trial) {
                    any_finite = true;
                    let phit = w.trial.merit();
                    if phit <= phi + o.c1 * alpha * dphi0 {
                        break Ok((alpha, lt, phit));
                    }
                    let denom = 2.0 * (phit - phi - dphi0 * alpha);
                    let aq = if denom > 0.0 {
                        -dphi0 * alpha * alpha / denom
                    } else {
                        0.5 * alpha
                    };
                    alpha = aq.clamp(0.1 * alpha, 0.5 * alpha);
                } else {
                    alpha *= 0.25;
                }
                if alpha < o.min_step_fraction {
                    break Err(if any_finite {
                        Termination::LineSearchFailed
                    } else {
                        Termination::NonFinite
                    });
                }
            };
            let (alpha, lt, phit) = match accepted {
                Ok(a) => a,
                Err(reason) => {
                    rep.reason = reason;
                    break;
                }
            };
            x.copy_from_slice(&w.xt);
            *lambda = lt;
            core::mem::swap(&mut w.cur, &mut w.trial);
            phi = phit;
            rep.iterations += 1;
            rep.step_norm = alpha * norm_inf(&w.rhs);
            let gnorm = norm_inf(&w.cur.g);
            let cabs = w.cur.c.abs();
            let converged = gnorm <= o.gtol && cabs <= o.ctol;
            if !converged && rep.step_norm <= o.xtol * (1.0 + norm_inf(x).max(lambda.abs())) {
                rep.energy = phi;
                rep.residual_norm = gnorm.max(cabs);
                rep.reason = Termination::StepTolerance;
                break;
            }
        }
        rep
    }
}

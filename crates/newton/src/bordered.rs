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
//! by block elimination on the problem's own factorisation of `H`
//! ([`LinearSystem`]: Cholesky where `H` is positive definite, the common
//! case, and symmetric pivots where it is not, so `H` may be indefinite, as
//! past a limit point in load, which a displacement target passes smoothly):
//! `a = -H^-1 g`, `b = -H^-1 g_lambda`,
//! `dlambda = -(c + c_x.a) / (c_lambda + c_x.b)`, `dx = a + b dlambda`, followed by one step of iterative
//! refinement on the whole bordered system (with `H` applied exactly), which
//! recovers the accuracy the elimination loses when `H` is nearly singular.
//! The solver holds no `n x n` matrix: work and storage are those of the
//! problem's factorisation.

use crate::linear::{all_finite, dot, norm_inf, Inertia};
use crate::options::{NewtonOptions, OptionsError};
use crate::problem::LinearSystem;
use crate::report::{Report, Termination};

/// One evaluation of a [`Bordered`] problem at `(x, lambda)`, besides the
/// Hessian the problem keeps; reused across evaluations.
#[derive(Clone, Debug, PartialEq)]
pub struct BorderedEval {
    /// `n`: gradient of the energy with respect to `x` at `(x, lambda)`.
    pub g: Vec<f64>,
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
    }

    fn merit(&self) -> f64 {
        0.5 * (self.g.iter().map(|v| v * v).sum::<f64>() + self.c * self.c)
    }
}

/// A parametrised equilibrium problem with one target equation; the
/// Hessian `H = d g / d x` of the last [`Bordered::eval`] is the problem's
/// [`LinearSystem`].
pub trait Bordered: LinearSystem {
    /// Number of state unknowns `n` (the load `lambda` is extra).
    fn dim(&self) -> usize;
    /// Fills every field of `out` (whose buffers already have the right
    /// sizes) at `(x, lambda)` and keeps `H` there. Returns `false` if the
    /// point cannot be evaluated. Non-finite entries of `out` are detected
    /// by the solver (the point is backtracked from); a non-finite `H` is
    /// detected when it is factorised and ends the solve with
    /// [`Termination::NonFinite`].
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

/// The bordered Newton solver and its workspace (all `O(n)`).
#[derive(Debug, Clone)]
pub struct BorderedNewton {
    n: usize,
    opts: NewtonOptions,
    a: Vec<f64>,
    b: Vec<f64>,
    r: Vec<f64>,
    hx: Vec<f64>,
    dx: Vec<f64>,
    xt: Vec<f64>,
    cur: BorderedEval,
    trial: BorderedEval,
    inertia: Option<Inertia>,
    /// The Schur complement `c_lambda - c_x . H^-1 g_lambda` of the last
    /// factorisation (its sign with that of `det H` orients the solution
    /// curve in the target).
    den: Option<f64>,
}

/// Factorises `H`: Cholesky first (a positive definite `H`, the common
/// case, costs no symmetric pivoting), symmetric pivots when it is not
/// positive definite; maps failures to the solver's terminations.
fn factor_h<P: LinearSystem + ?Sized>(p: &mut P) -> Result<Inertia, Termination> {
    crate::problem::factor_cholesky_first(p).map_err(|e| match e {
        crate::FactorError::NonFinite { .. } => Termination::NonFinite,
        _ => Termination::Singular,
    })
}

/// The tangent of the solution curve of a bordered problem with respect to
/// its target (see [`BorderedNewton::target_tangent`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TargetTangent {
    /// `d lambda / d s` for the target equation `c(x, lambda) = s`.
    pub dlambda: f64,
    /// The inertia of `H` at the point.
    pub inertia: Inertia,
    /// The orientation of the curve: the sign (+1 or -1) of the bordered
    /// Jacobian's determinant, `sign(det H) * sign(c_lambda - c_x . H^-1
    /// g_lambda)`. It is constant along a curve parametrised by the target
    /// and changes sign at a fold in the target (where the target turns
    /// back); a limit point in `lambda` leaves it unchanged (`det H` and
    /// the Schur complement change sign together there).
    pub orientation: f64,
}

impl TargetTangent {
    fn new(den: f64, inertia: Inertia) -> TargetTangent {
        let det_h = if inertia.negative.is_multiple_of(2) {
            1.0
        } else {
            -1.0
        };
        TargetTangent {
            dlambda: 1.0 / den,
            inertia,
            orientation: det_h * den.signum(),
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

impl BorderedNewton {
    /// A solver for `n` state unknowns.
    pub fn new(n: usize, opts: NewtonOptions) -> Result<BorderedNewton, OptionsError> {
        opts.validate()?;
        Ok(BorderedNewton {
            n,
            opts,
            a: vec![0.0; n],
            b: vec![0.0; n],
            r: vec![0.0; n],
            hx: vec![0.0; n],
            dx: vec![0.0; n],
            xt: vec![0.0; n],
            cur: BorderedEval::new(n),
            trial: BorderedEval::new(n),
            inertia: None,
            den: None,
        })
    }

    /// Replaces the options (validated; on error the old ones stay).
    pub fn set_options(&mut self, opts: NewtonOptions) -> Result<(), OptionsError> {
        opts.validate()?;
        self.opts = opts;
        Ok(())
    }

    /// The last evaluation (at the returned point after a solve).
    pub fn last(&self) -> &BorderedEval {
        &self.cur
    }

    /// The inertia of `H` at the last factorisation (the last Newton step,
    /// one evaluation before the returned point), if any.
    pub fn last_inertia(&self) -> Option<Inertia> {
        self.inertia
    }

    /// The curve's orientation and `d lambda / d s` at the last
    /// factorisation (the last Newton step, one evaluation before the
    /// returned point), if a step was taken ([`TargetTangent`]).
    pub fn last_tangent(&self) -> Option<TargetTangent> {
        Some(TargetTangent::new(self.den?, self.inertia?))
    }

    /// The tangent `dx/ds` of the solution curve (the target equation
    /// shifted to `c(x, lambda) = s`) at the last factorisation (the last
    /// Newton step, one evaluation before the returned point), into `dx`;
    /// `d lambda / d s` is [`TargetTangent::dlambda`] of
    /// [`BorderedNewton::last_tangent`]. A predictor for the next point of a
    /// continuation in the target, at no extra cost. `false` (and `dx`
    /// untouched) when no step was taken.
    ///
    /// # Panics
    /// If `dx.len()` differs from the dimension (programmer error).
    pub fn last_tangent_dx(&self, dx: &mut [f64]) -> bool {
        assert_eq!(
            dx.len(),
            self.n,
            "BorderedNewton::last_tangent_dx: dx.len()"
        );
        match self.den {
            Some(den) if den != 0.0 && den.is_finite() => {
                for (d, b) in dx.iter_mut().zip(&self.b) {
                    *d = b / den;
                }
                true
            }
            _ => false,
        }
    }

    /// The tangent of the solution curve at `(x, lambda)` with respect to
    /// the target: with the target equation shifted to `c(x, lambda) = s`,
    /// `dx/ds` is written to `dx` and `d lambda / d s`, the inertia of `H`
    /// and the curve's orientation are returned. One evaluation and one
    /// factorisation (Cholesky first), two solves with one step of
    /// refinement each. `Err` when the point cannot be evaluated
    /// (`NonFinite`) or `H` or the bordered matrix is singular there.
    ///
    /// # Panics
    /// If `x.len()`, `dx.len()` or `p.dim()` differ from the dimension given
    /// to [`BorderedNewton::new`] (programmer error).
    pub fn target_tangent<P: Bordered + ?Sized>(
        &mut self,
        p: &mut P,
        x: &[f64],
        lambda: f64,
        dx: &mut [f64],
    ) -> Result<TargetTangent, Termination> {
        let n = self.n;
        assert!(
            x.len() == n && dx.len() == n && p.dim() == n,
            "BorderedNewton::target_tangent: dimensions must equal the one given to BorderedNewton::new"
        );
        if !lambda.is_finite() || !evaluate(p, x, lambda, &mut self.cur) {
            return Err(Termination::NonFinite);
        }
        let inertia = factor_h(p)?;
        // b = -H^-1 g_lambda, refined once
        for (b, g) in self.b.iter_mut().zip(&self.cur.g_lambda) {
            *b = -g;
        }
        p.solve(&mut self.b);
        p.apply(&self.b, &mut self.hx);
        for i in 0..n {
            self.r[i] = -self.cur.g_lambda[i] - self.hx[i];
        }
        p.solve(&mut self.r);
        for (b, r) in self.b.iter_mut().zip(&self.r) {
            *b += r;
        }
        let den = self.cur.c_lambda + dot(&self.cur.c_x, &self.b);
        if !(den.is_finite() && den != 0.0 && all_finite(&self.b)) {
            return Err(Termination::Singular);
        }
        for (d, b) in dx.iter_mut().zip(&self.b) {
            *d = b / den;
        }
        self.inertia = Some(inertia);
        self.den = Some(den);
        Ok(TargetTangent::new(den, inertia))
    }

    /// The inertia of `H` restricted to the tangent space `{v : c_x . v =
    /// 0}` of the target equation at the returned point: the stability of
    /// the target-constrained equilibrium (no negative count: a strict
    /// local minimum of the energy on the constraint). See
    /// [`restricted_inertia`](crate::restricted_inertia) for the method and
    /// its errors.
    ///
    /// Call it right after a converged [`BorderedNewton::solve`] with the
    /// problem just solved: its Hessian is then the one at the returned
    /// point (the last evaluation), which this factorises once more
    /// (Cholesky first, symmetric pivots when `H` is not positive definite;
    /// not counted in the solve's report: a problem may invalidate its
    /// factorisation on evaluation, and the solve's last factorisation is
    /// one Newton step before the returned point). `c_x` is that of
    /// [`BorderedNewton::last`].
    /// Allocates nothing.
    pub fn last_restricted_inertia<P: LinearSystem + ?Sized>(
        &mut self,
        p: &mut P,
    ) -> Result<Inertia, crate::RestrictedInertiaError> {
        let inertia = crate::problem::factor_cholesky_first(p)
            .map_err(crate::RestrictedInertiaError::Hessian)?;
        crate::palc::restricted_inertia_with(p, inertia, &self.cur.c_x, &mut self.r, &mut self.hx)
    }

    /// Solves the bordered system at the problem's current evaluation
    /// (`self.cur`) for the Newton step: `dx` in `self.dx`, returns
    /// `dlambda`; `Err(NonFinite)` when `H` holds a non-finite entry,
    /// `Err(Singular)` when it cannot be factorised otherwise or the step
    /// is not finite.
    fn step<P: Bordered + ?Sized>(
        &mut self,
        p: &mut P,
        rep: &mut Report,
    ) -> Result<f64, Termination> {
        rep.factorizations += 1;
        self.inertia = Some(factor_h(p)?);
        let e = &self.cur;
        for (a, g) in self.a.iter_mut().zip(&e.g) {
            *a = -g;
        }
        p.solve(&mut self.a);
        for (b, g) in self.b.iter_mut().zip(&e.g_lambda) {
            *b = -g;
        }
        p.solve(&mut self.b);
        let den = e.c_lambda + dot(&e.c_x, &self.b);
        self.den = Some(den);
        let mut dl = -(e.c + dot(&e.c_x, &self.a)) / den;
        for ((d, a), b) in self.dx.iter_mut().zip(&self.a).zip(&self.b) {
            *d = a + b * dl;
        }
        // one step of iterative refinement on the bordered system
        p.apply(&self.dx, &mut self.hx);
        for i in 0..self.n {
            self.r[i] = -(self.hx[i] + e.g_lambda[i] * dl + e.g[i]);
        }
        let rc = -(dot(&e.c_x, &self.dx) + e.c_lambda * dl + e.c);
        p.solve(&mut self.r);
        let ddl = (rc - dot(&e.c_x, &self.r)) / den;
        for ((d, r), b) in self.dx.iter_mut().zip(&self.r).zip(&self.b) {
            *d += r + b * ddl;
        }
        dl += ddl;
        if dl.is_finite() && all_finite(&self.dx) {
            Ok(dl)
        } else {
            Err(Termination::Singular)
        }
    }

    /// Solves `g(x, lambda) = 0, c(x, lambda) = 0` for `x` and `lambda`
    /// by Newton's method on the bordered Jacobian, globalised by
    /// backtracking on the merit `phi = ||F||^2 / 2` (Armijo test
    /// `phi_t <= (1 - 2 c1 alpha) phi`, safeguarded quadratic
    /// interpolation; each trial point costs a full [`Bordered::eval`]).
    ///
    /// `x` and `lambda` are the start on input and the result on output (on
    /// failure: the last accepted iterate). Uses the same options as
    /// [`Newton::minimize`](crate::Newton::minimize): converged when
    /// `||g||_inf <= gtol` and `|c| <= ctol`; `max_iter`, `xtol` (on the step
    /// in `(x, lambda)`), `c1` and `min_step_fraction` as there. `Singular`
    /// is reported when `H` cannot be factorised (a singular pivot) or the
    /// step is not finite; a nearly singular system gives a huge step,
    /// which backtracking shortens or rejects (`LineSearchFailed`).
    ///
    /// Like any Newton method for equations, this converges from starts
    /// near a solution (warm starts along a branch); from far away it can
    /// stall in a local minimum of the merit (`LineSearchFailed`).
    ///
    /// In the [`Report`], `energy` holds the final merit `phi`,
    /// `residual_norm` is `max(||g||_inf, |c|)`, `hessian_evals` counts
    /// `eval` calls, `factorizations` factorisations of `H`, and `energy_evals`,
    /// `gradient_evals`, `max_shift` are 0.
    ///
    /// # Panics
    /// If `x.len()` or `p.dim()` differ from the dimension given to
    /// [`BorderedNewton::new`] (programmer error).
    pub fn solve<P: Bordered + ?Sized>(
        &mut self,
        p: &mut P,
        x: &mut [f64],
        lambda: &mut f64,
    ) -> Report {
        let n = self.n;
        assert_eq!(
            x.len(),
            n,
            "BorderedNewton::solve: x.len() must equal the dimension given to BorderedNewton::new"
        );
        assert_eq!(
            p.dim(),
            n,
            "BorderedNewton::solve: problem dim() must equal the dimension given to BorderedNewton::new"
        );
        let o = self.opts;
        let mut rep = Report::empty(Termination::Converged);
        self.inertia = None;
        self.den = None;

        rep.hessian_evals += 1;
        if !lambda.is_finite() || !evaluate(p, x, *lambda, &mut self.cur) {
            rep.reason = Termination::NonFinite;
            return rep;
        }
        let mut phi = self.cur.merit();

        loop {
            let gnorm = norm_inf(&self.cur.g);
            let cabs = self.cur.c.abs();
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
            let dl = match self.step(p, &mut rep) {
                Ok(dl) => dl,
                Err(reason) => {
                    rep.reason = reason;
                    break;
                }
            };
            // Backtracking on phi along the Newton direction (phi'(0) = -2 phi).
            let dphi0 = -2.0 * phi;
            let mut alpha = 1.0f64;
            let mut any_finite = false;
            let accepted = loop {
                for ((xt, xi), di) in self.xt.iter_mut().zip(x.iter()).zip(&self.dx) {
                    *xt = xi + alpha * di;
                }
                let lt = *lambda + alpha * dl;
                rep.hessian_evals += 1;
                if lt.is_finite() && evaluate(p, &self.xt, lt, &mut self.trial) {
                    any_finite = true;
                    let phit = self.trial.merit();
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
            x.copy_from_slice(&self.xt);
            *lambda = lt;
            core::mem::swap(&mut self.cur, &mut self.trial);
            phi = phit;
            rep.iterations += 1;
            rep.step_norm = alpha * norm_inf(&self.dx).max(dl.abs());
            let gnorm = norm_inf(&self.cur.g);
            let cabs = self.cur.c.abs();
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

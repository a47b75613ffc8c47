//! Newton's method with a shifted Cholesky and Armijo backtracking.

use crate::linear::{all_finite, norm_inf};
use crate::options::{NewtonOptions, OptionsError};
use crate::problem::Hessian;
use crate::report::{Report, Termination};

mod chord;
mod line_search;
mod shift;

/// Energy differences below `ROUNDOFF_FACTOR * eps * |f|` are treated as
/// round-off (see [`Newton::minimize`]).
const ROUNDOFF_FACTOR: f64 = 1e3;

/// A chord step is tried only while the last step reduced the gradient
/// norm by at least this factor (see [`NewtonOptions::chord_steps`]).
const CHORD_RATIO: f64 = 0.1;

/// Chord steps continue while at most this many more are expected to reach
/// `gtol` (a chord step costs about half a Newton step here); the
/// gradient-only landing of a predicted full step is tried when at most
/// two more are expected beyond it (the prediction is pessimistic).
const CHORD_STEPS_AHEAD: i32 = 2;

/// A full line-search step starts chord steps when its actual decrease is
/// within this fraction of the quadratic model's (see
/// [`NewtonOptions::chord_steps`]).
const MODEL_FIT: f64 = 1e-2;

/// The step cap grows at most to this multiple of
/// [`NewtonOptions::max_step`] (see [`Newton::minimize`]).
const MAX_CAP_GROWTH: f64 = 16.0;

/// How [`Newton::direction`] made the Hessian positive definite.
enum Direction {
    /// Shifted by `tau` (0: the Hessian as it is).
    Shifted(f64),
    /// By modified pivots ([`PivotKind::Modified`](crate::PivotKind::Modified)).
    Modified,
}

/// What [`Newton::land`] made of a full step.
enum Landing {
    /// Not accepted (the value where the step landed, which starts the
    /// line search): the iterate is unchanged.
    Rejected(f64),
    /// Accepted (and chord steps taken): value, gradient norm and the norm
    /// before the last step.
    Next((f64, f64, f64)),
    /// A non-finite Hessian where the chord steps stopped (the report says
    /// why).
    Failed,
    /// Accepted by Armijo with its Hessian, for an ordinary Newton step
    /// (value there; its gradient in `gt`); the iterate is unchanged.
    Accepted(f64),
}

/// Whether at most `steps` steps that each multiply gradient norm `g` by
/// `r` bring it to `gtol` (never unless `0 < r < 1`, where `g` is above
/// `gtol`): `g r^steps <= gtol`, the count `ln(gtol / g) / ln(r)` without
/// the logarithms.
fn reaches(g: f64, r: f64, gtol: f64, steps: i32) -> bool {
    g <= gtol || (r > 0.0 && r < 1.0 && g * r.powi(steps) <= gtol)
}

/// Newton minimiser and its reusable workspace.
///
/// `Newton::new(n, ..)` allocates the `O(n)` vectors a solve of dimension
/// `n` needs (gradient, direction, trial point); the Hessian, its
/// factorisation and their storage belong to the problem ([`Hessian`]), so
/// a structured problem never has an `n x n` matrix. [`Newton::minimize`]
/// then runs without heap allocation (if the problem's evaluations do not
/// allocate), so calling it repeatedly (e.g. along a continuation path)
/// costs only arithmetic and objective evaluations.
///
/// # Algorithm (`minimize`)
/// At the current iterate the full Hessian `H` is evaluated. The direction
/// solves `(H + tau I) p = -g` with a Cholesky factorisation; `tau = 0` is
/// tried first, and on failure (not positive definite, or `p` not a descent
/// direction) `tau` starts at `b - min(0, min_i H_ii)`, or at half the
/// previous iteration's shift if that is larger, and is doubled until the
/// factorisation succeeds (the problem's [`LinearSystem::factor`](crate::LinearSystem::factor)
/// with Cholesky pivots). Thus indefinite Hessians still give descent
/// directions, and near a non-degenerate minimum pure Newton steps (and
/// quadratic convergence) are recovered. The base shift is `b = 1e-3 s`
/// (with `s = max_i |H_ii|`, or 1 if that is 0), lowered under a finite
/// step cap to `|g|_inf / cap` (not below `1e-12 s`): a shift of
/// `1e-3 s` on a Hessian whose diagonal spans many orders of magnitude
/// makes steps `|g| / tau` far shorter than the cap along its soft
/// directions, and Newton crawls there (fpc's thick stacks under large tip
/// loads stalled just above the tolerance for 60 iterations, taking steps
/// of 3e-8 where the cap was 0.25); from the lower shift the doubling
/// finds about the least shift that factorises, whose step the cap and
/// the line search keep in hand.
///
/// With [`NewtonOptions::modified_pivots`], a Hessian that is not positive
/// definite is first factorised with [`PivotKind::Modified`](crate::PivotKind::Modified) (its negative
/// curvature turned positive, its positive curvature kept), and the shifts
/// follow only if the problem cannot do that. With
/// [`NewtonOptions::extend_modified`], a step along a shifted or modified
/// Hessian whose full length passes the line search is doubled (at most
/// twelve times, within the step cap) while the energy keeps falling and
/// Armijo holds. With [`NewtonOptions::step_growth`], the cap
/// [`NewtonOptions::max_step`] acts as a trust region's radius: a Newton
/// step (positive definite Hessian) shortened to it and taken whole
/// doubles it for the next step (up to 16 times
/// `max_step`), while a step the line search shortens, or a step along a
/// shifted or modified Hessian, resets it; a step shortened to the cap is
/// not taken for the quadratic phase. Backtracking then starts at the
/// full step (with its value, where a landing below evaluated it already),
/// evaluates only [`Energy::energy`](crate::Energy::energy) at
/// trial points, and accepts the first step fraction `alpha` with
/// `f(x + alpha p) <= f(x) + c1 alpha g^T p` (Armijo), safeguarded
/// quadratic interpolation (`alpha` shrinks by 0.1..0.5 per trial; by 0.25
/// after a non-finite trial value). A fraction found by backtracking is
/// then checked once: the minimiser of the cubic through `f(x)`, `g^T p`
/// and the last two trials' values is evaluated when it lies well between
/// them, and taken if its energy is lower (one more energy evaluation; a
/// tip load that turns the finger far makes the energy rise steeply past
/// its minimum along the step, where the quadratic estimate falls short
/// of it). The Hessian is evaluated only at accepted points.
///
/// Staged Hessians ([`Hessian::stages_hessian`], with
/// [`NewtonOptions::eager_full_steps`]): before the quadratic phase, the
/// point an unshifted step lands on (a step not shortened to the cap) is
/// evaluated with its Hessian at once. Accepted by Armijo, it is the next
/// iterate with its Hessian at hand: one evaluation instead of an energy
/// and then the Hessian. Where its decrease matched the quadratic model's
/// to 1 %, chord steps (below) follow with the factorisation the step came
/// from, which the problem keeps beside the new Hessian, and that Hessian
/// serves if they take no step. Rejected, its value starts the line
/// search. So the iterates are those of a problem that does not stage,
/// wherever its energy, gradient and Hessian evaluations give the same
/// value at a point; only the evaluations differ. (With a
/// [`NewtonOptions::chord_depth`] below 1 the first chord step after a
/// staged landing has one more condition, below, which a problem that
/// does not stage is not held to.)
///
/// Chord steps ([`NewtonOptions::chord_steps`], on by default): in the
/// quadratic phase, when the quadratic model predicts that the full step
/// cuts the gradient norm at least tenfold and that a few more such cuts
/// reach `gtol`; after a full unshifted step of the line search whose
/// energy decrease matched the quadratic model's to 1 %; and for the first
/// full step from a trusted start ([`NewtonOptions::trusted_start`]): only
/// the gradient is evaluated where the step lands. Then the next steps
/// solve with the factorisation already at hand (`p = -H_old^-1 g`, a
/// gradient and a solve each) for as long as the last cut was at least
/// tenfold and at most two more steps at that rate reach `gtol` (at most
/// four in all), and the Hessian is evaluated at the last accepted point
/// only if they stop short of convergence; with
/// [`NewtonOptions::chord_depth`] below 1 they go on, while each still
/// cuts the gradient tenfold, until it is that fraction of `gtol`. After
/// a landing whose Hessian is staged, the first chord step also needs two
/// more steps at the last cut's rate to reach that depth, not only `gtol`
/// (else the Newton step with the staged Hessian is taken: it costs a
/// factorisation, where slow chord steps to the depth cost more; with a
/// depth of 1 nothing changes). A chord step is accepted by
/// Armijo or by the round-off rule below, and only if it reduces the
/// gradient norm.
///
/// Accepted steps therefore strictly decrease the energy, with one
/// documented exception for the round-off regime close to a minimum, where
/// the predicted decrease is below the resolution of `f`: if Armijo fails
/// but `|f(x_t) - f(x)| <= 1e3 * eps * max(|f(x)|, |f(x_t)|)`, the trial is
/// accepted when its gradient norm is at most half the current one (one
/// extra [`Gradient::gradient`](crate::Gradient::gradient) call). An
/// energy "increase" on such a step is at most that round-off bound.
///
/// # Stopping
/// In this order, at each iterate: `||g||_inf <= gtol` → `Converged`;
/// `iterations >= max_iter` → `MaxIterations`; no shift gives a usable
/// factorisation → `Singular`; backtracking fails → `LineSearchFailed`
/// (`NonFinite` if every trial value was non-finite); after an accepted
/// step `s` with `||s||_inf <= xtol (1 + ||x||_inf)` and the gradient not
/// yet within `gtol` → `StepTolerance`.
///
/// Non-finite values: a non-finite value or gradient at the start →
/// `NonFinite` (x unchanged); from [`Hessian::hessian`] at an accepted
/// point → `NonFinite` with `x` restored to the previous iterate;
/// non-finite trial energies are backtracked from. A factorisation that
/// reports a non-finite Hessian entry ([`FactorError::NonFinite`](crate::FactorError::NonFinite)) →
/// `NonFinite` with `x` at the current iterate (finite energy and
/// gradient).
///
/// A start that is exactly stationary (`g = 0`, e.g. a saddle by symmetry)
/// is reported `Converged` at once; factorise the problem's Hessian with
/// symmetric pivots ([`LinearSystem::factor`](crate::LinearSystem::factor))
/// for its inertia to check stability.
pub struct Newton {
    n: usize,
    opts: NewtonOptions,
    valid: bool,
    g: Vec<f64>,
    p: Vec<f64>,
    xt: Vec<f64>,
    gt: Vec<f64>,
    xprev: Vec<f64>,
    /// The step cap in force (see [`Newton::descent`]).
    cap: f64,
    /// Whether the last direction was shortened to `cap`.
    capped: bool,
    /// `g^T p` and `||p||_inf` of the last direction ([`Newton::descent`]).
    gtp: f64,
    pnorm: f64,
}

impl core::fmt::Debug for Newton {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Newton")
            .field("n", &self.n)
            .field("opts", &self.opts)
            .finish_non_exhaustive()
    }
}

impl Newton {
    /// A solver for problems of dimension `n`, with all buffers allocated.
    ///
    /// Never panics: if `opts` is invalid (see [`NewtonOptions::validate`]),
    /// every solve returns [`Termination::InvalidInput`] without evaluating
    /// anything. Use [`Newton::try_new`] to get the error instead.
    pub fn new(n: usize, opts: NewtonOptions) -> Newton {
        let valid = opts.validate().is_ok();
        Newton {
            n,
            opts,
            valid,
            g: vec![0.0; n],
            p: vec![0.0; n],
            xt: vec![0.0; n],
            gt: vec![0.0; n],
            xprev: vec![0.0; n],
            cap: opts.max_step,
            capped: false,
            gtp: 0.0,
            pnorm: 0.0,
        }
    }

    /// Like [`Newton::new`], but rejects invalid options.
    pub fn try_new(n: usize, opts: NewtonOptions) -> Result<Newton, OptionsError> {
        opts.validate()?;
        Ok(Newton::new(n, opts))
    }

    /// The dimension this workspace was built for.
    pub fn dim(&self) -> usize {
        self.n
    }

    /// The options in use.
    pub fn options(&self) -> &NewtonOptions {
        &self.opts
    }

    /// Replaces the options (validated; on error the old ones stay).
    pub fn set_options(&mut self, opts: NewtonOptions) -> Result<(), OptionsError> {
        opts.validate()?;
        self.opts = opts;
        self.valid = true;
        Ok(())
    }

    /// The gradient at the `x` [`Newton::minimize`] returned (unless the
    /// solve ended `NonFinite`).
    pub fn gradient(&self) -> &[f64] {
        &self.g
    }

    /// Minimises `p` starting from `x`; on return `x` holds the result (on
    /// failure: the last accepted iterate, always finite if the start was).
    /// See the type-level docs for the algorithm and stopping rules.
    ///
    /// # Panics
    /// If `x.len()` or `p.dim()` differ from the dimension given to
    /// [`Newton::new`] (programmer error).
    pub fn minimize<P: Hessian + ?Sized>(&mut self, p: &mut P, x: &mut [f64]) -> Report {
        let n = self.n;
        assert_eq!(
            x.len(),
            n,
            "Newton::minimize: x.len() must equal the dimension given to Newton::new"
        );
        assert_eq!(
            p.dim(),
            n,
            "Newton::minimize: problem dim() must equal the dimension given to Newton::new"
        );
        if !self.valid {
            return Report::empty(Termination::InvalidInput);
        }
        let o = self.opts;
        let mut rep = Report::empty(Termination::Converged);

        let mut f = p.hessian(x, &mut self.g);
        rep.hessian_evals += 1;
        if !(f.is_finite() && all_finite(&self.g)) {
            rep.reason = Termination::NonFinite;
            return rep;
        }
        let mut gnorm = norm_inf(&self.g);
        let mut last_tau = 0.0;
        self.cap = o.max_step;
        // residual before the last accepted step, when that step was a full
        // unshifted Newton step (the quadratic phase); NaN otherwise
        let mut quadratic_prev = f64::NAN;

        loop {
            rep.energy = f;
            rep.residual_norm = gnorm;
            if gnorm <= o.gtol {
                rep.reason = Termination::Converged;
                break;
            }
            if rep.iterations >= o.max_iter {
                rep.reason = Termination::MaxIterations;
                break;
            }
            let (tau, plain) = match self.direction(p, last_tau, &mut rep) {
                Ok(Direction::Shifted(tau)) => (tau, tau == 0.0),
                Ok(Direction::Modified) => (0.0, false),
                Err(reason) => {
                    rep.reason = reason;
                    break;
                }
            };
            rep.max_shift = rep.max_shift.max(tau);
            last_tau = tau;
            let gtp = self.gtp;
            let chord = o.eager_full_steps && o.chord_steps;
            // A start known to be close (trusted_start): the first full step
            // is evaluated with its gradient, and chord steps follow at once
            // if it cut the gradient enough (else the Hessian there).
            let trusted = chord && o.trusted_start && rep.iterations == 0 && plain;
            // Otherwise, not yet in the quadratic phase, an unshifted step not
            // shortened to the cap, on a problem that stages its Hessian
            // beside the factorisation (Hessian::stages_hessian): the point
            // the full step lands on is evaluated with its Hessian at once,
            // instead of an energy first and the Hessian once it is accepted.
            let staged = !trusted
                && o.eager_full_steps
                && plain
                && !quadratic_prev.is_finite()
                && !self.capped
                && p.stages_hessian();
            // the value at the full step where a landing evaluated it (the
            // line search below starts from x with it), and the full step
            // accepted with its Hessian
            let (mut full, mut landed) = (None, None);
            if trusted || staged {
                self.step_to(x, 1.0);
                match self.land(p, x, (f, gtp, gnorm), staged, &mut rep) {
                    Landing::Next(next) => {
                        (f, gnorm, quadratic_prev) = next;
                        continue;
                    }
                    Landing::Failed => break,
                    Landing::Rejected(ft) => full = Some(ft),
                    Landing::Accepted(ft) => landed = Some(ft),
                }
            }
            // In the quadratic phase the full step is almost always accepted:
            // evaluate the point it lands on with the derivatives the next
            // iteration needs, instead of an energy first and the Hessian
            // after. When the quadratic model predicts convergence there,
            // the gradient alone decides (no Hessian for the last step).
            if o.eager_full_steps && plain && quadratic_prev.is_finite() {
                self.step_to(x, 1.0);
                let predicted = gnorm * gnorm * gnorm / (quadratic_prev * quadratic_prev);
                if predicted < 0.1 * o.gtol {
                    let ft = p.gradient(&self.xt, &mut self.gt);
                    rep.gradient_evals += 1;
                    if ft.is_finite()
                        && all_finite(&self.gt)
                        && ft <= f + o.c1 * gtp
                        && norm_inf(&self.gt) <= o.gtol
                    {
                        x.copy_from_slice(&self.xt);
                        self.g.copy_from_slice(&self.gt);
                        rep.iterations += 1;
                        rep.step_norm = self.pnorm;
                        rep.energy = ft;
                        rep.residual_norm = norm_inf(&self.g);
                        rep.reason = Termination::Converged;
                        break;
                    }
                } else if o.chord_steps
                    && predicted <= CHORD_RATIO * gnorm
                    && reaches(predicted, predicted / gnorm, o.gtol, CHORD_STEPS_AHEAD + 2)
                {
                    match self.land(p, x, (f, gtp, gnorm), false, &mut rep) {
                        Landing::Next(next) => {
                            (f, gnorm, quadratic_prev) = next;
                            continue;
                        }
                        Landing::Failed => break,
                        // x, f and g are the current iterate's; the line
                        // search below starts from them
                        Landing::Rejected(ft) => full = Some(ft),
                        Landing::Accepted(_) => {}
                    }
                } else {
                    let ft = p.hessian(&self.xt, &mut self.g);
                    rep.hessian_evals += 1;
                    if ft.is_finite() && all_finite(&self.g) && ft <= f + o.c1 * gtp {
                        x.copy_from_slice(&self.xt);
                        rep.iterations += 1;
                        rep.step_norm = self.pnorm;
                        quadratic_prev = gnorm;
                        f = ft;
                        gnorm = norm_inf(&self.g);
                        continue;
                    }
                    // rejected: g and h now belong to the trial point; the
                    // line search below needs only f, gtp and gnorm, and
                    // the Hessian is re-evaluated where it lands
                    full = Some(ft);
                }
            }
            let (mut alpha, mut ft) = match landed {
                Some(ft) => (1.0, ft),
                None => match self.line_search(p, x, (f, gtp, gnorm), full, &mut rep) {
                    Ok(found) => found,
                    Err(reason) => {
                        rep.reason = reason;
                        break;
                    }
                },
            };
            if o.extend_modified && !plain && alpha == 1.0 {
                (alpha, ft) = self.extend(p, x, f, gtp, ft, &mut rep);
            }
            if o.step_growth {
                // a trust region's radius: a capped Newton step (positive
                // definite Hessian) taken whole lets the next one be twice
                // as long, a shortened one resets it, and so does a step
                // along negative curvature (Newton::direction: the energy
                // may be unbounded that way; the extension above is the
                // only growth such a step has)
                if alpha < 1.0 {
                    self.cap = o.max_step;
                } else if self.capped && plain {
                    let grown = (2.0 * self.cap).min(MAX_CAP_GROWTH * o.max_step);
                    rep.grown_steps += usize::from(grown > self.cap);
                    self.cap = grown;
                }
            }
            // a full Newton step that the quadratic model predicted to 1 %
            // (the actual decrease over 1/2 g^T p): close to the minimum,
            // where chord steps may follow it
            let fit = (ft - f) / (0.5 * gtp);
            if landed.is_none() && chord && alpha == 1.0 && plain && (fit - 1.0).abs() <= MODEL_FIT
            {
                match self.land(p, x, (f, gtp, gnorm), false, &mut rep) {
                    Landing::Next(next) => {
                        (f, gnorm, quadratic_prev) = next;
                        continue;
                    }
                    Landing::Failed => break,
                    // (only if the gradient's value disagrees with the
                    // energy's): the Hessian at the accepted point below
                    Landing::Rejected(_) | Landing::Accepted(_) => {}
                }
            }
            self.xprev.copy_from_slice(x);
            x.copy_from_slice(&self.xt);
            let fnew = if landed.is_some() {
                self.g.copy_from_slice(&self.gt);
                ft
            } else {
                rep.hessian_evals += 1;
                p.hessian(x, &mut self.g)
            };
            if !(fnew.is_finite() && all_finite(&self.g)) {
                x.copy_from_slice(&self.xprev);
                rep.reason = Termination::NonFinite;
                break;
            }
            rep.iterations += 1;
            rep.shifted_steps += usize::from(!plain);
            rep.damped_steps += usize::from(alpha < 1.0);
            rep.step_norm = alpha * self.pnorm;
            // (a step shortened to the cap is not in the quadratic phase)
            quadratic_prev = if alpha == 1.0 && plain && !(o.step_growth && self.capped) {
                gnorm
            } else {
                f64::NAN
            };
            f = fnew;
            gnorm = norm_inf(&self.g);
            if gnorm > o.gtol && rep.step_norm <= o.xtol * (1.0 + norm_inf(x)) {
                rep.energy = f;
                rep.residual_norm = gnorm;
                rep.reason = Termination::StepTolerance;
                break;
            }
        }
        rep
    }

    /// `self.xt = x + alpha self.p` (the full step for `alpha = 1`, bit
    /// for bit: the product by 1 is exact).
    #[inline]
    fn step_to(&mut self, x: &[f64], alpha: f64) {
        for ((xt, xi), pi) in self.xt.iter_mut().zip(x).zip(&self.p) {
            *xt = xi + alpha * pi;
        }
    }
}

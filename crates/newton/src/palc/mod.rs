//! Pseudo-arclength continuation (PALC) of a parametrised equilibrium
//! `g(x, lambda) = 0`, through limit points, with fold and stability events;
//! and the inertia of a Hessian restricted to a constraint's tangent space.
//!
//! The method, its step control and event location are documented on
//! [`Palc`].

mod corrector;
mod inertia;
mod output;
mod path;
#[cfg(test)]
mod tests;

pub(crate) use inertia::restricted_inertia_with;
pub use inertia::{factor_restricted_inertia, restricted_inertia, RestrictedInertiaError};
pub use output::{
    Branch, BranchEvent, BranchPoint, Control, Direction, EventKind, PathEvent, PathObserver,
    PathPoint, PathReport, PathTermination,
};
pub use path::{BorderedPath, Path};

use crate::linear::dot;
use crate::options::{OptionsError, PalcOptions};
use corrector::{correct, distance, step_to, tangent, Border, Failure, Row, State, Work};
use output::Collect;

/// Pseudo-arclength continuation driver and its workspace (all `O(n)`,
/// allocated by [`Palc::new`]; [`Palc::follow`] allocates nothing).
///
/// # The problem
///
/// A [`Path`] problem evaluates `g` (the gradient of an energy with respect
/// to `x`, `x` in `R^n`) and `g_lambda = d g / d lambda` at `(x, lambda)`,
/// and keeps the Hessian `H = d g / d x` there as its [`LinearSystem`](crate::LinearSystem)
/// (symmetric, possibly indefinite). [`BorderedPath`] turns any
/// [`Bordered`](crate::Bordered) problem into a `Path` (its target equation is ignored).
///
/// # The method
///
/// The branch is the curve `z(s) = (x(s), lambda(s))` of solutions,
/// parametrised by (pseudo-)arclength in the weighted norm
///
/// ```text
/// ||(dx, dlambda)||_theta = sqrt(||dx||_2^2 + theta^2 dlambda^2)
/// ```
///
/// (`theta` = [`PalcOptions::theta`]: one unit of the load counts as `theta`
/// units of the state). With `<a, b>_theta = a_x . b_x + theta^2 a_l b_l`:
///
/// * **Tangent** at an accepted point: `t = (t_x, t_l)` with
///   `H t_x + g_lambda t_l = 0`, `||t||_theta = 1`, oriented so that
///   `<t, t_prev>_theta > 0`. It is computed from the bordered system
///   `[H g_lambda; t_prev_x^T theta^2 t_prev_l] (v, mu) = (0, 1)` and
///   normalised; at the start the border is `(0, 1)` and the sign of `mu`
///   is the requested [`Direction`].
/// * **Predictor** (Euler): `z_p = z_0 + ds t_0`.
/// * **Corrector**: Newton on `g(z) = 0`, `<t_0, z - z_0>_theta = ds`, i.e.
///   on the hyperplane through `z_p` orthogonal to `t_0`. Each step solves
///
///   ```text
///   [ H          g_lambda       ] [dx]     [ g ]
///   [ t_0x^T     theta^2 t_0l   ] [dl] = - [ N ]
///   ```
///
///   by block elimination on the problem's factorisation of `H` (symmetric
///   pivots, [`PivotKind::Symmetric`](crate::PivotKind::Symmetric)) with one step of iterative refinement
///   on the whole bordered system (as [`BorderedNewton`](crate::BorderedNewton)
///   does). At a simple fold `H` is singular but the bordered matrix is not
///   (`g_lambda` is not in the range of `H`, and `t_0x` is not orthogonal
///   to its null vector), so the corrector stays well posed through the
///   limit point; the refinement recovers what the elimination loses while
///   `H` is nearly singular. Only an `H` that is singular to the working
///   precision of its factorisation (a zero pivot) fails; the step is then
///   shortened and retried, so an accepted point never sits exactly on a
///   fold. Converged when `||g||_inf <= gtol` (the arclength equation is
///   linear and holds to rounding after the first Newton step).
/// * **Step control**: a step is rejected when the corrector does not
///   converge within `max_corrector_iterations`, an iterate strays farther
///   than `max_correction * ds` from the predictor, an evaluation or
///   factorisation is non-finite or singular, the tangent turns by more than
///   `acos(min_tangent_cos)`, or (with event detection) one step shows more
///   than one event; a rejected step is retried with `ds * shrink` (at least
///   `min_step`). After a corrector that needed at most `easy_iterations`
///   iterations the step grows by `grow` (at most `max_step`).
///
/// # Events
///
/// Every accepted point carries the inertia of `H` there (from the
/// factorisation the tangent needs anyway: no extra work), so its
/// stability (`negative == 0`: a local minimum of the energy in `x` at
/// fixed load). Between two accepted points:
///
/// * a sign change of `t_l` is a **fold** (limit point), [`EventKind::Fold`];
///   it is located by a safeguarded regula falsi (Illinois) on `t_l(s)`,
///   each trial a corrector solve at pseudo-arclength `s` along the step;
/// * a change of the number of negative eigenvalues without a sign change
///   of `t_l` is a **possible bifurcation** (branch point),
///   [`EventKind::PossibleBifurcation`], located by bisection on the
///   inertia. No branch switching is attempted.
///
/// A step whose endpoints show more than one event (a fold with a change of
/// the negative count other than one, or a change by more than one) is
/// retried shorter, so events are resolved one per step unless the step is
/// already at `min_step`. Two events closer together than one step with
/// no net change (two folds in one step) are not seen; `max_step` and
/// `min_tangent_cos` bound how far a step reaches.
///
/// Location tolerance: an event is bracketed to `event_tol` in the
/// pseudo-arclength `s` along the step, and the reported point is a
/// converged equilibrium (`||g||_inf <= gtol`) at one end of that bracket.
/// So its distance to the event is at most about `event_tol /
/// min_tangent_cos` in the weighted norm (in particular in `||x||_2`);
/// at a fold, where `d lambda / ds = 0`, its `lambda` is off by `O(event_tol^2)`
/// (times the curvature of `lambda(s)`). Corrector residuals add their own
/// `O(gtol / sigma_min)` to both.
///
/// # Output
///
/// [`Palc::follow`] hands every accepted point ([`PathPoint`]) and event
/// ([`PathEvent`]) to a [`PathObserver`] as borrowed slices and allocates
/// nothing once the [`Palc`] workspace exists (if the problem's
/// evaluations and factorisations do not allocate); the observer's answer
/// ([`Control`]) is the stop predicate. [`Palc::branch`] stores everything
/// in a [`Branch`] instead. Both end with a [`PathReport`].
///
/// # Restricted inertia
///
/// [`restricted_inertia`] and [`factor_restricted_inertia`] give the
/// inertia of `H` on the tangent space `{v : c_x . v = 0}` of a constraint
/// (the stability of a target-constrained equilibrium), from a symmetric
/// factorisation of `H` and the sign of one Schur complement (Haynsworth).
///
/// # Example
///
/// ```
/// use fpc_newton::{
///     Control, Direction, EventKind, FactorError, Inertia, LinearSystem, Palc, PalcOptions, Path,
///     PivotKind,
/// };
///
/// /// E = x^4/4 - x^2/2 - lambda x: g = x^3 - x - lambda, a snap-through;
/// /// `h` is its 1 x 1 Hessian and `f` the factor of `h + tau`.
/// struct Snap {
///     h: f64,
///     f: f64,
/// }
/// impl Path for Snap {
///     fn dim(&self) -> usize {
///         1
///     }
///     fn eval(&mut self, x: &[f64], l: f64, g: &mut [f64], gl: &mut [f64]) -> bool {
///         g[0] = x[0].powi(3) - x[0] - l;
///         gl[0] = -1.0;
///         self.h = 3.0 * x[0] * x[0] - 1.0;
///         true
///     }
/// }
/// impl LinearSystem for Snap {
///     fn diagonal_range(&self) -> (f64, f64) {
///         (self.h, self.h.abs())
///     }
///     fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
///         self.f = self.h + tau;
///         match self.f {
///             f if f > 0.0 => Ok(Inertia { positive: 1, negative: 0 }),
///             f if f < 0.0 && kind == PivotKind::Symmetric => Ok(Inertia { positive: 0, negative: 1 }),
///             f if f < 0.0 => Err(FactorError::NotPositiveDefinite { index: 0 }),
///             f if f == 0.0 => Err(FactorError::Singular { block: 0 }),
///             _ => Err(FactorError::NonFinite { block: 0 }),
///         }
///     }
///     fn solve(&mut self, b: &mut [f64]) {
///         b[0] /= self.f;
///     }
///     fn apply(&self, x: &[f64], out: &mut [f64]) {
///         out[0] = self.h * x[0];
///     }
/// }
///
/// let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
/// let mut p = Snap { h: 0.0, f: 0.0 };
/// // from the equilibrium near x = -1.32 at lambda = -1 up to lambda = +1
/// let branch = palc.branch(&mut p, &[-1.3], -1.0, Direction::Increasing, Some(1.0), |_| {
///     Control::Continue
/// });
/// assert_eq!(branch.report.termination, fpc_newton::PathTermination::ReachedTarget);
/// assert_eq!(branch.last().unwrap().lambda, 1.0);
/// let folds: Vec<_> = branch.folds().collect();
/// assert_eq!(folds.len(), 2);
/// let lf = 2.0 / (3.0 * 3f64.sqrt());
/// assert!((folds[0].lambda - lf).abs() < 1e-10 && (folds[1].lambda + lf).abs() < 1e-10);
/// assert_eq!(folds[0].kind, EventKind::Fold);
/// assert_eq!((folds[0].inertia_before.negative, folds[0].inertia_after.negative), (0, 1));
/// ```
#[derive(Clone, Debug)]
pub struct Palc {
    n: usize,
    opts: PalcOptions,
    cur: State,
    next: State,
    trial: State,
    event_x: Vec<f64>,
    ws: Work,
    started: bool,
}

impl Palc {
    /// A driver for `n` state unknowns.
    pub fn new(n: usize, opts: PalcOptions) -> Result<Palc, OptionsError> {
        opts.validate()?;
        Ok(Palc {
            n,
            opts,
            cur: State::new(n),
            next: State::new(n),
            trial: State::new(n),
            event_x: vec![0.0; n],
            ws: Work::new(n, opts.theta),
            started: false,
        })
    }

    /// The options.
    pub fn options(&self) -> &PalcOptions {
        &self.opts
    }

    /// Replaces the options (validated; on error the old ones stay).
    pub fn set_options(&mut self, opts: PalcOptions) -> Result<(), OptionsError> {
        opts.validate()?;
        self.opts = opts;
        self.ws.theta2 = opts.theta * opts.theta;
        Ok(())
    }

    /// The last accepted point `(x, lambda)` of the last run (`None` before
    /// a run, or when its start failed).
    pub fn last_point(&self) -> Option<(&[f64], f64)> {
        self.started.then_some((&self.cur.x[..], self.cur.lambda))
    }

    /// The unit tangent `(t_x, t_lambda)` at [`Palc::last_point`].
    pub fn last_tangent(&self) -> Option<(&[f64], f64)> {
        self.started.then_some((&self.cur.tx[..], self.cur.tl))
    }

    fn view(&self, index: usize, arclength: f64) -> PathPoint<'_> {
        PathPoint {
            index,
            lambda: self.cur.lambda,
            x: &self.cur.x,
            tangent_x: &self.cur.tx,
            tangent_lambda: self.cur.tl,
            inertia: self.cur.inertia,
            restricted: self.cur.restricted,
            arclength,
            corrector_iterations: self.cur.iterations,
        }
    }

    /// The inertia of `H` (factorised at the point, of inertia `inertia`)
    /// on the tangent space of the problem's constraint, if it has one
    /// (`None` too when it is not determined: singular there).
    fn restricted<P: Path + ?Sized>(
        p: &mut P,
        ws: &mut Work,
        inertia: crate::Inertia,
    ) -> Option<crate::Inertia> {
        ws.cx.copy_from_slice(p.constraint()?);
        inertia::restricted_inertia_with(p, inertia, &ws.cx, &mut ws.cw, &mut ws.cr).ok()
    }

    /// Follows the branch of `g(x, lambda) = 0` through `(x0, lambda0)`,
    /// handing every accepted point and event to `observer`.
    ///
    /// The start is first polished by Newton at fixed `lambda0` (at most
    /// `max_corrector_iterations` plain Newton steps, no line search: give
    /// an equilibrium or a close guess) and is point 0. The branch leaves it
    /// in `direction`; it ends at the first step that reaches or crosses
    /// `target` (if given; a start exactly at the target does not count),
    /// with a last point solved at `lambda = target` exactly (Newton at
    /// fixed load from the interpolation within the step); when the
    /// observer returns [`Control::Stop`]; after `max_steps` accepted steps;
    /// or when a step fails at `min_step` (see [`PathTermination`]).
    /// [`Palc::last_point`] then holds the last accepted point.
    ///
    /// Allocates nothing (the workspace is [`Palc::new`]'s), if the
    /// problem's evaluations, factorisations and solves and the observer do
    /// not.
    ///
    /// # Panics
    /// If `x0.len()` or `p.dim()` differ from the dimension given to
    /// [`Palc::new`] (programmer error).
    pub fn follow<P: Path + ?Sized, O: PathObserver + ?Sized>(
        &mut self,
        p: &mut P,
        x0: &[f64],
        lambda0: f64,
        direction: Direction,
        target: Option<f64>,
        observer: &mut O,
    ) -> PathReport {
        let n = self.n;
        assert_eq!(
            x0.len(),
            n,
            "Palc::follow: x0.len() must equal the dimension given to Palc::new"
        );
        assert_eq!(
            p.dim(),
            n,
            "Palc::follow: problem dim() must equal the dimension given to Palc::new"
        );
        let o = self.opts;
        let mut rep = PathReport::new(lambda0, o.initial_step);
        self.started = false;
        if o.validate().is_err() || !lambda0.is_finite() || target.is_some_and(|t| !t.is_finite()) {
            return rep;
        }

        // the start: Newton at fixed load, then the tangent
        self.cur.x.copy_from_slice(x0);
        self.cur.lambda = lambda0;
        let sign = match direction {
            Direction::Increasing => 1.0,
            Direction::Decreasing => -1.0,
        };
        let start = correct(
            p,
            &o,
            &mut self.ws,
            Row::Lambda(lambda0),
            &mut self.cur,
            f64::INFINITY,
            &mut rep,
        )
        .and_then(|()| tangent(p, &mut self.ws, Border::Lambda(sign), &mut self.cur));
        if let Err(f) = start {
            rep.termination = if f == Failure::NonFinite {
                PathTermination::NonFinite
            } else {
                PathTermination::StartFailed
            };
            return rep;
        }
        self.cur.restricted = Self::restricted(p, &mut self.ws, self.cur.inertia);
        self.started = true;
        let mut arc = 0.0;
        if observer.point(&self.view(0, arc)) == Control::Stop {
            rep.termination = PathTermination::Stopped;
            return rep;
        }

        let theta2 = self.ws.theta2;
        let mut ds = o.initial_step;
        loop {
            if rep.steps >= o.max_steps {
                rep.termination = PathTermination::MaxSteps;
                break;
            }
            let mut landed = false;
            let attempt = step_to(p, &o, &mut self.ws, &self.cur, ds, &mut self.next, &mut rep)
                .and_then(|()| {
                    let cos =
                        dot(&self.cur.tx, &self.next.tx) + theta2 * self.cur.tl * self.next.tl;
                    if cos < o.min_tangent_cos {
                        return Err(Failure::Turned);
                    }
                    // the target: land on it exactly
                    let (l0, l1) = (self.cur.lambda, self.next.lambda);
                    let Some(t) = target else { return Ok(()) };
                    if l0 == t || (l1 - t).signum() == (l0 - t).signum() && l1 != t {
                        return Ok(());
                    }
                    let f = (t - l0) / (l1 - l0);
                    for (x1, x0) in self.next.x.iter_mut().zip(&self.cur.x) {
                        *x1 = x0 + f * (*x1 - x0);
                    }
                    self.next.lambda = t;
                    correct(
                        p,
                        &o,
                        &mut self.ws,
                        Row::Lambda(t),
                        &mut self.next,
                        o.max_correction * ds,
                        &mut rep,
                    )?;
                    tangent(p, &mut self.ws, Border::Tangent(&self.cur), &mut self.next)?;
                    landed = true;
                    Ok(())
                })
                .and_then(|()| {
                    // the problem's factorisation is at the new point
                    self.next.restricted = Self::restricted(p, &mut self.ws, self.next.inertia);
                    // an inertia change across a long step: shorter, to
                    // tell this branch's event from a jump to another
                    let changed = self.next.inertia != self.cur.inertia
                        || self.next.restricted.map(|i| i.negative)
                            != self.cur.restricted.map(|i| i.negative);
                    if changed && ds > o.event_step && o.event_step > 0.0 && ds > o.min_step {
                        return Err(Failure::Events);
                    }
                    Ok(())
                })
                .and_then(|()| {
                    if !o.detect_events || ds <= o.min_step {
                        return Ok(());
                    }
                    let (fold, dneg) = self.events_between();
                    if (fold && dneg.abs() != 1) || dneg.abs() > 1 {
                        Err(Failure::Events)
                    } else {
                        Ok(())
                    }
                });
            if let Err(f) = attempt {
                rep.rejected += 1;
                if ds <= o.min_step {
                    rep.termination = if f == Failure::NonFinite {
                        PathTermination::NonFinite
                    } else {
                        PathTermination::StepTooSmall
                    };
                    break;
                }
                ds = (ds * o.shrink).max(o.min_step);
                rep.step = ds;
                continue;
            }

            // accepted: events first, then the point
            if o.detect_events {
                let (fold, dneg) = self.events_between();
                if fold || dneg != 0 {
                    let kind = if fold {
                        EventKind::Fold
                    } else {
                        EventKind::PossibleBifurcation
                    };
                    let (located, lambda, tl) = self.locate(p, kind, &mut rep);
                    rep.events += 1;
                    let ev = PathEvent {
                        kind,
                        lambda,
                        x: &self.event_x,
                        arclength: arc
                            + distance(theta2, &self.event_x, lambda, &self.cur.x, self.cur.lambda),
                        inertia_before: self.cur.inertia,
                        inertia_after: self.next.inertia,
                        tangent_lambda: tl,
                        located,
                        after_point: rep.steps,
                    };
                    observer.event(&ev);
                }
            }
            arc += distance(
                theta2,
                &self.next.x,
                self.next.lambda,
                &self.cur.x,
                self.cur.lambda,
            );
            core::mem::swap(&mut self.cur, &mut self.next);
            rep.steps += 1;
            rep.lambda = self.cur.lambda;
            rep.arclength = arc;
            let easy = self.cur.iterations <= o.easy_iterations;
            if observer.point(&self.view(rep.steps, arc)) == Control::Stop {
                rep.termination = PathTermination::Stopped;
                break;
            }
            if landed {
                rep.termination = PathTermination::ReachedTarget;
                break;
            }
            if easy {
                ds = (ds * o.grow).min(o.max_step);
            }
            rep.step = ds;
        }
        rep
    }

    /// Like [`Palc::follow`], storing every point and event in a
    /// [`Branch`] (allocates `O(n)` per point); `stop` is the stop
    /// predicate (return [`Control::Continue`] to follow to the target or
    /// the other limits).
    pub fn branch<P: Path + ?Sized, S: FnMut(&PathPoint<'_>) -> Control>(
        &mut self,
        p: &mut P,
        x0: &[f64],
        lambda0: f64,
        direction: Direction,
        target: Option<f64>,
        stop: S,
    ) -> Branch {
        let mut c = Collect {
            points: Vec::new(),
            events: Vec::new(),
            stop,
        };
        let report = self.follow(p, x0, lambda0, direction, target, &mut c);
        Branch {
            points: c.points,
            events: c.events,
            report,
        }
    }

    /// `(fold, change of the negative count)` between `cur` and `next`.
    fn events_between(&self) -> (bool, isize) {
        let (a, b) = (self.cur.tl, self.next.tl);
        let fold = (a > 0.0 && b <= 0.0) || (a < 0.0 && b >= 0.0);
        let dneg = self.next.inertia.negative as isize - self.cur.inertia.negative as isize;
        (fold, dneg)
    }

    /// Locates the event between `cur` and `next` ([`Palc`] docs) into
    /// `event_x`; returns `(located, lambda, t_lambda)` of the point found.
    fn locate<P: Path + ?Sized>(
        &mut self,
        p: &mut P,
        kind: EventKind,
        rep: &mut PathReport,
    ) -> (bool, f64, f64) {
        let o = self.opts;
        let theta2 = self.ws.theta2;
        let (cur, next, trial) = (&self.cur, &self.next, &mut self.trial);
        // the step's length along the tangent at its start
        let s1 = cur.along_tangent(theta2, next);
        let tol = o.event_tol;
        // best point so far: the endpoint nearer the event
        let (mut best_l, mut best_t) = (next.lambda, next.tl);
        self.event_x.copy_from_slice(&next.x);
        if kind == EventKind::Fold && cur.tl.abs() < next.tl.abs() {
            (best_l, best_t) = (cur.lambda, cur.tl);
            self.event_x.copy_from_slice(&cur.x);
        }
        if !(s1.is_finite() && s1 > 0.0) {
            return (false, best_l, best_t);
        }
        let mut iters = 0usize;
        match kind {
            EventKind::Fold => {
                // Illinois on t_l(s), s in [0, s1], kept inside the bracket
                // by tol / 2 so that it shrinks to tol
                let (mut a, mut fa) = (0.0, cur.tl);
                let (mut b, mut fb) = (s1, next.tl);
                let mut width = s1;
                let mut stalls = 0usize;
                while (b - a).abs() > tol && fb != 0.0 {
                    if iters >= o.max_locate_iterations {
                        return (false, best_l, best_t);
                    }
                    iters += 1;
                    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                    let mut s = if stalls >= 2 {
                        stalls = 0;
                        0.5 * (a + b)
                    } else {
                        b - fb * (b - a) / (fb - fa)
                    };
                    if !s.is_finite() {
                        s = 0.5 * (a + b);
                    }
                    s = s.clamp(lo + 0.5 * tol, hi - 0.5 * tol);
                    rep.locate_solves += 1;
                    if step_to(p, &o, &mut self.ws, cur, s, trial, rep).is_err() {
                        return (false, best_l, best_t);
                    }
                    let fs = trial.tl;
                    if fs.abs() <= best_t.abs() {
                        (best_l, best_t) = (trial.lambda, fs);
                        self.event_x.copy_from_slice(&trial.x);
                    }
                    if (fs > 0.0) != (fb > 0.0) {
                        (a, fa) = (b, fb);
                    } else {
                        fa *= 0.5;
                    }
                    (b, fb) = (s, fs);
                    let w = (b - a).abs();
                    if w > 0.5 * width {
                        stalls += 1;
                    } else {
                        stalls = 0;
                        width = w;
                    }
                }
                (true, best_l, best_t)
            }
            EventKind::PossibleBifurcation => {
                // bisection on the negative count
                let n0 = cur.inertia.negative;
                let (mut a, mut b) = (0.0, s1);
                while b - a > tol {
                    if iters >= o.max_locate_iterations {
                        return (false, best_l, best_t);
                    }
                    iters += 1;
                    let m = 0.5 * (a + b);
                    rep.locate_solves += 1;
                    if step_to(p, &o, &mut self.ws, cur, m, trial, rep).is_err() {
                        return (false, best_l, best_t);
                    }
                    if trial.inertia.negative == n0 {
                        a = m;
                    } else {
                        b = m;
                        (best_l, best_t) = (trial.lambda, trial.tl);
                        self.event_x.copy_from_slice(&trial.x);
                    }
                }
                (true, best_l, best_t)
            }
        }
    }
}

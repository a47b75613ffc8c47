//! Backtracking along a Newton direction (Armijo, with one cubic step
//! past the accepted fraction), and the doubling of shifted steps.

use super::{Newton, ROUNDOFF_FACTOR};
use crate::linear::{all_finite, norm_inf};
use crate::problem::Hessian;
use crate::report::{Report, Termination};

/// The cubic step of a line search is tried only between these multiples
/// of the accepted and the rejected step fractions (see
/// [`Newton::cubic_step`]): close to either it would gain little.
const CUBIC_MARGIN: (f64, f64) = (1.1, 0.9);

/// A shifted step is doubled at most this many times (see
/// [`Newton::extend`]).
const MAX_EXTENSIONS: usize = 12;

impl Newton {
    /// A shifted step whose full length was accepted: the shift keeps it
    /// short of where the energy stops falling (along a direction of
    /// negative curvature the quadratic model has no minimum), so the step
    /// is doubled while the energy keeps falling, Armijo holds and its
    /// length stays within `max_step`. Leaves the accepted point in
    /// `self.xt` and returns its fraction and value.
    pub(super) fn extend<P: Hessian + ?Sized>(
        &mut self,
        p: &mut P,
        x: &[f64],
        f: f64,
        gtp: f64,
        f_full: f64,
        rep: &mut Report,
    ) -> (f64, f64) {
        let o = self.opts;
        let len = self.pnorm;
        let (mut best, mut f_best) = (1.0, f_full);
        for _ in 0..MAX_EXTENSIONS {
            let alpha = 2.0 * best;
            if alpha * len > self.cap {
                break;
            }
            self.step_to(x, alpha);
            let ft = p.energy(&self.xt);
            rep.energy_evals += 1;
            if !(ft < f_best && ft <= f + o.c1 * alpha * gtp) {
                break;
            }
            (best, f_best) = (alpha, ft);
            rep.extended_steps += 1;
        }
        self.step_to(x, best);
        (best, f_best)
    }

    /// After backtracking from the rejected trial `(a0, f0)` to the
    /// accepted `(a1, f1)` (value `f` and slope `gtp` at 0): the minimiser
    /// of the cubic through these four values, evaluated when it lies well
    /// inside `(a1, a0)`, and taken (in `self.xt`) if its value is lower.
    /// The quadratic estimate that found `a1` ignores `f1`; under a load
    /// that turns the finger far, the energy rises steeply past its
    /// minimum and that estimate falls well short of it. `None` leaves
    /// `self.xt` at `a1`.
    #[allow(clippy::too_many_arguments)]
    #[inline(never)]
    fn cubic_step<P: Hessian + ?Sized>(
        &mut self,
        p: &mut P,
        x: &[f64],
        f: f64,
        gtp: f64,
        (a0, f0): (f64, f64),
        (a1, f1): (f64, f64),
        rep: &mut Report,
    ) -> Option<(f64, f64)> {
        // phi(a) = c3 a^3 + c2 a^2 + gtp a + f through phi(a0) and phi(a1)
        let (r0, r1) = (f0 - f - gtp * a0, f1 - f - gtp * a1);
        let d = a0 * a0 * a1 * a1 * (a1 - a0);
        let c3 = (a0 * a0 * r1 - a1 * a1 * r0) / d;
        let c2 = (a1 * a1 * a1 * r0 - a0 * a0 * a0 * r1) / d;
        let a = (-c2 + (c2 * c2 - 3.0 * c3 * gtp).sqrt()) / (3.0 * c3);
        // (false for NaN: no real minimiser, or c3 = 0)
        if !(a > CUBIC_MARGIN.0 * a1 && a < CUBIC_MARGIN.1 * a0) {
            return None;
        }
        self.step_to(x, a);
        let fa = p.energy(&self.xt);
        rep.energy_evals += 1;
        if fa < f1 {
            Some((a, fa))
        } else {
            self.step_to(x, a1);
            None
        }
    }

    /// Backtracking Armijo search along `self.p` from `x` (value `f`,
    /// slope `gtp`, gradient norm `gnorm`), starting with the full step's
    /// value `full` where a landing evaluated it already; leaves the
    /// accepted point in `self.xt` and returns the step fraction and the
    /// value there.
    pub(super) fn line_search<P: Hessian + ?Sized>(
        &mut self,
        p: &mut P,
        x: &[f64],
        (f, gtp, gnorm): (f64, f64, f64),
        mut full: Option<f64>,
        rep: &mut Report,
    ) -> Result<(f64, f64), Termination> {
        let o = self.opts;
        let mut alpha = 1.0f64;
        let mut any_finite = false;
        // the last finite trial that Armijo rejected
        let mut rejected: Option<(f64, f64)> = None;
        loop {
            self.step_to(x, alpha);
            let ft = full.take().unwrap_or_else(|| {
                rep.energy_evals += 1;
                p.energy(&self.xt)
            });
            if ft.is_finite() {
                any_finite = true;
                if ft <= f + o.c1 * alpha * gtp {
                    return Ok(rejected
                        .and_then(|r| self.cubic_step(p, x, f, gtp, r, (alpha, ft), rep))
                        .unwrap_or((alpha, ft)));
                }
                rejected = Some((alpha, ft));
                let noise = ROUNDOFF_FACTOR * f64::EPSILON * f.abs().max(ft.abs());
                if (ft - f).abs() <= noise {
                    let fg = p.gradient(&self.xt, &mut self.gt);
                    rep.gradient_evals += 1;
                    if fg.is_finite() && all_finite(&self.gt) && norm_inf(&self.gt) <= 0.5 * gnorm {
                        return Ok((alpha, ft));
                    }
                }
                // Minimiser of the quadratic through f, f'(0) = gtp, f(alpha) = ft.
                let denom = 2.0 * (ft - f - gtp * alpha);
                let aq = if denom > 0.0 {
                    -gtp * alpha * alpha / denom
                } else {
                    0.5 * alpha
                };
                // a non-finite quadratic estimate would make the clamp NaN
                // and the loop endless: halve instead
                alpha = if aq.is_finite() {
                    aq.clamp(0.1 * alpha, 0.5 * alpha)
                } else {
                    0.5 * alpha
                };
            } else {
                alpha *= 0.25;
            }
            if alpha.is_nan() || alpha < o.min_step_fraction {
                return Err(if any_finite {
                    Termination::LineSearchFailed
                } else {
                    Termination::NonFinite
                });
            }
        }
    }
}

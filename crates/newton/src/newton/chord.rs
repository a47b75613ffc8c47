//! Steps that reuse what a Newton step evaluated: a full step landed
//! with its gradient or its staged Hessian, and chord steps with the last
//! factorisation.

use super::{reaches, Landing, Newton, CHORD_RATIO, CHORD_STEPS_AHEAD, MODEL_FIT, ROUNDOFF_FACTOR};
use crate::linear::{all_finite, dot, norm_inf};
use crate::problem::Hessian;
use crate::report::{Report, Termination};

/// At most this many chord steps follow one Hessian.
const MAX_CHORD_STEPS: usize = 4;

impl Newton {
    /// Evaluates the full step `self.xt` from `x` (value `f`, `g^T p =
    /// gtp`, gradient norm `gnorm`): with its gradient only, or with its
    /// Hessian staged beside the factorisation at hand (`hessian`,
    /// [`Hessian::stages_hessian`]). Rejected unless its value is finite
    /// and passes Armijo (and, with the gradient only, its gradient is
    /// finite). With the gradient only it becomes the iterate and chord
    /// steps follow ([`Newton::chord_then_hessian`]); with the Hessian it
    /// does so where its decrease matches the quadratic model's to
    /// [`MODEL_FIT`] (and chord steps are on), with no Hessian to evaluate
    /// again if no chord step follows, and otherwise
    /// [`Landing::Accepted`] hands it to the ordinary Newton step.
    pub(super) fn land<P: Hessian + ?Sized>(
        &mut self,
        p: &mut P,
        x: &mut [f64],
        (f, gtp, gnorm): (f64, f64, f64),
        hessian: bool,
        rep: &mut Report,
    ) -> Landing {
        let ft = if hessian {
            rep.hessian_evals += 1;
            p.hessian(&self.xt, &mut self.gt)
        } else {
            rep.gradient_evals += 1;
            p.gradient(&self.xt, &mut self.gt)
        };
        let finite = all_finite(&self.gt);
        if !(ft.is_finite() && ft <= f + self.opts.c1 * gtp && (finite || hessian)) {
            return Landing::Rejected(ft);
        }
        let fit = (ft - f) / (0.5 * gtp);
        if hessian && !(self.opts.chord_steps && (fit - 1.0).abs() <= MODEL_FIT && finite) {
            return Landing::Accepted(ft);
        }
        x.copy_from_slice(&self.xt);
        self.g.copy_from_slice(&self.gt);
        rep.iterations += 1;
        rep.step_norm = self.pnorm;
        match self.chord_then_hessian(p, x, ft, gnorm, hessian, rep) {
            Some(next) => Landing::Next(next),
            None => Landing::Failed,
        }
    }

    /// After a step to `x` whose gradient alone was evaluated (in
    /// `self.g`; value `f`, the gradient norm before the step `prev`):
    /// chord steps while they pay ([`Newton::chord`]), then the Hessian at
    /// the last accepted point unless they converged (or took no step
    /// from a point whose Hessian is `staged` already). Returns the value,
    /// gradient norm and the norm before the last step, or `None` (the
    /// report says `NonFinite`) when that Hessian is not finite.
    fn chord_then_hessian<P: Hessian + ?Sized>(
        &mut self,
        p: &mut P,
        x: &mut [f64],
        f: f64,
        prev: f64,
        staged: bool,
        rep: &mut Report,
    ) -> Option<(f64, f64, f64)> {
        let gnorm = norm_inf(&self.g);
        let taken = rep.chord_steps;
        let (f, gnorm, prev) = self.chord(p, x, (f, gnorm, prev), staged, rep);
        if gnorm <= self.opts.gtol || (staged && rep.chord_steps == taken) {
            return Some((f, gnorm, prev));
        }
        let fh = p.hessian(x, &mut self.g);
        rep.hessian_evals += 1;
        if !(fh.is_finite() && all_finite(&self.g)) {
            rep.energy = f;
            rep.residual_norm = gnorm;
            rep.reason = Termination::NonFinite;
            return None;
        }
        Some((fh, norm_inf(&self.g), prev))
    }

    /// Chord steps from `x` (value `f`, gradient `self.g` of norm `gnorm`,
    /// the norm before the last step `prev`) with the last factorisation, while each
    /// cuts the gradient norm by [`CHORD_RATIO`] (type-level docs). Leaves
    /// the last accepted point in `x` and `self.g`; returns its value,
    /// gradient norm and the norm before it.
    ///
    /// Where `x`'s Hessian is `staged` already, the first chord step is
    /// taken only if the rate of the last cut reaches the depth the chord
    /// steps go on to ([`NewtonOptions::chord_depth`](crate::NewtonOptions::chord_depth) times `gtol`) within
    /// [`CHORD_STEPS_AHEAD`] steps, not merely `gtol`: the Newton step with
    /// that Hessian costs a factorisation more than a chord step, and
    /// slow chord steps to the depth cost more than that (fpc's cold
    /// 27-element finger solve at a relative residual of 1e-9 took four
    /// chord steps at a rate of about 1e-2 where at 1e-11 it took the
    /// Newton step and one chord step, and ended less accurate).
    fn chord<P: Hessian + ?Sized>(
        &mut self,
        p: &mut P,
        x: &mut [f64],
        (mut f, mut gnorm, mut prev): (f64, f64, f64),
        staged: bool,
        rep: &mut Report,
    ) -> (f64, f64, f64) {
        let o = self.opts;
        let depth = o.chord_depth * o.gtol;
        for k in 0..MAX_CHORD_STEPS {
            let r = gnorm / prev;
            let target = if staged && k == 0 { depth } else { o.gtol };
            if gnorm <= depth
                || r > CHORD_RATIO
                || !reaches(gnorm, r, target, CHORD_STEPS_AHEAD)
                || rep.iterations >= o.max_iter
            {
                break;
            }
            for (pi, gi) in self.p.iter_mut().zip(&self.g) {
                *pi = -gi;
            }
            p.solve(&mut self.p);
            let gtp = dot(&self.g, &self.p);
            if !(all_finite(&self.p) && gtp < 0.0) {
                break;
            }
            let len = norm_inf(&self.p);
            let shortened = len > o.max_step;
            if shortened {
                let s = o.max_step / len;
                self.p.iter_mut().for_each(|v| *v *= s);
            }
            self.step_to(x, 1.0);
            let ft = p.gradient(&self.xt, &mut self.gt);
            rep.gradient_evals += 1;
            let gt = norm_inf(&self.gt);
            let noise = ROUNDOFF_FACTOR * f64::EPSILON * f.abs().max(ft.abs());
            let decrease = ft <= f + o.c1 * gtp || (ft - f).abs() <= noise;
            if !(ft.is_finite() && all_finite(&self.gt) && decrease && gt < gnorm) {
                break;
            }
            x.copy_from_slice(&self.xt);
            self.g.copy_from_slice(&self.gt);
            rep.iterations += 1;
            rep.chord_steps += 1;
            rep.step_norm = if shortened { norm_inf(&self.p) } else { len };
            (f, prev, gnorm) = (ft, gnorm, gt);
        }
        (f, gnorm, prev)
    }
}

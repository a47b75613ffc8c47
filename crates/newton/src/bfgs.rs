//! Gradient-only BFGS minimiser, used to cross-check Newton's equilibria
//! with a method that never sees a Hessian.

use crate::dense::{all_finite, dot, norm_inf};
use crate::options::{BfgsOptions, OptionsError};
use crate::problem::Gradient;
use crate::report::{Report, Termination};

/// Round-off allowance of the line search, as in Newton (see
/// [`Bfgs::minimize`]).
const ROUNDOFF_FACTOR: f64 = 1e3;

/// BFGS quasi-Newton minimiser (inverse-Hessian form) with a strong-Wolfe
/// line search, and its workspace.
///
/// Not tuned for speed (the update is `O(n^2)` per iteration and the
/// convergence superlinear, not quadratic); it exists as an independent
/// check of [`Newton`](crate::Newton).
///
/// # Algorithm
/// The inverse-Hessian approximation starts as the identity, is rescaled
/// to `(s^T y / y^T y) I` after the first step, and receives the BFGS
/// update whenever `s^T y > eps ||s|| ||y||` (skipped otherwise). If the
/// direction `-H g` is not a descent direction, or its line search fails,
/// the approximation is reset to the identity once before giving up. The
/// first trial step is `min(1, 1/||g||_inf)` on the first iteration and 1
/// afterwards. The line search brackets and zooms (safeguarded quadratic
/// interpolation) until `f(x + a d) <= f + c1 a g^T d` and
/// `|g(x + a d)^T d| <= c2 |g^T d|`; as in Newton, in the round-off regime
/// (`|f_t - f| <= 1e3 eps max(|f|, |f_t|)`) sufficient decrease is judged
/// by the slope instead (`g_t^T d <= (1 - 2 c1) |g^T d|`, Hager–Zhang's
/// approximate Wolfe test). Non-finite trial values count as "too far".
///
/// Every trial point costs one [`Gradient::gradient`] call;
/// `energy_evals` and `hessian_evals` stay 0 and `max_shift` is 0.
/// Stopping rules match [`Newton::minimize`](crate::Newton::minimize).
pub struct Bfgs {
    n: usize,
    opts: BfgsOptions,
    valid: bool,
    hinv: Vec<f64>,
    g: Vec<f64>,
    d: Vec<f64>,
    xt: Vec<f64>,
    gt: Vec<f64>,
    s: Vec<f64>,
    y: Vec<f64>,
    hy: Vec<f64>,
}

impl core::fmt::Debug for Bfgs {
    fn fmt(&self, f: &mut core::fmt::Formatter<'_>) -> core::fmt::Result {
        f.debug_struct("Bfgs")
            .field("n", &self.n)
            .field("opts", &self.opts)
            .finish_non_exhaustive()
    }
}

/// A point evaluated by the line search.
#[derive(Clone, Copy)]
struct Pt {
    a: f64,
    f: f64,
    d: f64,
}

impl Bfgs {
    /// A BFGS solver for dimension `n` with its buffers allocated.
    ///
    /// Never panics: with invalid `opts` every solve returns
    /// [`Termination::InvalidInput`]; use [`Bfgs::try_new`] for the error.
    pub fn new(n: usize, opts: BfgsOptions) -> Bfgs {
        let valid = opts.validate().is_ok();
        Bfgs {
            n,
            opts,
            valid,
            hinv: vec![0.0; n * n],
            g: vec![0.0; n],
            d: vec![0.0; n],
            xt: vec![0.0; n],
            gt: vec![0.0; n],
            s: vec![0.0; n],
            y: vec![0.0; n],
            hy: vec![0.0; n],
        }
    }

    /// Like [`Bfgs::new`], but rejects invalid options.
    pub fn try_new(n: usize, opts: BfgsOptions) -> Result<Bfgs, OptionsError> {
        opts.validate()?;
        Ok(Bfgs::new(n, opts))
    }

    /// The options in use.
    pub fn options(&self) -> &BfgsOptions {
        &self.opts
    }

    /// Gradient at the returned point of the last solve.
    pub fn gradient(&self) -> &[f64] {
        &self.g
    }

    fn reset(&mut self, diag: f64) {
        let n = self.n;
        self.hinv.fill(0.0);
        for i in 0..n {
            self.hinv[i * (n + 1)] = diag;
        }
    }

    /// Minimises `p` from `x`; `x` holds the result (on failure the last
    /// accepted iterate).
    ///
    /// # Panics
    /// If `x.len()` or `p.dim()` differ from the dimension given to
    /// [`Bfgs::new`] (programmer error).
    pub fn minimize<P: Gradient + ?Sized>(&mut self, p: &mut P, x: &mut [f64]) -> Report {
        let n = self.n;
        assert_eq!(
            x.len(),
            n,
            "Bfgs::minimize: x.len() must equal the dimension given to Bfgs::new"
        );
        assert_eq!(
            p.dim(),
            n,
            "Bfgs::minimize: problem dim() must equal the dimension given to Bfgs::new"
        );
        if !self.valid {
            return Report::empty(Termination::InvalidInput);
        }
        let o = self.opts;
        let mut rep = Report::empty(Termination::Converged);
        let mut f = p.gradient(x, &mut self.g);
        rep.gradient_evals += 1;
        if !(f.is_finite() && all_finite(&self.g)) {
            rep.reason = Termination::NonFinite;
            return rep;
        }
        self.reset(1.0);
        let mut first = true;
        let mut is_identity = true;
        loop {
            let gnorm = norm_inf(&self.g);
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
            self.direction();
            let mut gtd = dot(&self.g, &self.d);
            if !(gtd < 0.0 && all_finite(&self.d)) {
                self.reset(1.0);
                is_identity = true;
                self.direction();
                gtd = dot(&self.g, &self.d);
            }
            let a0 = if first { (1.0 / gnorm).min(1.0) } else { 1.0 };
            let ft = match self.wolfe(p, x, f, gtd, a0, &mut rep) {
                Ok(ft) => ft,
                Err(reason) => {
                    if is_identity {
                        rep.reason = reason;
                        break;
                    }
                    self.reset(1.0);
                    is_identity = true;
                    continue;
                }
            };
            for (((s, y), (xt, xi)), (gt, g)) in self
                .s
                .iter_mut()
                .zip(self.y.iter_mut())
                .zip(self.xt.iter().zip(x.iter()))
                .zip(self.gt.iter().zip(&self.g))
            {
                *s = xt - xi;
                *y = gt - g;
            }
            x.copy_from_slice(&self.xt);
            self.g.copy_from_slice(&self.gt);
            f = ft;
            rep.iterations += 1;
            rep.step_norm = norm_inf(&self.s);
            let sy = dot(&self.s, &self.y);
            let yy = dot(&self.y, &self.y);
            let ss = dot(&self.s, &self.s);
            if sy > f64::EPSILON * (ss * yy).sqrt() {
                if first {
                    self.reset(sy / yy);
                }
                self.update(sy);
                is_identity = false;
            }
            first = false;
            let gnorm = norm_inf(&self.g);
            if gnorm > o.gtol && rep.step_norm <= o.xtol * (1.0 + norm_inf(x)) {
                rep.energy = f;
                rep.residual_norm = gnorm;
                rep.reason = Termination::StepTolerance;
                break;
            }
        }
        rep
    }

    /// `d = -H g`.
    fn direction(&mut self) {
        let n = self.n;
        self.d.fill(0.0);
        for j in 0..n {
            let gj = self.g[j];
            for i in 0..n {
                self.d[i] -= self.hinv[i + j * n] * gj;
            }
        }
    }

    /// `H <- (I - r s y^T) H (I - r y s^T) + r s s^T`, `r = 1 / s^T y`,
    /// expanded as `H + ((1 + r y^T H y) r) s s^T - r (H y s^T + s y^T H)`.
    fn update(&mut self, sy: f64) {
        let n = self.n;
        let r = 1.0 / sy;
        self.hy.fill(0.0);
        for j in 0..n {
            let yj = self.y[j];
            for i in 0..n {
                self.hy[i] += self.hinv[i + j * n] * yj;
            }
        }
        let yhy = dot(&self.y, &self.hy);
        let k = (1.0 + r * yhy) * r;
        for j in 0..n {
            for i in 0..n {
                self.hinv[i + j * n] += k * self.s[i] * self.s[j]
                    - r * (self.hy[i] * self.s[j] + self.s[i] * self.hy[j]);
            }
        }
    }

    /// Evaluates the trial point `x + a d` into `xt`, `gt`.
    fn eval<P: Gradient + ?Sized>(
        &mut self,
        p: &mut P,
        x: &[f64],
        a: f64,
        rep: &mut Report,
    ) -> Option<Pt> {
        for ((xt, xi), di) in self.xt.iter_mut().zip(x).zip(&self.d) {
            *xt = xi + a * di;
        }
        let f = p.gradient(&self.xt, &mut self.gt);
        rep.gradient_evals += 1;
        if f.is_finite() && all_finite(&self.gt) {
            Some(Pt {
                a,
                f,
                d: dot(&self.gt, &self.d),
            })
        } else {
            None
        }
    }

    /// Strong-Wolfe line search; on success `xt`, `gt` hold the accepted
    /// point and its value is returned.
    fn wolfe<P: Gradient + ?Sized>(
        &mut self,
        p: &mut P,
        x: &[f64],
        f0: f64,
        dphi0: f64,
        a0: f64,
        rep: &mut Report,
    ) -> Result<f64, Termination> {
        let (c1, c2) = (self.opts.c1, self.opts.c2);
        let mut lo = Pt {
            a: 0.0,
            f: f0,
            d: dphi0,
        };
        // Upper end of the bracket once found; f = +inf marks a non-finite trial.
        let mut hi: Option<Pt> = None;
        let mut a = a0;
        let mut any_finite = false;
        for _ in 0..self.opts.max_line_search {
            match self.eval(p, x, a, rep) {
                None => {
                    hi = Some(Pt {
                        a,
                        f: f64::INFINITY,
                        d: f64::NAN,
                    })
                }
                Some(t) => {
                    any_finite = true;
                    let noise = ROUNDOFF_FACTOR * f64::EPSILON * f0.abs().max(t.f.abs());
                    let sufficient = t.f <= f0 + c1 * t.a * dphi0
                        || ((t.f - f0).abs() <= noise && t.d <= (2.0 * c1 - 1.0) * dphi0);
                    if !sufficient || (lo.a > 0.0 && t.f > lo.f) {
                        hi = Some(t);
                    } else {
                        if t.d.abs() <= -c2 * dphi0 {
                            return Ok(t.f);
                        }
                        match hi {
                            Some(h) => {
                                if t.d * (h.a - t.a) >= 0.0 {
                                    hi = Some(lo);
                                }
                            }
                            None => {
                                if t.d >= 0.0 {
                                    hi = Some(lo);
                                }
                            }
                        }
                        lo = t;
                    }
                }
            }
            a = match hi {
                None => 4.0 * lo.a.max(a),
                Some(h) => {
                    let t = h.a - lo.a;
                    let (amin, amax) = if t > 0.0 { (lo.a, h.a) } else { (h.a, lo.a) };
                    let width = amax - amin;
                    if width.partial_cmp(&(1e-14 * amax)) != Some(core::cmp::Ordering::Greater) {
                        break;
                    }
                    let mut cand = 0.5 * (lo.a + h.a);
                    if h.f.is_finite() {
                        let kappa = (h.f - lo.f - lo.d * t) / (t * t);
                        if kappa > 0.0 {
                            cand = lo.a - lo.d / (2.0 * kappa);
                        }
                    }
                    cand.clamp(amin + 0.1 * width, amax - 0.1 * width)
                }
            };
        }
        // Budget exhausted or bracket collapsed: fall back to the best point
        // that satisfied sufficient decrease, if any.
        if lo.a > 0.0 {
            if let Some(t) = self.eval(p, x, lo.a, rep) {
                return Ok(t.f);
            }
        }
        Err(if any_finite {
            Termination::LineSearchFailed
        } else {
            Termination::NonFinite
        })
    }
}

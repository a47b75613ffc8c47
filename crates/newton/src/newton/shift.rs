//! The Newton direction: the Hessian's Cholesky factorisation, shifted
//! (or with modified pivots) until it is positive definite.

use super::{Direction, Newton};
use crate::linear::{all_finite, dot, norm_inf, FactorError};
use crate::problem::Hessian;
use crate::report::{Report, Termination};
use crate::semiseparable::PivotKind;

/// Number of shifted factorisations tried before giving up with
/// [`Termination::Singular`]. Shifts double per try from at least
/// `1e-12 * scale` ([`SHIFT_FLOOR`]), so 64 tries reach beyond
/// `9e6 * scale`.
const MAX_SHIFT_TRIES: usize = 64;

/// The first shift of an indefinite Hessian, relative to its largest
/// diagonal entry, where the step cap does not lower it (type-level docs).
const SHIFT_BASE: f64 = 1e-3;

/// The least first shift, relative to the largest diagonal entry: far
/// above the rounding of the diagonal.
const SHIFT_FLOOR: f64 = 1e-12;

impl Newton {
    /// Computes the (shifted) Newton direction into `self.p`; returns the
    /// shift used, `Err(NonFinite)` if the Hessian holds a non-finite entry
    /// (checked only once the unshifted factorisation has failed, so the
    /// common positive definite case pays nothing), or `Err(Singular)` if no
    /// shift produced a usable factorisation. `last_tau` (the previous
    /// iteration's shift) seeds the escalation.
    pub(super) fn direction<P: Hessian + ?Sized>(
        &mut self,
        problem: &mut P,
        last_tau: f64,
        rep: &mut Report,
    ) -> Result<Direction, Termination> {
        let mut tau = 0.0;
        for _ in 0..MAX_SHIFT_TRIES {
            rep.factorizations += 1;
            match problem.factor(tau, PivotKind::Cholesky) {
                Ok(_) => {
                    if tau > 0.0 {
                        // along negative curvature the cap starts again
                        self.cap = self.opts.max_step;
                    }
                    if self.descent(problem) {
                        return Ok(Direction::Shifted(tau));
                    }
                }
                Err(FactorError::NonFinite { .. }) => return Err(Termination::NonFinite),
                Err(_) => {}
            }
            if tau == 0.0 && self.opts.modified_pivots {
                // not positive definite: the modified factorisation, where
                // the problem offers it (a problem that does not may treat
                // it as symmetric pivots: its inertia then has negatives)
                rep.factorizations += 1;
                self.cap = self.opts.max_step;
                match problem.factor(0.0, PivotKind::Modified) {
                    Ok(inertia) if inertia.negative == 0 && self.descent(problem) => {
                        return Ok(Direction::Modified);
                    }
                    Err(FactorError::NonFinite { .. }) => return Err(Termination::NonFinite),
                    _ => {}
                }
            }
            tau = if tau == 0.0 {
                self.first_shift(problem, last_tau)
            } else {
                2.0 * tau
            };
        }
        Err(Termination::Singular)
    }

    /// The first nonzero shift: enough to make the diagonal positive, and
    /// not far below the shift the previous iteration needed (`last_tau`;
    /// read only once the unshifted factorisation has failed: factorising
    /// leaves the matrix as it was, so the diagonal is the same then).
    /// Under a finite cap, no larger than a shift whose gradient step is
    /// about the cap long (type-level docs). Off the path of a Hessian
    /// that factorises, hence cold.
    #[cold]
    #[inline(never)]
    fn first_shift<P: Hessian + ?Sized>(&self, problem: &P, last_tau: f64) -> f64 {
        let (dmin, dmax) = problem.diagonal_range();
        let scale = if dmax > 0.0 { dmax } else { 1.0 };
        let reach = if self.cap.is_finite() {
            norm_inf(&self.g) / self.cap
        } else {
            f64::INFINITY
        };
        let beta = (SHIFT_BASE * scale).min(reach.max(SHIFT_FLOOR * scale));
        (if dmin > 0.0 { beta } else { beta - dmin }).max(0.5 * last_tau)
    }

    /// `self.p = -H^-1 g` with the factorisation at hand, shortened to
    /// the cap, with its `g^T p` and norm; whether it is finite and a
    /// direction of descent.
    fn descent<P: Hessian + ?Sized>(&mut self, problem: &mut P) -> bool {
        for (pi, gi) in self.p.iter_mut().zip(&self.g) {
            *pi = -gi;
        }
        problem.solve(&mut self.p);
        let gtp = dot(&self.g, &self.p);
        if !(all_finite(&self.p) && gtp < 0.0) {
            return false;
        }
        let len = norm_inf(&self.p);
        self.capped = len > self.cap;
        (self.gtp, self.pnorm) = (gtp, len);
        if self.capped {
            let s = self.cap / len;
            self.p.iter_mut().for_each(|v| *v *= s);
            (self.gtp, self.pnorm) = (dot(&self.g, &self.p), norm_inf(&self.p));
        }
        true
    }
}

//! Outcome of a solve: why it stopped and what it cost.

use core::fmt;

/// Why a solver stopped. This is data, not an error: only
/// [`Termination::Converged`] means the tolerances were met.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Termination {
    /// The convergence test passed (gradient, and for bordered solves the
    /// target residual, within tolerance).
    Converged,
    /// The accepted step became negligible (`xtol`) before the gradient met
    /// `gtol`; the iterate is stalled, not certified.
    StepTolerance,
    /// The iteration limit was reached.
    MaxIterations,
    /// Backtracking could not find an acceptable step (the step fraction
    /// fell below `min_step_fraction`, or the evaluation budget ran out).
    LineSearchFailed,
    /// The objective returned a non-finite value (or refused to evaluate)
    /// at the start point or at an accepted point, or at every trial point
    /// of a line search.
    NonFinite,
    /// The linear system could not be solved: the shifted Cholesky failed
    /// for every shift tried, or the bordered LU met a (numerically) zero
    /// pivot.
    Singular,
    /// The solver or driver was given invalid options or a non-finite
    /// parameter; nothing was evaluated.
    InvalidInput,
}

impl Termination {
    /// True only for [`Termination::Converged`].
    pub fn is_converged(self) -> bool {
        self == Termination::Converged
    }
}

impl fmt::Display for Termination {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let s = match self {
            Termination::Converged => "converged: residual within tolerance",
            Termination::StepTolerance => {
                "stalled: step below the step tolerance before the residual met its tolerance"
            }
            Termination::MaxIterations => "iteration limit reached before convergence",
            Termination::LineSearchFailed => "line search failed to find an acceptable step",
            Termination::NonFinite => "objective returned a non-finite value",
            Termination::Singular => "linear system singular: no usable factorisation",
            Termination::InvalidInput => "invalid options or parameters: nothing was evaluated",
        };
        f.write_str(s)
    }
}

/// Summary of one solve.
///
/// Counters count calls made to the objective by this solve. Fields whose
/// value is unknown because nothing finite was ever evaluated hold
/// `f64::INFINITY` (never NaN), so reports compare with `==`.
#[derive(Clone, Debug, PartialEq)]
pub struct Report {
    /// Why the solver stopped.
    pub reason: Termination,
    /// Number of accepted steps (all kinds: the counts below say how many
    /// were chord steps, shifted or damped).
    pub iterations: usize,
    /// Accepted chord steps: the last factorisation reused, only the
    /// gradient evaluated (included in `iterations`).
    pub chord_steps: usize,
    /// Accepted steps along a modified Hessian's direction, shifted (`tau >
    /// 0`) or with modified pivots
    /// ([`NewtonOptions::modified_pivots`](crate::NewtonOptions::modified_pivots)):
    /// the Hessian was not positive definite there.
    pub shifted_steps: usize,
    /// Accepted steps the line search shortened (step fraction below 1).
    pub damped_steps: usize,
    /// Times the step cap was doubled
    /// ([`NewtonOptions::step_growth`](crate::NewtonOptions::step_growth)):
    /// 0 means every step was held to `max_step`, as without the option.
    pub grown_steps: usize,
    /// Times a step along a modified Hessian was doubled
    /// ([`NewtonOptions::extend_modified`](crate::NewtonOptions::extend_modified)):
    /// 0 means every such step kept the length its shift gave it.
    pub extended_steps: usize,
    /// Calls to [`Energy::energy`](crate::Energy::energy).
    pub energy_evals: usize,
    /// Calls to [`Gradient::gradient`](crate::Gradient::gradient).
    pub gradient_evals: usize,
    /// Calls to [`Hessian::hessian`](crate::Hessian::hessian) (for bordered
    /// solves: calls to [`Bordered::eval`](crate::Bordered::eval)).
    pub hessian_evals: usize,
    /// Final residual: `||g||_inf` (bordered solves: `max(||g||_inf, |c|)`).
    pub residual_norm: f64,
    /// Infinity norm of the last accepted step (0 if none was taken).
    pub step_norm: f64,
    /// Final objective value (bordered solves: the merit `||F||^2 / 2`).
    pub energy: f64,
    /// Number of matrix factorisations (Newton: one per shift tried;
    /// bordered: one per iteration).
    pub factorizations: usize,
    /// Largest Hessian shift `tau` used (0 when every Newton step used the
    /// unmodified Hessian; always 0 for bordered solves).
    pub max_shift: f64,
}

impl Report {
    /// True when the solve met its convergence test.
    pub fn converged(&self) -> bool {
        self.reason.is_converged()
    }

    /// A report of no work: zero counts, an infinite residual, the given
    /// reason (for callers that build reports, e.g. around [`continuation`](crate::continuation)).
    pub fn empty(reason: Termination) -> Self {
        Self {
            reason,
            iterations: 0,
            chord_steps: 0,
            shifted_steps: 0,
            damped_steps: 0,
            grown_steps: 0,
            extended_steps: 0,
            energy_evals: 0,
            gradient_evals: 0,
            hessian_evals: 0,
            factorizations: 0,
            residual_norm: f64::INFINITY,
            step_norm: 0.0,
            energy: f64::INFINITY,
            max_shift: 0.0,
        }
    }
}

impl fmt::Display for Report {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} after {} iterations (|r| = {:.3e}, |step| = {:.3e}, energy = {:.6e}, evals E/G/H = {}/{}/{}, factorisations {}, max shift = {:.3e})",
            self.reason,
            self.iterations,
            self.residual_norm,
            self.step_norm,
            self.energy,
            self.energy_evals,
            self.gradient_evals,
            self.hessian_evals,
            self.factorizations,
            self.max_shift
        )
    }
}

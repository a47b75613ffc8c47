//! Solver options with validation.
//!
//! Every options struct has public fields, a [`Default`] and a `validate`
//! method. Solvers never panic on bad option
//! values: constructing a solver with invalid options (e.g. fields assigned
//! directly to NaN) makes every solve return
//! [`Termination::InvalidInput`](crate::Termination::InvalidInput) without
//! evaluating the objective; `try_new` constructors report the
//! [`OptionsError`] up front instead.

/// An option value that breaks its rule.
///
/// Names the option, the offending value and the rule it must satisfy.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("invalid option `{name}` = {value}: {rule}")]
pub struct OptionsError {
    /// Name of the option (the struct field name).
    pub name: &'static str,
    /// The rejected value (integers are converted to `f64`).
    pub value: f64,
    /// The rule the value must satisfy.
    pub rule: &'static str,
}

impl OptionsError {
    fn new(name: &'static str, value: f64, rule: &'static str) -> Self {
        Self { name, value, rule }
    }
}

fn check_nonneg(name: &'static str, v: f64) -> Result<(), OptionsError> {
    if v.is_finite() && v >= 0.0 {
        Ok(())
    } else {
        Err(OptionsError::new(name, v, "must be finite and >= 0"))
    }
}

fn check_positive(name: &'static str, v: f64) -> Result<(), OptionsError> {
    if v.is_finite() && v > 0.0 {
        Ok(())
    } else {
        Err(OptionsError::new(name, v, "must be finite and > 0"))
    }
}

/// A limit: positive, `+inf` for none.
fn check_limit(name: &'static str, v: f64, rule: &'static str) -> Result<(), OptionsError> {
    if v.is_nan() || v <= 0.0 {
        Err(OptionsError::new(name, v, rule))
    } else {
        Ok(())
    }
}

/// Whether a continuation's largest step may be infinite.
#[derive(Clone, Copy, PartialEq)]
enum Max {
    MayBeInfinite,
    Finite,
}

/// The step bounds of a continuation: `0 < min <= initial <= max`, all
/// finite (`max` too unless it [`Max::MayBeInfinite`]).
fn check_steps(initial: f64, min: f64, max: f64, max_rule: Max) -> Result<(), OptionsError> {
    check_positive("min_step", min)?;
    let (max_ok, max_rule_text) = match max_rule {
        Max::MayBeInfinite => (!max.is_nan() && max >= min, "must be >= min_step"),
        Max::Finite => (
            max.is_finite() && max >= min,
            "must be finite and >= min_step",
        ),
    };
    if !max_ok {
        return Err(OptionsError::new("max_step", max, max_rule_text));
    }
    if !(initial.is_finite() && initial >= min && initial <= max) {
        let rule = match max_rule {
            Max::MayBeInfinite => "must be finite and lie in [min_step, max_step]",
            Max::Finite => "must lie in [min_step, max_step]",
        };
        return Err(OptionsError::new("initial_step", initial, rule));
    }
    Ok(())
}

/// A continuation's step growth factor: finite and at least 1.
fn check_grow(grow: f64) -> Result<(), OptionsError> {
    if grow.is_finite() && grow >= 1.0 {
        Ok(())
    } else {
        Err(OptionsError::new("grow", grow, "must be finite and >= 1"))
    }
}

fn check_open_unit(name: &'static str, v: f64) -> Result<(), OptionsError> {
    if v > 0.0 && v < 1.0 {
        Ok(())
    } else {
        Err(OptionsError::new(
            name,
            v,
            "must lie in the open interval (0, 1)",
        ))
    }
}

/// Options of [`Newton`](crate::Newton) (both `minimize` and `solve_bordered`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct NewtonOptions {
    /// Convergence: infinity norm of the gradient `<= gtol` (absolute). Default 1e-10.
    pub gtol: f64,
    /// Step tolerance: stop when the accepted step satisfies
    /// `||s||_inf <= xtol * (1 + ||x||_inf)`. Default 1e-14.
    pub xtol: f64,
    /// Bordered solves only: convergence also needs `|c| <= ctol`. Default 1e-10.
    pub ctol: f64,
    /// Maximum number of Newton iterations (accepted steps). Default 100.
    pub max_iter: usize,
    /// Armijo sufficient-decrease constant `c1` in (0, 1). Default 1e-4.
    pub c1: f64,
    /// Backtracking gives up (`LineSearchFailed`) once the step fraction
    /// `alpha` falls below this value, in (0, 1). Default 1e-10.
    pub min_step_fraction: f64,
    /// Largest infinity norm of a Newton step before the line search (the
    /// direction is shortened to it): keeps iterates in the basin where the
    /// model is meant to hold when the energy is unbounded far away. Positive;
    /// default `f64::INFINITY` (no cap).
    pub max_step: f64,
    /// In the quadratic phase (the previous step was a full, unshifted
    /// Newton step), evaluate the full step's landing point with the
    /// Hessian straight away (or only the gradient when the quadratic model
    /// predicts convergence there), falling back to the line search if it
    /// fails the Armijo test. Saves an energy evaluation per iteration and
    /// the final Hessian; the price is that a rejected trial point has had
    /// its Hessian evaluated. On a problem that stages its Hessians
    /// ([`Hessian::stages_hessian`](crate::Hessian::stages_hessian)) the
    /// same holds before the quadratic phase for every unshifted step not
    /// shortened to [`max_step`](Self::max_step) (see [`Newton`](crate::Newton)).
    /// Default true.
    pub eager_full_steps: bool,
    /// With [`eager_full_steps`](Self::eager_full_steps), in the quadratic
    /// phase: when the quadratic model predicts that the full step reduces
    /// the gradient at least tenfold and a few more such steps converge
    /// (or, after a line search, when a full unshifted step decreased the
    /// energy as the quadratic model said to 1 %), evaluate only the
    /// gradient where it lands, and take chord steps (the
    /// last factorised Hessian again, with a fresh gradient) while the last
    /// step cut the gradient tenfold and at most two more at that rate
    /// reach `gtol` (at most four in all); the Hessian is evaluated when
    /// they stop short of convergence. Close to a minimum a chord step
    /// costs a gradient and a solve instead of a Hessian, a factorisation
    /// and a solve. Needs problems whose [`energy`](crate::Energy::energy)
    /// and [`gradient`](crate::Gradient::gradient) leave the Hessian and
    /// its factorisation alone. Default true.
    pub chord_steps: bool,
    /// The start is known to lie close to the minimum (a nested
    /// iteration's prolongated state): with
    /// [`chord_steps`](Self::chord_steps), the first full step is
    /// evaluated with its gradient instead of its energy, so that chord
    /// steps can follow it without another evaluation. A rejected first
    /// step then costs a gradient instead of an energy. Default false.
    pub trusted_start: bool,
    /// Chord steps go on until the gradient norm is this fraction of
    /// `gtol`, in `(0, 1]`. They converge linearly, so one that stops just
    /// under `gtol` leaves the softest directions less accurate than the
    /// landing of a full Newton step, which overshoots the tolerance
    /// quadratically; a fraction below 1 buys that accuracy back with a
    /// step or two more. Default 1.
    pub chord_depth: f64,
    /// Where the Hessian is not positive definite, take the direction from
    /// its modified factorisation ([`PivotKind::Modified`](crate::PivotKind::Modified):
    /// negative curvature turned positive, positive curvature kept) before
    /// falling back to shifting the whole diagonal. For one block that is
    /// the Hessian with its negative eigenvalues' signs flipped; along a
    /// chain of blocks a flipped pivot is a Schur complement's, and its
    /// step can carry the whole chain into another basin. Default false.
    pub modified_pivots: bool,
    /// Let the step cap act as a trust region's radius: with a finite
    /// [`max_step`](Self::max_step), a Newton step on a positive definite
    /// Hessian shortened to the cap and taken whole doubles the cap for the
    /// next step (up to 16 times `max_step`; [`Report::grown_steps`](crate::Report::grown_steps)
    /// counts the doublings), while a step the line search shortens, or
    /// one along a modified Hessian, resets it. Like `modified_pivots`, it
    /// can change which minimum a start far from every minimum ends in.
    /// Default false.
    pub step_growth: bool,
    /// Let a step along a modified (shifted or modified-pivot) Hessian
    /// grow: where its full length is accepted it is doubled while the
    /// energy keeps falling and Armijo holds (within the step cap). Along
    /// negative curvature the quadratic model has no minimum, so the shift
    /// keeps such a step short of where the energy stops falling
    /// ([`Report::extended_steps`](crate::Report::extended_steps) counts
    /// the doublings). Like `step_growth`, it can change which minimum a
    /// start far from every minimum ends in. Default false.
    pub extend_modified: bool,
}

impl Default for NewtonOptions {
    fn default() -> Self {
        Self {
            gtol: 1e-10,
            xtol: 1e-14,
            ctol: 1e-10,
            max_iter: 100,
            c1: 1e-4,
            min_step_fraction: 1e-10,
            max_step: f64::INFINITY,
            eager_full_steps: true,
            chord_steps: true,
            trusted_start: false,
            chord_depth: 1.0,
            modified_pivots: false,
            step_growth: false,
            extend_modified: false,
        }
    }
}

impl NewtonOptions {
    /// Checks every field against its rule.
    pub fn validate(&self) -> Result<(), OptionsError> {
        check_nonneg("gtol", self.gtol)?;
        check_nonneg("xtol", self.xtol)?;
        check_nonneg("ctol", self.ctol)?;
        check_open_unit("c1", self.c1)?;
        check_open_unit("min_step_fraction", self.min_step_fraction)?;
        check_limit(
            "max_step",
            self.max_step,
            "must be positive (infinity for no cap)",
        )?;
        if !(self.chord_depth > 0.0 && self.chord_depth <= 1.0) {
            return Err(OptionsError::new(
                "chord_depth",
                self.chord_depth,
                "must lie in (0, 1]",
            ));
        }
        Ok(())
    }
}

/// Options of the [`continuation`](crate::continuation()) driver.
///
/// Step lengths are absolute, in units of the continuation parameter.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContinuationOptions {
    /// First step length (`min_step <= initial_step <= max_step`). Default 0.1.
    pub initial_step: f64,
    /// The driver stops (incomplete) when the step would shrink below this (> 0). Default 1e-6.
    pub min_step: f64,
    /// Largest step length (may be `+inf`). Default 1.
    pub max_step: f64,
    /// Step growth factor after an easy success (finite, >= 1). Default 2.
    pub grow: f64,
    /// Step shrink factor after a failure, in (0, 1). Default 0.5.
    pub shrink: f64,
    /// Maximum number of solve attempts (accepted + rejected). Default 1000.
    pub max_steps: usize,
    /// A success is "easy" (the step grows) when the solve needed at most
    /// this many iterations. Default 4.
    pub easy_iterations: usize,
    /// Use the secant predictor from the last two accepted states
    /// (otherwise the last accepted state is the start of each solve). Default true.
    pub predictor: bool,
}

impl Default for ContinuationOptions {
    fn default() -> Self {
        Self {
            initial_step: 0.1,
            min_step: 1e-6,
            max_step: 1.0,
            grow: 2.0,
            shrink: 0.5,
            max_steps: 1000,
            easy_iterations: 4,
            predictor: true,
        }
    }
}

impl ContinuationOptions {
    /// The rule on `max_step` (infinity: no largest step).
    const MAX_STEP: Max = Max::MayBeInfinite;

    /// Checks every field against its rule.
    pub fn validate(&self) -> Result<(), OptionsError> {
        check_steps(
            self.initial_step,
            self.min_step,
            self.max_step,
            Self::MAX_STEP,
        )?;
        check_grow(self.grow)?;
        check_open_unit("shrink", self.shrink)?;
        Ok(())
    }
}

/// Options of the pseudo-arclength continuation driver [`Palc`](crate::Palc).
///
/// Step lengths are pseudo-arclengths in the weighted norm
/// `||(dx, dlambda)||_theta = sqrt(||dx||_2^2 + theta^2 dlambda^2)` (see
/// [`theta`](Self::theta)).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PalcOptions {
    /// First step length (`min_step <= initial_step <= max_step`). Default 0.05.
    pub initial_step: f64,
    /// Smallest step length (finite, > 0): a failure at this length ends the
    /// branch ([`PathTermination::StepTooSmall`](crate::PathTermination::StepTooSmall)
    /// or [`NonFinite`](crate::PathTermination::NonFinite)). Default 1e-8.
    pub min_step: f64,
    /// Largest step length (finite, `>= min_step`). Default 0.5.
    pub max_step: f64,
    /// Step growth factor after an easy corrector solve (finite, >= 1). Default 1.5.
    pub grow: f64,
    /// Step shrink factor after a rejected step, in (0, 1). Default 0.5.
    pub shrink: f64,
    /// Largest number of accepted steps (points after the start). Default 10 000.
    pub max_steps: usize,
    /// Weight `theta` of the load in the arclength norm (finite, > 0): one
    /// unit of `lambda` counts as `theta` units of `x`. Default 1.
    pub theta: f64,
    /// Corrector convergence: `||g||_inf <= gtol` (absolute; finite, >= 0). Default 1e-10.
    pub gtol: f64,
    /// Newton iterations allowed per corrector solve (>= 1). Default 8.
    pub max_corrector_iterations: usize,
    /// A corrector solve needing at most this many iterations lets the step
    /// grow. Default 3.
    pub easy_iterations: usize,
    /// A corrector iterate farther than `max_correction * ds` (weighted
    /// norm) from its predictor rejects the step: guards against jumping to
    /// another branch (> 0, may be infinite). Default 1.
    pub max_correction: f64,
    /// A step whose new tangent makes `cos(angle) < min_tangent_cos` with
    /// the previous one (weighted inner product) is rejected: bounds the
    /// turn of the branch per step, so events are not stepped over, in
    /// [-1, 1] (-1: no check). Default 0.95.
    pub min_tangent_cos: f64,
    /// Detect folds and inertia changes between accepted points, and locate
    /// them. Default true.
    pub detect_events: bool,
    /// Events are located to this pseudo-arclength along the step (finite,
    /// > 0; see [`Palc`](crate::Palc) for what it means in `x` and `lambda`). Default 1e-10.
    pub event_tol: f64,
    /// Corrector solves allowed to locate one event (0: events are reported
    /// at the accepted point after them, unlocated). Default 100.
    pub max_locate_iterations: usize,
    /// A step across which the inertia of `H`, or its inertia restricted
    /// to the problem's constraint ([`crate::Path::constraint`]), changes
    /// is retried shorter until it is at most this long (finite, >= 0; 0:
    /// no such check). A change seen across a long step may be a jump to
    /// another branch passing close by rather than an event of this one;
    /// across a step this short it is this branch's. Default 0.
    pub event_step: f64,
}

impl Default for PalcOptions {
    fn default() -> Self {
        Self {
            initial_step: 0.05,
            min_step: 1e-8,
            max_step: 0.5,
            grow: 1.5,
            shrink: 0.5,
            max_steps: 10_000,
            theta: 1.0,
            gtol: 1e-10,
            max_corrector_iterations: 8,
            easy_iterations: 3,
            max_correction: 1.0,
            min_tangent_cos: 0.95,
            detect_events: true,
            event_tol: 1e-10,
            max_locate_iterations: 100,
            event_step: 0.0,
        }
    }
}

impl PalcOptions {
    /// The rule on `max_step`.
    const MAX_STEP: Max = Max::Finite;

    /// Checks every field against its rule.
    pub fn validate(&self) -> Result<(), OptionsError> {
        check_steps(
            self.initial_step,
            self.min_step,
            self.max_step,
            Self::MAX_STEP,
        )?;
        check_grow(self.grow)?;
        check_open_unit("shrink", self.shrink)?;
        check_positive("theta", self.theta)?;
        check_nonneg("gtol", self.gtol)?;
        if self.max_corrector_iterations == 0 {
            return Err(OptionsError::new(
                "max_corrector_iterations",
                0.0,
                "must be >= 1",
            ));
        }
        check_limit(
            "max_correction",
            self.max_correction,
            "must be > 0 (infinity for no check)",
        )?;
        if !(self.min_tangent_cos >= -1.0 && self.min_tangent_cos <= 1.0) {
            return Err(OptionsError::new(
                "min_tangent_cos",
                self.min_tangent_cos,
                "must lie in [-1, 1]",
            ));
        }
        check_positive("event_tol", self.event_tol)?;
        check_nonneg("event_step", self.event_step)?;
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn defaults_are_valid() {
        NewtonOptions::default().validate().unwrap();
        ContinuationOptions::default().validate().unwrap();
        PalcOptions::default().validate().unwrap();
    }

    #[test]
    fn nan_and_out_of_range_are_rejected_with_names() {
        let newton = |o: NewtonOptions| o.validate().unwrap_err().name;
        let d = NewtonOptions::default();
        let e = NewtonOptions {
            gtol: f64::NAN,
            ..d
        }
        .validate()
        .unwrap_err();
        assert_eq!(e.name, "gtol");
        assert!(e.to_string().contains("gtol"));
        assert_eq!(newton(NewtonOptions { xtol: -1.0, ..d }), "xtol");
        assert_eq!(
            newton(NewtonOptions {
                ctol: f64::INFINITY,
                ..d
            }),
            "ctol"
        );
        assert_eq!(newton(NewtonOptions { c1: 1.0, ..d }), "c1");
        assert_eq!(
            newton(NewtonOptions {
                min_step_fraction: 0.0,
                ..d
            }),
            "min_step_fraction"
        );
        let continuation = |o: ContinuationOptions| o.validate().unwrap_err().name;
        let d = ContinuationOptions::default();
        let initial_step = f64::NAN;
        assert_eq!(
            continuation(ContinuationOptions { initial_step, ..d }),
            "initial_step"
        );
        assert_eq!(continuation(ContinuationOptions { grow: 0.5, ..d }), "grow");
        assert_eq!(
            continuation(ContinuationOptions { shrink: 1.0, ..d }),
            "shrink"
        );
        let d = PalcOptions::default();
        let palc = |o: PalcOptions| o.validate().unwrap_err().name;
        assert_eq!(
            palc(PalcOptions {
                initial_step: 1.0,
                ..d
            }),
            "initial_step"
        );
        assert_eq!(
            palc(PalcOptions {
                event_tol: 0.0,
                ..d
            }),
            "event_tol"
        );
    }
}

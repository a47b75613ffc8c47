//! Error paths of the library: bad input is rejected with a typed error
//! naming the field, the value and the rule on one line; what is merely
//! unusual (a mounting angle outside the design space, a prestrain outside
//! the fitted range) is a warning; and solves that genuinely fail return
//! [`SolveError::NotConverged`] with the last iterate's diagnostics,
//! without panicking and without NaN.
//!
//! The actuator's and the partition's rules are in
//! tests/actuator_validation.rs, the scene keys in src/scene/, and which
//! field the load and guess errors of `Finger::solve` name in
//! tests/finger/input.rs; these modules cover the rest, one per subject.

#[path = "../common/plans.rs"]
mod plans;
use plans::solve_to_tip_tolerance;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_3};
use std::fmt::{Debug, Display};
use std::panic::{catch_unwind, AssertUnwindSafe};

use fpc::actuator::{Prestressed, PsiLaw, EPS0_FIT_RANGE};
use fpc::finger::{Solver, Strategy, TargetProblem};
use fpc::gripper::design_space;
use fpc::plan::MAX_REFINED_ELEMENTS;
use fpc::studies::study7_curvature;
use fpc::{
    Actuator, ActuatorParams, Coefficients, Finger, Gripper, GripperParams, InputError, Load,
    ModelId, PalmSpec, Partition, Plan, PlannedFinger, Solution, SolveError, SolveOptions,
    StudyOptions, Termination, Warning,
};

// ---------------------------------------------------------------- helpers

/// The message of `e`, checked to be one non-empty line.
pub(crate) fn one_line(e: &impl Display) -> String {
    let msg = e.to_string();
    assert!(
        !msg.is_empty() && !msg.contains('\n') && !msg.contains('\r'),
        "not one line: {msg:?}"
    );
    msg
}

/// `e` names `field`, shows `value` as `field = value:` and states `rule`,
/// all on one line.
pub(crate) fn names(e: &InputError, field: &str, value: f64, rule: &str) {
    let msg = one_line(e);
    assert_eq!(e.field(), field, "{msg}");
    // (a value far from 1 is written with an exponent: 1e-12, 1e308)
    assert!(
        msg.starts_with(&format!("{field} = {value}: "))
            || msg.starts_with(&format!("{field} = {value:e}: ")),
        "{msg} does not show {field} = {value}"
    );
    assert!(msg.contains(rule), "{msg} does not state {rule:?}");
}

/// `e` is an [`InputError::Inconsistent`] of `field` stating `rule`.
pub(crate) fn inconsistent(e: &InputError, field: &str, rule: &str) {
    let msg = one_line(e);
    assert!(matches!(e, InputError::Inconsistent { .. }), "{e:?}");
    assert_eq!(e.field(), field, "{msg}");
    assert!(msg.starts_with(&format!("{field}: ")), "{msg}");
    assert!(msg.contains(rule), "{msg} does not state {rule:?}");
}

/// The input error of a result that must be one.
pub(crate) fn input<T: Debug>(r: Result<T, SolveError>) -> InputError {
    match r {
        Err(SolveError::Input(e)) => e,
        Err(e) => panic!("expected an input error, got: {e}"),
        Ok(v) => panic!("accepted bad input: {v:?}"),
    }
}

/// Runs `f`, failing the test (instead of unwinding through it) if it panics.
pub(crate) fn no_panic<T>(what: &str, f: impl FnOnce() -> T) -> T {
    catch_unwind(AssertUnwindSafe(f)).unwrap_or_else(|_| panic!("{what}: the library panicked"))
}

/// Every number of a solution is finite (none is NaN).
pub(crate) fn assert_finite_solution(what: &str, s: &Solution) {
    let fin = |v: f64| v.is_finite();
    assert!(s.tip.iter().copied().all(fin), "{what}: tip {:?}", s.tip);
    assert!(fin(s.end_angle), "{what}: end angle {}", s.end_angle);
    assert!(fin(s.energy), "{what}: energy {}", s.energy);
    assert!(
        s.coefficients.iter().flatten().copied().all(fin),
        "{what}: {:?}",
        s.coefficients
    );
    assert!(s.points.iter().flatten().copied().all(fin), "{what}");
    assert!(s.radius.is_none_or(fin), "{what}: radius {:?}", s.radius);
    assert_eq!(
        s.stable,
        s.negative_eigenvalues.map(|k| k == 0),
        "{what}: stability"
    );
    assert!(fin(s.report.residual_norm), "{what}: {:?}", s.report);
    assert!(s.report.reason.is_converged(), "{what}: {:?}", s.report);
}

/// What a failed solve reports.
pub(crate) struct Failure {
    reason: Termination,
    iterations: usize,
    relative_residual: f64,
    element: Option<usize>,
    last: Coefficients,
    message: String,
}

/// The [`SolveError::NotConverged`] of a result that must be one, checked:
/// a one-line message naming the reason, the iterations and the element;
/// a residual that is never NaN; one finite coefficient set per element
/// (`n`) in `last`.
pub(crate) fn failed<T: Debug>(what: &str, n: usize, r: Result<T, SolveError>) -> Failure {
    let e = match r {
        Err(e @ SolveError::NotConverged { .. }) => e,
        Err(e) => panic!("{what}: expected a failed solve, got the input error: {e}"),
        Ok(v) => panic!("{what}: expected a failed solve, got {v:?}"),
    };
    let message = one_line(&e);
    let SolveError::NotConverged {
        reason,
        iterations,
        relative_residual,
        element,
        last,
    } = e
    else {
        unreachable!()
    };
    assert!(!reason.is_converged(), "{what}: {message}");
    assert!(message.starts_with("solve failed"), "{what}: {message}");
    assert!(
        message.contains(&reason.to_string()),
        "{what}: {message} does not name {reason:?}"
    );
    assert!(
        message.contains(&format!("after {iterations} iterations")),
        "{what}: {message}"
    );
    assert!(message.contains("relative residual"), "{what}: {message}");
    assert!(
        !relative_residual.is_nan() && relative_residual >= 0.0,
        "{what}: relative residual {relative_residual}"
    );
    if let Some(i) = element {
        assert!(i < n, "{what}: element {i} of {n}");
        assert!(
            message.contains(&format!("for element {i}")),
            "{what}: {message}"
        );
    }
    assert_eq!(
        last.elements(),
        n,
        "{what}: one coefficient set per element"
    );
    assert!(
        last.as_slice().iter().all(|v| v.is_finite()),
        "{what}: non-finite last iterate {last:?}"
    );
    Failure {
        reason,
        iterations,
        relative_residual,
        element,
        last,
        message,
    }
}

pub(crate) fn tip(fx: f64, fz: f64) -> Load {
    Load::unloaded().with_tip_force(fx, fz)
}

mod failed;
mod gripper;
mod load;
mod partition;
mod refinement;
mod studies;
mod target;

//! Why a solve failed: a rejected input, Newton short of the tolerance
//! (with the last iterate), a target the path does not reach, or work the
//! caller stopped.

use crate::coefficients::Coefficients;
use crate::error::InputError;
use crate::field::Field;
use crate::num::Num;

/// A failed solve's last residual in a message: its value, or words
/// where it is not a finite number (no message shows NaN or inf).
fn residual_text(r: f64) -> String {
    if r.is_finite() {
        format!("relative residual {r:.3e}")
    } else {
        "relative residual not a finite number".into()
    }
}

/// A scene that could not be solved: the input was rejected, or Newton
/// (with continuation where enabled) did not reach the tolerance.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// A rejected input value.
    #[error(transparent)]
    Input(#[from] InputError),
    /// The solver stopped without meeting the residual tolerance.
    #[error(
        "solve failed{}: {reason} after {iterations} iterations ({})",
        element.map(|e| format!(" for element {e}")).unwrap_or_default(),
        residual_text(*relative_residual)
    )]
    NotConverged {
        /// Why Newton stopped.
        reason: fpc_newton::Termination,
        /// Iterations spent.
        iterations: usize,
        /// Last residual over the finger's stiffness scale.
        relative_residual: f64,
        /// The element whose decoupled solve failed, if any.
        element: Option<usize>,
        /// The last iterate's coefficients.
        last: Coefficients,
    },
    /// The target lies beyond a fold of the path that reaches it from rest
    /// (closing a gripper on an object, or pushing a tip): the equilibrium
    /// there belongs to another branch, which that path does not reach;
    /// `detail` says where the path turns back.
    #[error("{target} = {}: not reached on the path from rest: {detail}", Num(*.value))]
    NotOnPath {
        /// The target's field path.
        target: Field,
        /// The target's value.
        value: f64,
        /// Where and how the path turns back.
        detail: String,
    },
    /// A target solve (a grasp size, a force, a displacement) did not
    /// reach its target: the path from the reference state stopped short.
    #[error(
        "{target} = {}: not reached; the path from the unloaded finger stopped at {percent:.0} % of the way ({detail})",
        Num(*value),
        percent = 100.0 * reached
    )]
    TargetNotReached {
        /// The target's field path.
        target: Field,
        /// The target's value.
        value: f64,
        /// How far along the path the last accepted state was (0 to 1).
        reached: f64,
        /// The failure at the step that could not be taken.
        detail: String,
    },
    /// The caller stopped the work ([`crate::cancel`]): no solve was tried.
    #[error("cancelled: the caller asked the work to stop")]
    Cancelled,
}

impl SolveError {
    /// The same error with the field it names (an input error's, a
    /// target's) renamed where `name` gives it another name, the value
    /// converted to that name's unit by `value`; other errors unchanged.
    pub fn renamed(
        self,
        name: impl Fn(&Field) -> Option<Field>,
        value: impl Fn(&Field, f64) -> f64,
    ) -> SolveError {
        let rename = |f: Field, v: f64| match name(&f) {
            Some(n) => (n, value(&f, v)),
            None => (f, v),
        };
        match self {
            SolveError::Input(i) => match name(i.field()) {
                Some(n) => {
                    let f = i.field().clone();
                    SolveError::Input(i.renamed(n, |v| value(&f, v)))
                }
                None => SolveError::Input(i),
            },
            SolveError::TargetNotReached {
                target,
                value: v,
                reached,
                detail,
            } => {
                let (target, value) = rename(target, v);
                SolveError::TargetNotReached {
                    target,
                    value,
                    reached,
                    detail,
                }
            }
            SolveError::NotOnPath {
                target,
                value: v,
                detail,
            } => {
                let (target, value) = rename(target, v);
                SolveError::NotOnPath {
                    target,
                    value,
                    detail,
                }
            }
            e => e,
        }
    }
}

//! Input errors and non-fatal warnings.
//!
//! Every error names the offending field by its path in the input (for
//! example `actuator.geometry.h1` or `partition.lengths[2]`), the value
//! where there is one, and the rule it breaks, on one line.

use std::fmt;

/// A rejected input: one field, its value where it has one, and the rule.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum InputError {
    /// The value is NaN or infinite.
    #[error("{field} = {value}: must be finite")]
    NotFinite { field: String, value: f64 },
    /// The value must be strictly positive.
    #[error("{field} = {value}: must be positive")]
    NotPositive { field: String, value: f64 },
    /// The value lies outside its admissible range; `rule` states the range.
    #[error("{field} = {value}: {rule}")]
    OutOfRange {
        field: String,
        value: f64,
        rule: String,
    },
    /// Several fields together are inconsistent (the layer stack, a
    /// channel outside its layer, overlapping ribs); `rule` says how.
    #[error("{field}: {rule}")]
    Inconsistent { field: String, rule: String },
}

impl InputError {
    /// The path of the offending field.
    pub fn field(&self) -> &str {
        match self {
            InputError::NotFinite { field, .. }
            | InputError::NotPositive { field, .. }
            | InputError::OutOfRange { field, .. }
            | InputError::Inconsistent { field, .. } => field,
        }
    }
}

/// Fails with [`InputError::NotFinite`] unless `value` is finite.
pub(crate) fn finite(field: &str, value: f64) -> Result<f64, InputError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(InputError::NotFinite {
            field: field.to_string(),
            value,
        })
    }
}

/// Fails unless `value` is finite and strictly positive.
pub(crate) fn positive(field: &str, value: f64) -> Result<f64, InputError> {
    finite(field, value)?;
    if value > 0.0 {
        Ok(value)
    } else {
        Err(InputError::NotPositive {
            field: field.to_string(),
            value,
        })
    }
}

/// Fails with [`InputError::OutOfRange`] unless `ok`.
pub(crate) fn require(ok: bool, field: &str, value: f64, rule: String) -> Result<(), InputError> {
    if ok {
        Ok(())
    } else {
        Err(InputError::OutOfRange {
            field: field.to_string(),
            value,
            rule,
        })
    }
}

/// A non-fatal note about an accepted input: the model runs, but the
/// result may be outside what the model was fitted or meant for.
#[derive(Debug, Clone, PartialEq)]
pub enum Warning {
    /// The prestrain lies outside [`lo`, `hi`], the strain range of the
    /// uniaxial test the prestressed law was fitted to (the paper's
    /// samples use 0.15 to 0.4). A negative value means a precompressed
    /// layer.
    Eps0OutsideFit { eps0: f64, lo: f64, hi: f64 },
    /// The prestressed law's tangent modulus psi''(eps0) is not positive:
    /// the unloaded layer softens and equilibria may be unstable.
    SofteningPrestressLaw { eps0: f64, tangent: f64 },
    /// The gripper's mounting angle (rad) lies outside the design space
    /// [`lo`, `hi`] = [arccot mu, pi/2]: fingers pressed flat cannot hold
    /// the object by friction (docs/model.md section 5).
    MountingAngleOutsideDesignSpace { angle: f64, lo: f64, hi: f64 },
    /// The palm diameter exceeds twice the fingers' inward reach
    /// (`palm > 2 l0`, a negative overlap): the fingers leave a gap at rest,
    /// and objects smaller than `palm - 2 l0` cannot be grasped.
    PalmGapAtRest { palm: f64, reach: f64 },
}

impl fmt::Display for Warning {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Warning::Eps0OutsideFit { eps0, lo, hi } => write!(
                f,
                "actuator.pemc.eps0 = {eps0}: outside [{lo}, {hi}], the range the prestressed law was fitted to"
            ),
            Warning::SofteningPrestressLaw { eps0, tangent } => write!(
                f,
                "actuator.pemc.eps0 = {eps0}: the prestressed law's tangent modulus there is {tangent} MPa (not positive)"
            ),
            Warning::MountingAngleOutsideDesignSpace { angle, lo, hi } => write!(
                f,
                "gripper.mounting_angle = {angle}: outside the design space [{lo}, {hi}] (arccot mu to pi/2)"
            ),
            Warning::PalmGapAtRest { palm, reach } => write!(
                f,
                "gripper.palm = {palm}: wider than twice the finger's inward reach l0 = {reach} mm, the fingers leave a gap at rest"
            ),
        }
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
        "solve failed{}: {reason} after {iterations} iterations (relative residual {relative_residual:.3e})",
        element.map(|e| format!(" for element {e}")).unwrap_or_default()
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
        /// The last iterate's coefficients, one `[a1, a3, b1, c2]` per element.
        last: Vec<[f64; 4]>,
    },
}

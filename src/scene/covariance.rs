//! A `[calibration]` covariance, checked when the scene is read: every
//! key a parameter of the scene, the matrix symmetric positive
//! semi-definite (a [`Covariance`] of `crate::sensitivity`; propagated in
//! `uncertainty.rs`).

use nalgebra::{DMatrix, SymmetricEigen};

use crate::actuator::Actuator;
use crate::error::InputError;
use crate::field::Field;
use crate::sensitivity::{Covariance, Param};

use super::schema::CalibrationSection;

/// Relative tolerance of the covariance's symmetry and of its smallest
/// eigenvalue (against the largest): round-off of a fit's inverse.
const PSD_TOLERANCE: f64 = 1e-9;

fn rejected(key: &'static str, rule: String) -> InputError {
    InputError::Inconsistent {
        field: Field::key(key),
        rule,
    }
}

/// The covariance of a `[calibration]` table (already checked for its
/// size and finite entries), or `None` without one: every key must be a
/// parameter of `actuator` (or `load.kappa` in a finger scene), each at
/// most once, and the matrix symmetric positive semi-definite.
pub(super) fn covariance_of(
    c: &CalibrationSection,
    actuator: &Actuator,
    gripper_scene: bool,
) -> Result<Option<Covariance>, InputError> {
    let Some(m) = &c.covariance else {
        return Ok(None);
    };
    let known = Param::all(actuator);
    let mut params = Vec::with_capacity(c.parameters.len());
    for name in &c.parameters {
        let p = Param::from_name(name)
            .filter(|p| matches!(p, Param::Actuator(_) | Param::Kappa) && known.contains(p))
            .ok_or_else(|| InputError::Unrecognised {
                field: Field::key("calibration.parameters"),
                value: name.clone(),
                rule: "not a parameter of this scene's actuator or load.kappa".into(),
            })?;
        if gripper_scene && p == Param::Kappa {
            return Err(rejected(
                "calibration.parameters",
                "load.kappa is not a parameter of a gripper scene (its grasps are solved at kappa's default)".into(),
            ));
        }
        if params.contains(&p) {
            return Err(InputError::Unrecognised {
                field: Field::key("calibration.parameters"),
                value: name.clone(),
                rule: "named twice".into(),
            });
        }
        params.push(p);
    }
    let n = params.len();
    let scale = (0..n).map(|i| m[i][i].abs()).fold(0.0, f64::max);
    for i in 0..n {
        if m[i][i] < 0.0 {
            return Err(rejected(
                "calibration.covariance",
                format!(
                    "a variance must not be negative (row {}: {})",
                    i + 1,
                    m[i][i]
                ),
            ));
        }
        for j in 0..i {
            let tol = PSD_TOLERANCE * (m[i][i] * m[j][j]).sqrt().max(f64::MIN_POSITIVE);
            if (m[i][j] - m[j][i]).abs() > tol {
                return Err(rejected(
                    "calibration.covariance",
                    format!("must be symmetric (rows {} and {} differ)", j + 1, i + 1),
                ));
            }
            // the correlation scaling below cannot see a covariance beside
            // a zero variance, which semi-definiteness forbids
            if (m[i][i] == 0.0 || m[j][j] == 0.0) && m[i][j] != 0.0 {
                return Err(rejected(
                    "calibration.covariance",
                    format!(
                        "must be positive semi-definite (rows {} and {} covary beside a zero variance)",
                        j + 1,
                        i + 1
                    ),
                ));
            }
        }
    }
    if n > 0 && scale > 0.0 {
        // eigenvalues of the correlation-scaled matrix, so keys of very
        // different units weigh alike
        let d: Vec<f64> = (0..n)
            .map(|i| {
                if m[i][i] > 0.0 {
                    1.0 / m[i][i].sqrt()
                } else {
                    0.0
                }
            })
            .collect();
        let a = DMatrix::from_fn(n, n, |i, j| 0.5 * (m[i][j] + m[j][i]) * d[i] * d[j]);
        let eig = SymmetricEigen::new(a).eigenvalues;
        let max = eig.iter().fold(0.0_f64, |a, &b| a.max(b.abs()));
        let min = eig.iter().fold(f64::INFINITY, |a, &b| a.min(b));
        if min < -PSD_TOLERANCE.sqrt() * max.max(1.0) {
            return Err(rejected(
                "calibration.covariance",
                format!("must be positive semi-definite (a correlation eigenvalue is {min:.3e})"),
            ));
        }
    }
    Ok(Some(Covariance::checked(params, m.clone())))
}

//! The sensitivities of one equilibrium, one row per parameter.

use crate::coefficients::Coefficients;

use super::params::Param;

/// The derivatives of an equilibrium's outputs with respect to one
/// parameter, per unit of the parameter's key.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Sensitivity {
    /// The parameter.
    pub param: Param,
    /// Its value at the equilibrium (in its key's unit).
    pub value: f64,
    /// d(tip X, tip Z)/dp (mm per unit).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// d(end angle)/dp (rad per unit).
    #[serde(rename = "end_angle_rad")]
    pub end_angle: f64,
    /// d(Pi)/dp (N mm per unit), the total potential's total derivative.
    #[serde(rename = "energy_nmm")]
    pub energy: f64,
    /// d(lambda)/dp for a target solve (`None` otherwise).
    pub lambda: Option<f64>,
    /// dK/dp: the derivative of the raw element unknowns.
    pub coefficients: Coefficients,
}

/// The sensitivities of one equilibrium ([`Finger::sensitivities`](crate::Finger::sensitivities),
/// [`Finger::target_sensitivities`](crate::Finger::target_sensitivities)), one row per parameter asked for, in
/// that order.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Sensitivities {
    /// Tip position (X, Z) at the equilibrium (mm).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// End angle at the equilibrium (rad).
    #[serde(rename = "end_angle_rad")]
    pub end_angle: f64,
    /// Total potential at the equilibrium (N mm).
    #[serde(rename = "energy_nmm")]
    pub energy: f64,
    /// The load factor of a target solve (`None` otherwise).
    pub lambda: Option<f64>,
    /// One row per parameter.
    pub rows: Vec<Sensitivity>,
}

impl Sensitivities {
    /// The row of a parameter.
    pub fn get(&self, param: Param) -> Option<&Sensitivity> {
        self.rows.iter().find(|r| r.param == param)
    }
}

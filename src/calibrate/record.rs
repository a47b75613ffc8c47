//! The record of a calibration: fitted values with their errors, the
//! correlations, the identifiability analysis, the fit's quality and its
//! cost.

use serde::Serialize;

use super::crossval::CrossValidation;
use super::identify::Identifiability;
use super::lm::Termination;
use super::residuals::FitResidual;

/// One fitted unknown.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FittedParameter {
    /// `key`, or `key[specimen]` for a specimen's own parameter.
    pub name: String,
    /// The scene key.
    pub key: String,
    /// The specimen of an own parameter (`None`: shared).
    pub specimen: Option<String>,
    /// The manifest's value, where the fit started.
    pub start: f64,
    /// The fitted value.
    pub value: f64,
    /// The standard error from the weighted Jacobian, `sqrt((J^T J)^-1)`
    /// on the diagonal: the data's standard deviations taken as known
    /// (`None`: the covariance does not exist, see the identifiability).
    pub standard_error: Option<f64>,
    /// The same scaled by `sqrt(chi-square per degree of freedom)`: for
    /// standard deviations known only up to a common factor.
    pub scaled_standard_error: Option<f64>,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
    /// The value sits on a bound (its standard error then means little).
    pub at_bound: bool,
}

/// A calibration ([`calibrate`](crate::calibrate::calibrate)).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Calibration {
    /// The manifest.
    pub manifest: String,
    /// The fitted unknowns.
    pub parameters: Vec<FittedParameter>,
    /// The covariance `(J^T J)^-1` of the unknowns, in their order (`None`
    /// where it does not exist).
    pub covariance: Option<Vec<Vec<f64>>>,
    /// The correlation matrix (`None` with the covariance).
    pub correlation: Option<Vec<Vec<f64>>>,
    /// The singular values of the scaled Jacobian and the verdict.
    pub identifiability: Identifiability,
    /// The sum of squared weighted residuals at the fit.
    pub chi_square: f64,
    /// How many residuals.
    pub points: usize,
    /// Degrees of freedom: residuals less unknowns.
    pub dof: usize,
    /// `chi_square / dof` (about 1 for the right model and honest
    /// standard deviations).
    pub chi_square_per_dof: f64,
    /// The chi-square at the start.
    pub start_chi_square: f64,
    /// Every residual at the fit.
    pub residuals: Vec<FitResidual>,
    /// Levenberg-Marquardt iterations.
    pub iterations: usize,
    /// Evaluations of the residuals and Jacobian.
    pub evaluations: usize,
    /// Equilibrium solves, over all evaluations.
    pub solves: usize,
    /// Target solves (forces), over all evaluations.
    pub target_solves: usize,
    /// How the iterations ended.
    pub termination: Termination,
    /// Leave-one-pressure-out prediction errors (when asked for; their
    /// solves are not in `solves` and `target_solves`).
    pub cross_validation: Option<CrossValidation>,
    /// Solves at the fit whose finger is outside the model
    /// (docs/model.md section 8).
    pub outside_model: usize,
    /// The calibrated scenes compared with the data again through the
    /// ordinary path (`fpc compare`'s): the fit's residuals reproduced or
    /// not.
    pub reproduction: Reproduction,
}

/// How far (in standard deviations) a residual of the comparison may lie
/// from the fit's: far above the solves' tolerances (a marker's position
/// to about 1e-9 mm, a force's target solve to 1e-9 of the force), far
/// below anything a reader of the residuals would see.
pub const REPRODUCE_SD: f64 = 1e-6;

/// What [`REPRODUCE_SD`] allows more, relative to the predicted value:
/// two paths that compute a prediction differently agree to a fraction
/// of it, not to a fixed part of a standard deviation many times smaller
/// (the radius of a nearly straight finger, 1e5 mm with a 1 mm standard
/// deviation, agrees to about 1e-8 of itself, 1e-3 sd).
pub const REPRODUCE_RELATIVE: f64 = 1e-7;

/// The calibrated scenes compared with the data again.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Reproduction {
    /// The comparison's chi-square (`None`: the comparison did not run).
    pub chi_square: Option<f64>,
    /// How many residuals it has.
    pub points: usize,
    /// The largest difference between a residual of the comparison and
    /// the fit's (standard deviations).
    pub largest_difference_sd: Option<f64>,
    /// Every row of the fit predicted again, each residual within
    /// [`REPRODUCE_SD`] of the fit's, give or take [`REPRODUCE_RELATIVE`]
    /// of the predicted value.
    pub reproduced: bool,
    /// What the comparison gave, in words.
    pub detail: String,
}

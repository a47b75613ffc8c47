//! Calibration: the parameters that make the model match measurements,
//! how well the data determine them, and which combinations they cannot
//! (docs/calibration.md).
//!
//! [`calibrate`] fits the parameters a [`CalibrateOptions`] names to every
//! test of a measurement [`Manifest`](crate::measure::Manifest) by weighted
//! nonlinear least squares: Levenberg-Marquardt with bounds (`lm.rs`) on
//! the exact Jacobian of the residuals, from the implicit-function-theorem
//! sensitivities of every equilibrium ([`crate::sensitivity`]) carried
//! exactly to each prediction (the marker points through the chain,
//! `crate::sensitivity`'s `midplane.rs`; the circle fit's radius by implicit
//! differentiation, `crate::circle_fit`; `residuals.rs`: the force target
//! solve). A parameter a specimen lists in its `own` tables is
//! fitted once per specimen, any other once for all. The [`Calibration`]
//! gives the fitted values with standard errors, the correlation matrix,
//! the singular values of the column-scaled Jacobian with an
//! identifiability [`Verdict`] naming the worst determined combination
//! (`identify.rs`), chi-square per degree of freedom, residuals, the
//! iterations and solves it took, and its [`Reproduction`]: the calibrated
//! scenes compared with the data again through [`crate::compare`]'s own
//! path (`reproduce.rs`). [`calibrate_with_progress`] and
//! [`choose_model_with_progress`] tell an observer how far they have got
//! ([`CalibrateProgress`]: iterations, evaluations, the current
//! chi-square).
//!
//! ```no_run
//! use fpc::calibrate::{calibrate, CalibrateOptions};
//! use fpc::measure::Manifest;
//!
//! let manifest = Manifest::load("examples/calibration/manifest.toml".as_ref())?;
//! let fit = calibrate(&manifest, &CalibrateOptions::new(&["eps0", "kappa"]))?;
//! for p in &fit.parameters {
//!     println!("{} = {} +- {:?}", p.name, p.value, p.standard_error);
//! }
//! println!("{}", fit.identifiability.message);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod choice;
mod crossval;
mod driver;
mod fit;
mod identify;
mod lm;
mod options;
mod params;
mod progress;
mod record;
mod reproduce;
mod residuals;
mod scene;

pub use choice::{choose_model, choose_model_with_progress, Candidate, ModelChoice};
pub use crossval::{CrossValidation, HeldOut};
pub use driver::STEP_TOLERANCE;
pub use fit::{calibrate, calibrate_with_progress};
pub use identify::{
    Component, Identifiability, Verdict, POORLY_DETERMINED_RATIO, UNIDENTIFIABLE_RATIO,
};
pub use lm::Termination;
pub use options::{
    CalibrateOptions, DEFAULT_ITERATIONS, MAX_FIT_NAMES, MAX_HELD_OUT_PRESSURES, MAX_ITERATIONS,
    MAX_UNKNOWNS,
};
pub use params::Unknown;
pub use progress::{CalibrateProgress, CalibrateStage};
pub use record::{Calibration, FittedParameter, Reproduction, REPRODUCE_RELATIVE, REPRODUCE_SD};
pub use residuals::FitResidual;
pub use scene::calibrated_scenes;

#[cfg(test)]
mod tests;

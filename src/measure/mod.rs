//! Measurements of real fingers, and the model held against them without
//! fitting (docs/measurements.md).
//!
//! A [`Manifest`] (TOML) lists specimens. Each specimen has its actuator,
//! as scene tables (docs/model.md, README "Scene files"): the `[shared]`
//! tables every specimen has (materials, geometry), optionally a scene
//! file, and the specimen's `own` tables (its prestrain `eps0`). Its tests
//! are CSV files with the unit in every column name:
//!
//! - `markers`: points of the mid-plane at their position `s_mm` along
//!   it, at a pressure, in the finger frame or in a camera frame with its
//!   rigid transform to the finger frame ([`CameraFrame`]);
//! - `radius`: the circle-fit radius of the mid-plane at a pressure (the
//!   paper's reduced form, Sec. 6.2);
//! - `force`: the tip force that moves the tip a distance along X or Z
//!   from its pressurised shape (Sec. 6.3).
//!
//! [`Manifest::load`] reads everything before anything is computed; bad
//! input is a [`MeasureError`] naming the file, the row and column (both
//! from 1) and the field. Sizes are bounded before reading further
//! ([`MAX_MANIFEST_BYTES`], [`MAX_DATA_BYTES`], [`MAX_ROWS`],
//! [`MAX_TOTAL_ROWS`], [`MAX_SPECIMENS`], [`MAX_TESTS`]), and so is every
//! measured value, within physical limits generous for any soft finger:
//! pressures from vacuum to [`MAX_PRESSURE_KPA`], lengths (coordinates,
//! radii, displacements, camera offsets) within [`MAX_LENGTH_MM`], forces
//! within [`MAX_FORCE_N`], a camera angle within [`MAX_ANGLE_DEG`],
//! standard deviations from [`MIN_SD`] of their unit to the bound of
//! their quantity, at most [`MAX_REPEATS`] repeats. A bad scene value is
//! named by the key as written where it is written: in the manifest
//! (`shared.actuator.pemc.e2`, `specimen.own.actuator.pemc.eps0`, at that
//! key's line) or in a scene file (its key, at its line).
//!
//! [`compare`] then predicts every measured value, with its residual in
//! units and in standard deviations, the chi-square, and the model's
//! validity verdict on every prediction. A model value that is not finite
//! or beyond 1e100 in magnitude is no prediction (the row's `failure` says
//! so), so every residual and chi-square is a finite number.
//!
//! The types keep what a calibrator needs: which scene keys are a
//! specimen's own parameters ([`Specimen::own`]) and which are shared
//! ([`Manifest::shared`]), and a camera frame's transform as values a fit
//! may treat as nuisance parameters.
//!
//! ```
//! use fpc::measure::Manifest;
//!
//! // the synthetic set of examples/calibration/ (the model plus noise)
//! let manifest = Manifest::load("examples/calibration/manifest.toml".as_ref())?;
//! assert_eq!(manifest.specimens[0].own, ["actuator.pemc.eps0"]);
//! let c = fpc::compare(&manifest)?;
//! // right model, right standard deviations: about one per residual
//! assert!(c.chi_square < 2.0 * c.points as f64);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod comparison;
mod input;
mod manifest;
mod table;

pub use comparison::{
    compare, figures, table, Comparison, ForceCurve, Prediction, Residual, SpecimenComparison,
    TestComparison, COMPARE_COLUMNS, FIGURE_STEMS,
};
pub(crate) use comparison::{compare_with, total};
pub use input::{
    MeasureError, TestKind, MAX_ANGLE_DEG, MAX_DATA_BYTES, MAX_FORCE_N, MAX_LENGTH_MM,
    MAX_MANIFEST_BYTES, MAX_PRESSURE_KPA, MAX_REPEATS, MAX_ROWS, MAX_SCENE_BYTES, MAX_SPECIMENS,
    MAX_TESTS, MAX_TOTAL_ROWS, MIN_SD, VACUUM_KPA,
};
pub use manifest::{CameraFrame, Manifest, Specimen, Test, TestData};
pub use table::{ForceRow, MarkerRow, RadiusRow};

#[cfg(test)]
mod tests;

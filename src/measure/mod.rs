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
//! [`MAX_TOTAL_ROWS`], [`MAX_SPECIMENS`], [`MAX_TESTS`]). [`compare`] then predicts every
//! measured value, with its residual in units and in standard deviations,
//! the chi-square, and the model's validity verdict on every prediction.
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
mod manifest;
mod table;

use std::io::Read as _;
use std::path::Path;

pub use comparison::{
    compare, figures, table, Comparison, ForceCurve, Prediction, Residual, SpecimenComparison,
    TestComparison, COMPARE_COLUMNS,
};
pub use manifest::{CameraFrame, Manifest, Specimen, Test, TestData, TestKind};
pub use table::{ForceRow, MarkerRow, RadiusRow};

/// Largest manifest file (bytes): 1 MiB.
pub const MAX_MANIFEST_BYTES: u64 = 1 << 20;
/// Largest scene file a manifest names (bytes): 4 MiB, as `fpc solve`.
pub const MAX_SCENE_BYTES: u64 = 4 << 20;
/// Largest CSV file of a test (bytes): 16 MiB.
pub const MAX_DATA_BYTES: u64 = 16 << 20;
/// Most data rows of one CSV file (the header and comment lines not
/// counted).
pub const MAX_ROWS: usize = 10_000;
/// Most data rows of all the test files of a manifest together.
pub const MAX_TOTAL_ROWS: usize = 4 * MAX_ROWS;
/// Most specimens of a manifest.
pub const MAX_SPECIMENS: usize = 64;
/// Most tests of one specimen.
pub const MAX_TESTS: usize = 16;

/// Gauge pressure of absolute vacuum (kPa): no measured pressure is lower.
pub const VACUUM_KPA: f64 = crate::finger::VACUUM_GAUGE_MPA * 1e3;

/// Bad measurement input: the file as the manifest names it (or the
/// manifest itself), the place in it (row and column from 1; for a CSV
/// file the row is the line, the header being row 1; `None` for what
/// concerns the whole file), the field (a column or a manifest key) and
/// why.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{}: {field}: {reason}", place(file, *at))]
pub struct MeasureError {
    /// The file.
    pub file: String,
    /// Row and column (from 1), when the error has a place in the file.
    pub at: Option<(usize, usize)>,
    /// The column or key.
    pub field: String,
    /// What is wrong.
    pub reason: String,
}

fn place(file: &str, at: Option<(usize, usize)>) -> String {
    match at {
        Some((row, col)) => format!("{file}:{row}:{col}"),
        None => file.to_string(),
    }
}

impl MeasureError {
    /// An error at a row and column of `file`.
    pub(crate) fn at(
        file: &str,
        row: usize,
        col: usize,
        field: impl Into<String>,
        reason: impl Into<String>,
    ) -> MeasureError {
        MeasureError {
            file: file.to_string(),
            at: Some((row, col)),
            field: field.into(),
            reason: reason.into(),
        }
    }

    /// The row, when the error has a place.
    pub fn row(&self) -> Option<usize> {
        self.at.map(|a| a.0)
    }

    /// The column, when the error has a place.
    pub fn column(&self) -> Option<usize> {
        self.at.map(|a| a.1)
    }
}

/// Reads at most `limit` bytes of `path` as UTF-8 text: a larger file, one
/// that cannot be read or is not UTF-8 is an error naming `shown` (the
/// file as the user wrote it).
pub(crate) fn read_text(path: &Path, shown: &str, limit: u64) -> Result<String, MeasureError> {
    let whole = |field: &str, reason: String| MeasureError {
        file: shown.to_string(),
        at: None,
        field: field.to_string(),
        reason,
    };
    let file = std::fs::File::open(path).map_err(|e| whole("file", format!("cannot read: {e}")))?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| whole("file", format!("cannot read: {e}")))?;
    if bytes.len() as u64 > limit {
        return Err(whole(
            "file",
            format!("larger than {limit} bytes, the limit for this file"),
        ));
    }
    String::from_utf8(bytes).map_err(|e| {
        let at = e.utf8_error().valid_up_to();
        whole(
            "file",
            format!("not UTF-8 text (invalid byte at offset {at})"),
        )
    })
}

#[cfg(test)]
mod tests;

//! What every file of a manifest shares: the bounds on sizes and counts,
//! the error naming a file, row, column and field, bounded reading of a
//! text file, and the kinds of test.

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::num::Num;

/// The kind of a test (its CSV columns: docs/measurements.md).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum TestKind {
    /// Marker points of the mid-plane.
    Markers,
    /// The circle-fit radius of the mid-plane.
    Radius,
    /// The tip force for a tip displacement.
    Force,
}

impl TestKind {
    /// `markers`, `radius` or `force`.
    pub fn name(self) -> &'static str {
        match self {
            TestKind::Markers => "markers",
            TestKind::Radius => "radius",
            TestKind::Force => "force",
        }
    }
}

/// Largest manifest file (bytes): 1 MiB.
pub const MAX_MANIFEST_BYTES: u64 = 1 << 20;
/// Largest scene file a manifest names (bytes): 4 MiB, the library's
/// bound on every scene file.
pub use crate::scene::MAX_SCENE_BYTES;
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

// The physical bounds of measured values: generous for any soft finger,
// they keep every sum and difference of the comparison (a residual, an
// error bar `value ± sd`, a figure's range, the chi-square) finite.

/// Highest measured pressure (kPa, gauge): 10 MPa, far beyond the burst
/// pressure of an elastomer actuator.
pub const MAX_PRESSURE_KPA: f64 = 1e4;
/// Largest magnitude of a measured length (mm): a point's coordinate, a
/// radius, a displacement, a camera offset and a standard deviation in
/// mm; 100 m, the actuator's own bound on its dimensions
/// ([`crate::actuator::MAX_DIMENSION_MM`]).
pub const MAX_LENGTH_MM: f64 = crate::actuator::MAX_DIMENSION_MM;
/// Largest magnitude of a measured force and of its standard deviation
/// (N): ten times the largest grasp force the library follows
/// ([`crate::gripper::MAX_GRASP_FORCE_N`]).
pub const MAX_FORCE_N: f64 = 1e3;
/// Smallest standard deviation, in its quantity's unit (mm or N): a
/// nanometre, a micronewton. A smaller one is no measurement's, and
/// divides a residual into an overflow.
pub const MIN_SD: f64 = 1e-6;
/// Largest magnitude of a camera frame's angle (degrees): one turn.
pub const MAX_ANGLE_DEG: f64 = 360.0;
/// Most repeats a force row may be the mean of.
pub const MAX_REPEATS: u32 = 1_000_000;

/// Why a measured value `x` (in `unit`) is refused: its magnitude beyond
/// `max`; `None` when it is within.
pub(crate) fn beyond(x: f64, max: f64, unit: &str) -> Option<String> {
    (x.abs() > max).then(|| {
        format!(
            "{} {unit} is beyond the bound of a measured value, {} {unit} in magnitude",
            Num(x),
            Num(max)
        )
    })
}

/// Why a standard deviation `x` (in `unit`) is refused:
/// not positive, below [`MIN_SD`] or above `max`; `None` when it is a
/// standard deviation.
pub(crate) fn bad_sd(x: f64, max: f64, unit: &str) -> Option<String> {
    if x <= 0.0 {
        Some(format!("{} must be positive", Num(x)))
    } else if x < MIN_SD {
        Some(format!(
            "{} {unit} is below {} {unit}, the smallest standard deviation of a measurement",
            Num(x),
            Num(MIN_SD)
        ))
    } else if x > max {
        Some(format!(
            "{} {unit} is above {} {unit}, the largest standard deviation of a measurement",
            Num(x),
            Num(max)
        ))
    } else {
        None
    }
}

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

/// Reads at most `limit` bytes of `path` as UTF-8 text (the library's
/// bounded reader, [`crate::scene::read_text`]): a larger file, one that
/// cannot be read or is not UTF-8 is an error naming `shown` (the file as
/// the user wrote it).
pub(crate) fn read_text(path: &Path, shown: &str, limit: u64) -> Result<String, MeasureError> {
    crate::scene::read_text(path, limit, "this file").map_err(|e| MeasureError {
        file: shown.to_string(),
        at: None,
        field: "file".to_string(),
        reason: match e {
            crate::scene::TextFileError::Io(e) => format!("cannot read: {e}"),
            e => e.to_string(),
        },
    })
}

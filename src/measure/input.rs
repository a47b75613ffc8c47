//! What every file of a manifest shares: the bounds on sizes and counts,
//! the error naming a file, row, column and field, bounded reading of a
//! text file, and the kinds of test.

use std::io::Read as _;
use std::path::Path;

use serde::{Deserialize, Serialize};

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

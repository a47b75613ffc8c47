//! The Pareto front of time against accuracy and the fastest configuration
//! per tolerance.

use fpc::plan::Refinement;
use serde::Serialize;

/// Relative difference of times taken as equal on the front and for the
/// fastest configuration per tolerance: the spread of the fastest batches
/// of one configuration over repeated runs (about 1 %), with a margin.
pub const TIME_RESOLUTION: f64 = 0.03;

/// The tolerances (mm) whose fastest configuration is reported.
pub const TOLERANCES_MM: [f64; 3] = [1.0, 0.1, 0.01];

/// One configuration, measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AccuracyRow {
    /// `model/partition/startxlevels[+richardson]`.
    pub label: String,
    /// The configuration.
    pub plan: Refinement,
    /// Elements of the finest level.
    pub elements: usize,
    /// Elements of every level, coarsest first.
    pub elements_per_level: Vec<usize>,
    /// Newton iterations of every level, coarsest first.
    pub iterations: Vec<usize>,
    /// The tip the configuration reports (extrapolated or the finest
    /// level's; mm).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// Its distance from the CCM reference (mm).
    pub error_vs_ccm_mm: f64,
    /// Its distance from its own model's reference (mm).
    pub error_vs_own_mm: f64,
    /// The refinement's own estimate (mm; `None` with one level).
    pub estimated_error_mm: Option<f64>,
    /// Time of the timed call (us): the fastest round's median.
    pub time_us: f64,
    /// The median of each round (us).
    pub rounds_us: Vec<f64>,
    /// Timed runs, over all rounds.
    pub runs: usize,
    /// `time_us / t8`.
    pub time_over_n8: f64,
    /// On the Pareto front (time against the error vs the CCM reference).
    pub pareto: bool,
}

/// A row of the Pareto front.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrontPoint {
    /// Index into [`AccuracyStudy::rows`](super::AccuracyStudy::rows).
    pub row: usize,
    /// Its label.
    pub label: String,
    /// Its time (us).
    pub time_us: f64,
    /// Its time over t8.
    pub time_over_n8: f64,
    /// Its error vs the CCM reference (mm).
    pub error_vs_ccm_mm: f64,
}

/// What the library picks for a tolerance, measured like the rows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LibraryChoice {
    /// `Refinement::for_tolerance` as a tip tolerance (`fpc::Plan::TipTolerance`) ran it
    /// (levels as solved).
    pub plan: Refinement,
    /// Its label.
    pub label: String,
    /// Its estimate when it stopped (mm).
    pub estimated_error_mm: Option<f64>,
    /// Its error vs the CCM reference (mm).
    pub error_vs_ccm_mm: f64,
    /// Its median time (us), timed like the rows.
    pub time_us: f64,
    /// Its time over t8.
    pub time_over_n8: f64,
    /// The error is within the tolerance.
    pub meets: bool,
}

/// The fastest configuration within a tolerance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fastest {
    /// The tolerance (mm, error vs the CCM reference).
    pub tolerance_mm: f64,
    /// The fastest row within it (`None`: no row; times within
    /// [`TIME_RESOLUTION`] count as equal, the more accurate row is taken).
    pub fastest: Option<FrontPoint>,
    /// The fastest row within it whose own error estimate is within it too
    /// (a refinement that knows it met the tolerance, as
    /// a tip tolerance must).
    pub fastest_estimated: Option<FrontPoint>,
    /// The library's choice (`None`: it failed).
    pub library: Option<LibraryChoice>,
    /// The library's time over the fastest row's (`None` without both).
    pub library_over_fastest: Option<f64>,
}

fn front_point(i: usize, r: &AccuracyRow) -> FrontPoint {
    FrontPoint {
        row: i,
        label: r.label.clone(),
        time_us: r.time_us,
        time_over_n8: r.time_over_n8,
        error_vs_ccm_mm: r.error_vs_ccm_mm,
    }
}

/// The fastest row meeting `ok`: among those within [`TIME_RESOLUTION`]
/// of the fastest, the most accurate.
pub(super) fn fastest_row(
    rows: &[AccuracyRow],
    ok: impl Fn(&AccuracyRow) -> bool,
) -> Option<FrontPoint> {
    let t = rows
        .iter()
        .filter(|r| ok(r))
        .map(|r| r.time_us)
        .fold(f64::INFINITY, f64::min);
    rows.iter()
        .enumerate()
        .filter(|(_, r)| ok(r) && r.time_us <= t * (1.0 + TIME_RESOLUTION))
        .min_by(|a, b| a.1.error_vs_ccm_mm.total_cmp(&b.1.error_vs_ccm_mm))
        .map(|(i, r)| front_point(i, r))
}

/// Marks the rows on the Pareto front of time against the error vs the
/// CCM reference and returns them, fastest first. A row is dominated by
/// one at most [`TIME_RESOLUTION`] slower that is at least as accurate
/// (and strictly faster or more accurate): the extrapolation of a
/// refinement costs nothing, so a row without it is never on the front
/// merely by timing noise.
pub(super) fn pareto(rows: &mut [AccuracyRow]) -> Vec<FrontPoint> {
    let dominated = |i: usize, rows: &[AccuracyRow]| {
        let (t, e) = (rows[i].time_us, rows[i].error_vs_ccm_mm);
        rows.iter().enumerate().any(|(j, r)| {
            j != i
                && r.time_us <= t * (1.0 + TIME_RESOLUTION)
                && r.error_vs_ccm_mm <= e
                && (r.time_us < t || r.error_vs_ccm_mm < e)
        })
    };
    let on: Vec<bool> = (0..rows.len())
        .map(|i| {
            rows[i].time_us.is_finite()
                && rows[i].error_vs_ccm_mm.is_finite()
                && !dominated(i, rows)
        })
        .collect();
    let mut front = Vec::new();
    for (i, r) in rows.iter_mut().enumerate() {
        r.pareto = on[i];
        if on[i] {
            front.push(front_point(i, r));
        }
    }
    front.sort_by(|a, b| {
        a.time_us
            .total_cmp(&b.time_us)
            .then(b.error_vs_ccm_mm.total_cmp(&a.error_vs_ccm_mm))
    });
    front
}

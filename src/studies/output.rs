//! A study's outputs as data: its tables and figure (the model of
//! [`crate::report`]), its entries of a summary, a small overview table,
//! notes, the sweeps that stopped, and how many of its points leave the
//! model's validity (docs/model.md section 8).
//!
//! Nothing here writes a file or draws: a front end (the CLI's `fpc paper`)
//! writes every [`Table`] as CSV, renders every [`Figure`] and assembles the
//! summaries, the same way for every study.

use std::collections::BTreeMap;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, PI};

use serde::Serialize;
use serde_json::Value;

use super::bands::BandColumn;
use super::options::SweepStop;
use crate::error::Warning;
use crate::gripper::{Invalid, SweepEnd};
pub use crate::report::*;

// ------------------------------------------------------------ columns

/// `status`: `ok`, `stopped` (a sweep that ended early), `failed`.
pub const STATUS: Column = Column::new("status", "");
/// `note`: why a row is not `ok`, or a remark on it.
pub const NOTE: Column = Column::new("note", "");
/// `reversed`: the grasp bends an element backwards (`curvature_reversal`).
pub const REVERSED: Column = Column::new("reversed", "");
/// `valid`: the grasp's one verdict (`gripper::Verdict`): the paper's
/// rules hold, the finger is inside the model, the grasp is stable and on
/// the loading path.
pub const VALID: Column = Column::new("valid", "");
/// `invalid`: why not valid, the first reason's kind (`second_contact`,
/// `outside_model`, `unstable`, ...); empty when valid.
pub const INVALID: Column = Column::new("invalid", "");
/// `warnings`: the validity kinds the point raises, `;`-separated.
pub const WARNINGS: Column = Column::new("warnings", "");

impl Table {
    /// Appends the row of a sweep that stopped at `at` (in column `at_column`).
    pub(crate) fn push_stop(&mut self, lead: Vec<(&str, Cell)>, at_column: &str, s: &SweepStop) {
        let mut cells = lead;
        cells.push((at_column, s.at.into()));
        // a natural end is a result ("ended"), a failed solve a stop
        let status = if s.is_natural() { "ended" } else { "stopped" };
        cells.push((STATUS.name, status.into()));
        cells.push((NOTE.name, s.reason.clone().into()));
        self.push_named(cells);
    }
}

// ------------------------------------------------------------ validity

/// The validity kinds of [`Warning::kind`] (those with
/// [`Warning::is_validity`]), in the order of docs/model.md section 8.
pub const VALIDITY_KINDS: [&str; 6] = [
    "element_slope",
    "strain_range",
    "self_contact",
    "thickness_ratio",
    "curvature_reversal",
    "beyond_flat",
];

/// The kinds of [`VALIDITY_KINDS`] among `warnings`, each once, in order
/// of appearance.
pub fn validity_kinds(warnings: &[Warning]) -> Vec<&'static str> {
    let mut kinds = Vec::new();
    for w in warnings
        .iter()
        .filter(|w| VALIDITY_KINDS.contains(&w.kind()))
    {
        if !kinds.contains(&w.kind()) {
            kinds.push(w.kind());
        }
    }
    kinds
}

/// The `warnings` cell: the validity kinds, `;`-separated (empty: none).
pub fn warnings_cell(warnings: &[Warning]) -> Cell {
    let kinds = validity_kinds(warnings);
    if kinds.is_empty() {
        Cell::Empty
    } else {
        Cell::Text(kinds.join(";"))
    }
}

/// Counts, over the points of a study (every row that is a grasp or a
/// finger state), how many raise each validity kind.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct Tally {
    points: usize,
    by_kind: BTreeMap<String, usize>,
}

impl Default for Tally {
    fn default() -> Tally {
        Tally {
            points: 0,
            by_kind: VALIDITY_KINDS.iter().map(|k| (k.to_string(), 0)).collect(),
        }
    }
}

impl Tally {
    /// Counts one point and returns its `warnings` cell.
    pub fn point(&mut self, warnings: &[Warning]) -> Cell {
        self.points += 1;
        for k in validity_kinds(warnings) {
            *self.by_kind.entry(k.to_string()).or_default() += 1;
        }
        warnings_cell(warnings)
    }
}

// ------------------------------------------------------------ assembly

/// The columns every table of grasps ends with.
pub(crate) const GRASP_TAIL: [Column; 6] = [REVERSED, VALID, INVALID, WARNINGS, STATUS, NOTE];

/// The columns every table of finger states ends with.
pub(crate) const STATE_TAIL: [Column; 3] = [WARNINGS, STATUS, NOTE];

/// `lead`, then `tail`: a table's columns.
pub(crate) fn columns(lead: &[Column], tail: &[Column]) -> Vec<Column> {
    lead.iter().chain(tail).copied().collect()
}

/// A study's outputs under assembly, the one path every study takes from
/// its typed result to its [`StudyOutput`]: a row per grasp or finger state
/// (counted in the validity tally), a row, a note and a stop record per
/// sweep that stopped, then [`Assembly::finish`] with the figure and the
/// summary.
pub(crate) struct Assembly {
    /// The tables, by index in the calls below.
    pub tables: Vec<Table>,
    /// The overview table.
    pub overview: Overview,
    /// Remarks.
    pub notes: Vec<String>,
    /// Grasps strict mode ruled out.
    pub strict_dropped: usize,
    stops: Vec<Stop>,
    design_warnings: Vec<String>,
    tally: Tally,
}

impl Assembly {
    /// Empty tables of these names and columns, an overview with this header.
    pub fn new(tables: &[(&str, &[Column])], overview: &[&str]) -> Assembly {
        Assembly {
            tables: tables.iter().map(|(n, c)| Table::new(*n, c)).collect(),
            overview: Overview::new(overview),
            notes: Vec::new(),
            strict_dropped: 0,
            stops: Vec::new(),
            design_warnings: Vec::new(),
            tally: Tally::default(),
        }
    }

    /// A row of table `t` that is no point: `lead`, then `ok` and no note.
    pub fn row(&mut self, t: usize, mut lead: Vec<Cell>) {
        lead.extend(["ok".into(), Cell::Empty]);
        self.tables[t].push(lead);
    }

    /// A row of a grasp (a point of the tally): `lead`, then its
    /// [`GRASP_TAIL`] cells, `ok` and no note.
    pub fn grasp(
        &mut self,
        t: usize,
        mut lead: Vec<Cell>,
        reversed: bool,
        invalid: Option<&Invalid>,
        warnings: &[Warning],
    ) {
        lead.extend([
            reversed.into(),
            invalid.is_none().into(),
            invalid.map_or(Cell::Empty, |i| i.kind().into()),
        ]);
        self.state(t, lead, warnings, Cell::Empty);
    }

    /// A row of a finger state (a point of the tally): `lead`, then its
    /// `warnings` cell, `ok` and `note`.
    pub fn state(&mut self, t: usize, mut lead: Vec<Cell>, warnings: &[Warning], note: Cell) {
        lead.extend([self.tally.point(warnings), "ok".into(), note]);
        self.tables[t].push(lead);
    }

    /// A row of a point that did not solve: `lead`, the rest empty, status
    /// `failed` and `note`.
    pub fn failed(&mut self, t: usize, mut lead: Vec<Cell>, note: Cell) {
        let table = &mut self.tables[t];
        lead.resize(table.columns.len() - 2, Cell::Empty);
        lead.extend(["failed".into(), note]);
        table.push(lead);
    }

    /// A sweep `case` that stopped: its row in table `t` (the named `lead`
    /// cells, where it stopped in `at_column`), its stop record and, when
    /// `noted`, a note saying where and why.
    #[allow(clippy::too_many_arguments)]
    pub fn stop(
        &mut self,
        t: usize,
        lead: Vec<(&str, Cell)>,
        at_column: &str,
        case: &str,
        at: fn(f64) -> StopAt,
        s: &SweepStop,
        noted: bool,
    ) {
        self.tables[t].push_stop(lead, at_column, s);
        if noted {
            let place = match at(s.at) {
                StopAt::Mm(d) => format!("sweep stopped at d = {d:.1} mm"),
                StopAt::Kpa(p) => format!("pressure sweep stopped at {p:.1} kPa"),
            };
            let case = if case.is_empty() {
                String::new()
            } else {
                format!("{case}: ")
            };
            self.notes.push(format!("{case}{place}: {}", s.reason));
        }
        self.stops.push(Stop::of_sweep(case, at, s));
    }

    /// A stop record that has no row of its own.
    pub fn stop_record(&mut self, stop: Stop) {
        self.stops.push(stop);
    }

    /// Adds the design warnings of a gripper, each once.
    pub fn design(&mut self, warnings: &[Warning]) {
        for w in warnings {
            let w = w.to_string();
            if !self.design_warnings.contains(&w) {
                self.design_warnings.push(w);
            }
        }
    }

    /// The outputs, with this figure and these summary entries.
    pub fn finish<T: Serialize>(self, figure: Figure, summary: &T) -> StudyOutput {
        StudyOutput {
            tables: self.tables,
            figure,
            summary: entries(summary),
            overview: self.overview,
            notes: self.notes,
            stops: self.stops,
            design_warnings: self.design_warnings,
            points: self.tally.points,
            warnings_by_kind: self.tally.by_kind,
            strict_dropped: self.strict_dropped,
            bands: Vec::new(),
        }
    }

    /// The outputs of a study that has no result: its tables without rows,
    /// an empty figure and these (empty) summary entries.
    pub fn empty<T: Serialize>(self, summary: &T) -> StudyOutput {
        self.finish(Figure::row("", [800, 600], Vec::new()), summary)
    }
}

/// Where a stopped sweep stopped, with its unit in the key (`at_mm`,
/// `at_kpa`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub enum StopAt {
    /// A grasping size (mm).
    #[serde(rename = "at_mm")]
    Mm(f64),
    /// A pressure (kPa).
    #[serde(rename = "at_kpa")]
    Kpa(f64),
}

/// A sweep of a study that ended before its last point:
/// `{"case", "at_mm" | "at_kpa", "reason", "end"?}`. With `end` it is a
/// natural end of the sweep (a fold, the validity limit, a force bound:
/// a result); without, a numerical stop (a failed solve).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Stop {
    /// Which sweep (`eps0 = 0.25, a = π/3`).
    pub case: String,
    /// Where.
    #[serde(flatten)]
    pub at: StopAt,
    /// Why.
    pub reason: String,
    /// The natural end, if it is one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub end: Option<SweepEnd>,
}

impl Stop {
    /// The stop of a sweep `case` at `at(s.at)`.
    pub(crate) fn of_sweep(case: impl Into<String>, at: fn(f64) -> StopAt, s: &SweepStop) -> Stop {
        Stop {
            case: case.into(),
            at: at(s.at),
            reason: s.reason.clone(),
            end: s.end.clone().filter(|e| !e.is_numerical()),
        }
    }

    /// True for a natural end (not a failed solve).
    pub fn is_natural(&self) -> bool {
        self.end.is_some()
    }
}

/// A stop as a summary value: `{"at_mm" | "at_kpa", "reason"}`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct StopEntry {
    #[serde(flatten)]
    at: StopAt,
    reason: String,
}

/// The summary value of an optional stop, in mm or kPa.
pub(crate) fn stop_entry(s: &Option<SweepStop>, unit: fn(f64) -> StopAt) -> Option<StopEntry> {
    s.as_ref().map(|s| StopEntry {
        at: unit(s.at),
        reason: s.reason.clone(),
    })
}

/// Everything a study produces, as data.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StudyOutput {
    /// Its tables (unique names across all studies).
    pub tables: Vec<Table>,
    /// Its figure.
    pub figure: Figure,
    /// Its entries of a summary document (key, value), built by serde.
    pub summary: Vec<(String, Value)>,
    /// The small table a report shows.
    pub overview: Overview,
    /// Remarks (stopped sweeps, failed points).
    pub notes: Vec<String>,
    /// The sweeps that stopped early.
    pub stops: Vec<Stop>,
    /// The design warnings of its grippers (text, each once).
    pub design_warnings: Vec<String>,
    /// The points counted in `warnings_by_kind`: the rows that are a grasp
    /// or a finger state.
    pub points: usize,
    /// How many of those points raise each validity kind (every kind of
    /// [`VALIDITY_KINDS`] present, 0 included).
    pub warnings_by_kind: BTreeMap<String, usize>,
    /// Grasps strict mode rules out (bent backwards): removed from the
    /// sweeps, or kept and marked not valid where a study keeps every row;
    /// 0 when not strict.
    pub strict_dropped: usize,
    /// The `<column>_sd` columns of its 1-sigma bands and how each was
    /// computed (empty without a covariance, or for a study without bands).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub bands: Vec<BandColumn>,
}

impl StudyOutput {
    /// Marks every fold its sweeps met (a natural end that is a limit
    /// point, [`SweepEnd::Fold`]) in its figure: a vertical line at the
    /// fold's grasping size on every panel over the grasping size (an x
    /// axis named `... d` in mm), and a note with the fold's force on the
    /// first panel.
    pub(crate) fn mark_folds(&mut self) {
        let folds: Vec<(&str, f64, f64)> = self
            .stops
            .iter()
            .filter_map(|s| match &s.end {
                Some(SweepEnd::Fold {
                    force_n, size_mm, ..
                }) => Some((s.case.as_str(), *size_mm, *force_n)),
                _ => None,
            })
            .collect();
        if folds.is_empty() {
            return;
        }
        let over_size = |p: &Panel| p.x.unit == "mm" && p.x.label.ends_with(" d");
        for p in self
            .figure
            .rows
            .iter_mut()
            .flatten()
            .filter(|p| over_size(p))
        {
            for &(case, size, force) in &folds {
                p.vlines.push(RefLine {
                    at: size,
                    label: format!("fold ({case}): F = {force:.3} N"),
                });
            }
        }
        if let Some(p) = self.figure.rows.iter_mut().flatten().next() {
            for &(case, size, force) in &folds {
                p.notes.push(format!(
                    "{case}: snaps through at F = {force:.3} N, d = {size:.2} mm (fold)"
                ));
            }
        }
    }

    /// The table called `name`.
    pub fn table(&self, name: &str) -> Option<&Table> {
        self.tables.iter().find(|t| t.name == name)
    }
}

/// The fields of a serializable struct as summary entries (key, value).
/// Non-finite numbers become `null`.
pub(crate) fn entries<T: Serialize>(v: &T) -> Vec<(String, Value)> {
    match serde_json::to_value(v) {
        Ok(Value::Object(m)) => m.into_iter().collect(),
        Ok(other) => panic!("a study summary must be a struct, got {other}"),
        Err(e) => panic!("a study summary does not serialize: {e}"),
    }
}

// ------------------------------------------------------------ text

/// `x` with `digits` decimals, `–` when not finite.
pub(crate) fn fmt(x: f64, digits: usize) -> String {
    if x.is_finite() {
        format!("{x:.digits$}")
    } else {
        "–".into()
    }
}

/// [`fmt`] of an optional value (`–` when absent).
pub(crate) fn fmt_opt(x: Option<f64>, digits: usize) -> String {
    x.map_or("–".into(), |x| fmt(x, digits))
}

/// The paper's mounting angles: (value, name in text, name in a colour key).
const ANGLE_NAMES: [(f64, &str, &str); 3] = [
    (FRAC_PI_2, "π/2", "pi/2"),
    (PI / 2.5, "π/2.5", "pi/2.5"),
    (FRAC_PI_3, "π/3", "pi/3"),
];

fn named_angle(a: f64) -> Option<(&'static str, &'static str)> {
    ANGLE_NAMES
        .iter()
        .find(|(v, _, _)| (a - v).abs() < 1e-12)
        .map(|&(_, text, key)| (text, key))
}

/// The paper's name of a mounting angle (`π/2`, `π/2.5`, `π/3`), else degrees.
pub fn angle_name(a: f64) -> String {
    named_angle(a).map_or_else(|| format!("{:.1}°", a.to_degrees()), |n| n.0.into())
}

/// The colour key of a mounting angle: `a=pi/3` (else `a=<degrees>deg`).
pub fn angle_key(a: f64) -> String {
    named_angle(a).map_or_else(
        || format!("a={:.1}deg", a.to_degrees()),
        |n| format!("a={}", n.1),
    )
}

/// The colour key of a prestrain: `eps0=0.25`.
pub fn eps0_key(eps0: f64) -> String {
    format!("eps0={eps0}")
}

/// The colour key of an overlap: `g=10mm`.
pub fn overlap_key(g: f64) -> String {
    format!("g={g}mm")
}

/// Points `(x, y)` as `[x, y]`.
pub(crate) fn pts(it: impl IntoIterator<Item = (f64, f64)>) -> Vec<[f64; 2]> {
    it.into_iter().map(|(x, y)| [x, y]).collect()
}

/// The largest finite value.
pub(crate) fn max_of(it: impl Iterator<Item = f64>) -> Option<f64> {
    it.filter(|x| x.is_finite()).reduce(f64::max)
}

/// The smallest finite value.
pub(crate) fn min_of(it: impl Iterator<Item = f64>) -> Option<f64> {
    it.filter(|x| x.is_finite()).reduce(f64::min)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validity_kinds_are_listed_once_and_counted_per_point() {
        let w = [
            Warning::ElementSlope {
                element: 1,
                degrees: 50.0,
                limit: 45.0,
            },
            Warning::ElementSlope {
                element: 2,
                degrees: 60.0,
                limit: 45.0,
            },
            Warning::Eps0OutsideFit {
                eps0: 0.7,
                lo: 0.0,
                hi: 0.6,
            },
            Warning::CurvatureReversal {
                element: 3,
                curvature: -0.01,
            },
        ];
        assert_eq!(
            warnings_cell(&w),
            Cell::Text("element_slope;curvature_reversal".into())
        );
        assert_eq!(
            warnings_cell(&w[2..3]),
            Cell::Empty,
            "notes are not validity"
        );
        let mut t = Tally::default();
        t.point(&w);
        t.point(&[]);
        t.point(&w[..1]);
        assert_eq!(t.points, 3);
        assert_eq!(t.by_kind["element_slope"], 2);
        assert_eq!(t.by_kind["curvature_reversal"], 1);
        assert_eq!(t.by_kind["beyond_flat"], 0);
        assert!(!t.by_kind.contains_key("eps0_outside_fit"));
    }

    #[test]
    fn stops_carry_their_unit_in_the_key() {
        let s = Stop {
            case: "c".into(),
            at: StopAt::Kpa(20.0),
            reason: "r".into(),
            end: None,
        };
        let v = serde_json::to_value(&s).unwrap();
        assert_eq!(
            v,
            serde_json::json!({"case": "c", "at_kpa": 20.0, "reason": "r"})
        );
        let e = stop_entry(&Some(SweepStop::failed(5.5, "why".into())), StopAt::Mm);
        assert_eq!(
            serde_json::to_value(e).unwrap(),
            serde_json::json!({"at_mm": 5.5, "reason": "why"})
        );
    }

    #[test]
    fn folds_are_marked_on_the_panels_over_the_grasping_size() {
        let size = Panel::new(
            "",
            PlotAxis::new("grasping size d", "mm"),
            PlotAxis::new("f", "N"),
        );
        let other = Panel::new(
            "",
            PlotAxis::new("pressure P", "kPa"),
            PlotAxis::new("F", "N"),
        );
        let mut out = Assembly::new(&[], &[]).finish(
            Figure::row("t", [800, 400], vec![other, size]),
            &serde_json::json!({}),
        );
        let end = |end| Stop {
            case: "b = 0.5 rad".into(),
            at: StopAt::Mm(80.0),
            reason: "r".into(),
            end,
        };
        out.stops = vec![
            end(Some(SweepEnd::Fold {
                force_n: 2.5,
                size_mm: 81.25,
                tip_mm: [1.0, 2.0],
            })),
            end(Some(SweepEnd::ForceBound {
                force_n: 100.0,
                size_mm: 90.0,
            })),
            end(None),
        ];
        out.mark_folds();
        let [p0, p1] = &out.figure.rows[0][..] else {
            panic!("two panels")
        };
        // only the fold, only on the panel over d; the note on the first
        assert!(p0.vlines.is_empty());
        assert_eq!(p1.vlines.len(), 1);
        assert_eq!(p1.vlines[0].at, 81.25);
        assert!(p1.vlines[0].label.contains("F = 2.500 N"));
        assert_eq!(p0.notes.len(), 1);
        assert!(p0.notes[0].contains("snaps through at F = 2.500 N, d = 81.25 mm"));
        // nothing to mark: nothing changes
        let before = out.figure.clone();
        out.stops.remove(0);
        out.mark_folds();
        assert_eq!(out.figure, before);
    }

    /// A panel over `d` (mm) of `f` (N) with one series through `ys` at
    #[test]
    fn keys_and_names() {
        assert_eq!(angle_key(FRAC_PI_3), "a=pi/3");
        assert_eq!(angle_name(PI / 2.5), "π/2.5");
        assert_eq!(angle_name(0.5), "28.6°");
        assert_eq!(eps0_key(0.25), "eps0=0.25");
        assert_eq!(overlap_key(10.0), "g=10mm");
        #[derive(Serialize)]
        struct S {
            a: Option<f64>,
            b: f64,
        }
        let e = entries(&S {
            a: None,
            b: f64::NAN,
        });
        assert_eq!(
            e,
            vec![("a".into(), Value::Null), ("b".into(), Value::Null)]
        );
    }
}

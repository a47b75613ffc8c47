//! A study's outputs as data: named tables, a figure described panel by
//! panel, its entries of a summary, a small overview table, notes, the
//! sweeps that stopped, and how many of its points leave the model's
//! validity (docs/model.md section 8).
//!
//! Nothing here writes a file or draws: a front end (the CLI's `fpc paper`)
//! writes every [`Table`] as CSV, renders every [`Figure`] and assembles the
//! summaries, the same way for every study.

use std::collections::BTreeMap;
use std::f64::consts::{FRAC_PI_2, FRAC_PI_3, PI};

use serde::Serialize;
use serde_json::Value;

use super::SweepStop;
use crate::error::Warning;
use crate::gripper::SweepEnd;

// ------------------------------------------------------------ tables

/// A column: its name as written in a CSV header (unit last, as in `d_mm`,
/// `F_n`, `pressure_kpa`) and that unit on its own (`None`: a pure number,
/// a flag or text).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Column {
    /// Header name, e.g. `d_mm`.
    pub name: &'static str,
    /// Unit, e.g. `mm`.
    pub unit: Option<&'static str>,
}

impl Column {
    /// A column with a unit (`""`: none).
    pub const fn new(name: &'static str, unit: &'static str) -> Column {
        Column {
            name,
            unit: if unit.is_empty() { None } else { Some(unit) },
        }
    }
}

/// `status`: `ok`, `stopped` (a sweep that ended early), `failed`.
pub const STATUS: Column = Column::new("status", "");
/// `note`: why a row is not `ok`, or a remark on it.
pub const NOTE: Column = Column::new("note", "");
/// `reversed`: the grasp bends an element backwards (`curvature_reversal`).
pub const REVERSED: Column = Column::new("reversed", "");
/// `valid`: the grasp breaks no rule (`gripper::rules`).
pub const VALID: Column = Column::new("valid", "");
/// `warnings`: the validity kinds the point raises, `;`-separated.
pub const WARNINGS: Column = Column::new("warnings", "");

/// One cell of a table.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(untagged)]
pub enum Cell {
    /// A number (written empty when not finite).
    Num(f64),
    /// Text.
    Text(String),
    /// A flag.
    Bool(bool),
    /// Nothing.
    Empty,
}

impl From<f64> for Cell {
    fn from(x: f64) -> Cell {
        Cell::Num(x)
    }
}

impl From<Option<f64>> for Cell {
    fn from(x: Option<f64>) -> Cell {
        x.map_or(Cell::Empty, Cell::Num)
    }
}

impl From<bool> for Cell {
    fn from(b: bool) -> Cell {
        Cell::Bool(b)
    }
}

impl From<&str> for Cell {
    fn from(s: &str) -> Cell {
        Cell::Text(s.to_string())
    }
}

impl From<String> for Cell {
    fn from(s: String) -> Cell {
        Cell::Text(s)
    }
}

/// A named table: `name` is the file stem (`study1`, `study1_shapes`).
/// Every row has one cell per column; every table of the studies ends with
/// the columns `status` and `note`.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Table {
    /// File stem.
    pub name: String,
    /// The columns.
    pub columns: Vec<Column>,
    /// The rows, each as wide as `columns`.
    pub rows: Vec<Vec<Cell>>,
}

impl Table {
    /// An empty table.
    pub fn new(name: impl Into<String>, columns: &[Column]) -> Table {
        Table {
            name: name.into(),
            columns: columns.to_vec(),
            rows: Vec::new(),
        }
    }

    /// The index of the column called `name`.
    pub fn column(&self, name: &str) -> Option<usize> {
        self.columns.iter().position(|c| c.name == name)
    }

    /// The cell of row `row` in column `name`.
    pub fn cell(&self, row: usize, name: &str) -> Option<&Cell> {
        self.rows.get(row)?.get(self.column(name)?)
    }

    /// Appends a row; panics (a programming error) when it is not as wide
    /// as the table.
    pub fn push(&mut self, row: Vec<Cell>) {
        assert_eq!(
            row.len(),
            self.columns.len(),
            "row width of table {}",
            self.name
        );
        self.rows.push(row);
    }

    /// Appends a row whose only filled cells are the named ones; panics on
    /// an unknown column name.
    pub fn push_named(&mut self, cells: Vec<(&str, Cell)>) {
        let mut row = vec![Cell::Empty; self.columns.len()];
        for (name, cell) in cells {
            let i = self
                .column(name)
                .unwrap_or_else(|| panic!("table {} has no column {name}", self.name));
            row[i] = cell;
        }
        self.rows.push(row);
    }

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
pub const VALIDITY_KINDS: [&str; 5] = [
    "element_slope",
    "strain_range",
    "self_contact",
    "curvature_reversal",
    "beyond_flat",
];

/// The validity kinds among `warnings`, each once, in order of appearance.
pub fn validity_kinds(warnings: &[Warning]) -> Vec<&'static str> {
    let mut kinds = Vec::new();
    for w in warnings.iter().filter(|w| w.is_validity()) {
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

    /// The `reversed`, `valid` and `warnings` cells of a grasp, counted.
    pub fn grasp(&mut self, reversed: bool, valid: bool, warnings: &[Warning]) -> [Cell; 3] {
        [reversed.into(), valid.into(), self.point(warnings)]
    }
}

// ------------------------------------------------------------ figures

/// A figure: a title and rows of panels (each row split evenly across the
/// width, the rows evenly down the height).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Figure {
    /// Title over the whole figure.
    pub title: String,
    /// Width and height in pixels.
    pub size: [u32; 2],
    /// Rows of panels, top to bottom.
    pub rows: Vec<Vec<Panel>>,
}

impl Figure {
    /// A figure of one row of panels.
    pub fn row(title: impl Into<String>, size: [u32; 2], panels: Vec<Panel>) -> Figure {
        Figure {
            title: title.into(),
            size,
            rows: vec![panels],
        }
    }

    /// Every panel, row by row.
    pub fn panels(&self) -> impl Iterator<Item = &Panel> {
        self.rows.iter().flatten()
    }
}

/// One axis of a panel.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct PlotAxis {
    /// What is plotted, e.g. `grasping size d`.
    pub label: String,
    /// Its unit, e.g. `mm` (empty: a pure number).
    pub unit: String,
    /// A fixed range (else fitted to the data).
    pub range: Option<[f64; 2]>,
    /// Include 0 in a fitted range.
    pub include_zero: bool,
    /// A logarithmic axis: positive values only, ticks at powers of ten.
    pub log: bool,
}

impl PlotAxis {
    /// An axis with a fitted range.
    pub fn new(label: &str, unit: &str) -> PlotAxis {
        PlotAxis {
            label: label.into(),
            unit: unit.into(),
            range: None,
            include_zero: false,
            log: false,
        }
    }

    /// A logarithmic axis (a renderer skips values that are not positive).
    pub fn log(mut self) -> Self {
        self.log = true;
        self
    }

    /// The label with its unit, `label (unit)`.
    pub fn text(&self) -> String {
        if self.unit.is_empty() {
            self.label.clone()
        } else {
            format!("{} ({})", self.label, self.unit)
        }
    }
}

/// How a series is drawn.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum SeriesKind {
    /// A solid line.
    Line,
    /// A dashed line.
    Dashed,
    /// A line with a marker at every point.
    LinePoints,
    /// Filled markers.
    Points,
    /// Small translucent markers (dense scatter).
    Scatter,
    /// Hollow markers.
    Hollow,
    /// Crosses.
    Cross,
    /// The area between the curve and y = 0.
    Area,
    /// Points whose grasp bends an element backwards (`curvature_reversal`):
    /// hollow markers over the curve they belong to, one legend entry per
    /// panel.
    BentBackwards,
}

/// The legend entry and colour key of every [`SeriesKind::BentBackwards`]
/// series.
pub const BENT_BACKWARDS: &str = "bent backwards";

/// One data series. `color` is a key naming the variable and its value
/// (`eps0=0.25`, `a=pi/3`, `g=10mm`) or the quantity (`normal force`), so
/// a renderer can give every key one colour across panels and studies.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Series {
    /// Legend entry (`None`: not in the legend).
    pub label: Option<String>,
    /// Colour key.
    pub color: String,
    /// How it is drawn.
    pub kind: SeriesKind,
    /// The points (x, y); non-finite ones are skipped when drawn.
    pub points: Vec<[f64; 2]>,
}

impl Series {
    /// A series without a legend entry.
    pub fn new(color: impl Into<String>, kind: SeriesKind, points: Vec<[f64; 2]>) -> Series {
        Series {
            label: None,
            color: color.into(),
            kind,
            points,
        }
    }

    /// With a legend entry.
    pub fn label(mut self, label: impl Into<String>) -> Series {
        self.label = Some(label.into());
        self
    }

    /// The markers of the points that are bent backwards (colour key and
    /// legend entry [`BENT_BACKWARDS`]); `None` when there is none.
    pub fn bent_backwards(points: Vec<[f64; 2]>) -> Option<Series> {
        (!points.is_empty()).then(|| {
            Series::new(BENT_BACKWARDS, SeriesKind::BentBackwards, points).label(BENT_BACKWARDS)
        })
    }
}

/// A dashed grey reference line at a constant x or y.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RefLine {
    /// Where.
    pub at: f64,
    /// Legend entry (empty: none).
    pub label: String,
}

/// A shaded x range spanning the panel's height.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Band {
    /// From x.
    pub from: f64,
    /// To x.
    pub to: f64,
    /// Colour key.
    pub color: String,
}

/// A corner of a panel (where its legend goes).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Corner {
    /// Top left.
    UpperLeft,
    /// Top right.
    UpperRight,
    /// Bottom left.
    LowerLeft,
    /// Bottom right.
    LowerRight,
}

/// One chart.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Panel {
    /// Title (may be empty).
    pub title: String,
    /// Horizontal axis.
    pub x: PlotAxis,
    /// Vertical axis.
    pub y: PlotAxis,
    /// Data series, drawn in order.
    pub series: Vec<Series>,
    /// Horizontal reference lines.
    pub hlines: Vec<RefLine>,
    /// Vertical reference lines.
    pub vlines: Vec<RefLine>,
    /// Shaded x ranges.
    pub bands: Vec<Band>,
    /// The bands' legend entry.
    pub band_label: Option<String>,
    /// Lines of text in the top-left corner.
    pub notes: Vec<String>,
    /// Same scale on both axes (shapes).
    pub equal_aspect: bool,
    /// Where the legend goes.
    pub legend: Corner,
}

impl Panel {
    /// An empty panel.
    pub fn new(title: impl Into<String>, x: PlotAxis, y: PlotAxis) -> Panel {
        Panel {
            title: title.into(),
            x,
            y,
            series: Vec::new(),
            hlines: Vec::new(),
            vlines: Vec::new(),
            bands: Vec::new(),
            band_label: None,
            notes: Vec::new(),
            equal_aspect: false,
            legend: Corner::UpperRight,
        }
    }

    /// Adds a series, and the markers of its points bent backwards.
    pub(crate) fn curve(&mut self, s: Series, bent: Vec<[f64; 2]>) {
        self.series.push(s);
        self.series.extend(Series::bent_backwards(bent));
    }
}

// ------------------------------------------------------------ the output

/// The small table a report shows for a study: a header and rows of text.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Overview {
    /// Column titles.
    pub header: Vec<String>,
    /// Rows, each as wide as the header.
    pub rows: Vec<Vec<String>>,
}

impl Overview {
    /// An empty overview with this header.
    pub fn new(header: &[&str]) -> Overview {
        Overview {
            header: header.iter().map(|h| h.to_string()).collect(),
            rows: Vec::new(),
        }
    }

    /// Appends a row.
    pub fn push(&mut self, row: Vec<String>) {
        self.rows.push(row);
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

    /// An output with these tables, figure and summary entries, and
    /// nothing else yet.
    pub(crate) fn new(tables: Vec<Table>, figure: Figure, summary: Vec<(String, Value)>) -> Self {
        StudyOutput {
            tables,
            figure,
            summary,
            overview: Overview::default(),
            notes: Vec::new(),
            stops: Vec::new(),
            design_warnings: Vec::new(),
            points: 0,
            warnings_by_kind: Tally::default().by_kind,
            strict_dropped: 0,
        }
    }

    /// Takes the counts of `tally`.
    pub(crate) fn tallied(mut self, tally: Tally) -> Self {
        self.points = tally.points;
        self.warnings_by_kind = tally.by_kind;
        self
    }

    /// The table called `name`.
    pub fn table(&self, name: &str) -> Option<&Table> {
        self.tables.iter().find(|t| t.name == name)
    }

    /// Adds the design warnings of a gripper, each once.
    pub(crate) fn design(&mut self, warnings: &[Warning]) {
        for w in warnings {
            let w = w.to_string();
            if !self.design_warnings.contains(&w) {
                self.design_warnings.push(w);
            }
        }
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
    fn tables_check_their_width() {
        let mut t = Table::new("t", &[Column::new("d_mm", "mm"), STATUS, NOTE]);
        assert_eq!(t.columns[0].unit, Some("mm"));
        assert_eq!(t.columns[1].unit, None);
        t.push(vec![1.0.into(), "ok".into(), Cell::Empty]);
        t.push_named(vec![("status", "stopped".into())]);
        assert_eq!(t.rows[1], [Cell::Empty, "stopped".into(), Cell::Empty]);
        assert_eq!(t.cell(0, "d_mm"), Some(&Cell::Num(1.0)));
        let wide = std::panic::catch_unwind(move || t.push(vec![Cell::Empty]));
        assert!(wide.is_err(), "a short row is a programming error");
    }

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
        let mut out = StudyOutput::new(
            Vec::new(),
            Figure::row("t", [800, 400], vec![other, size]),
            Vec::new(),
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

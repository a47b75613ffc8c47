//! The CSV files of the tests: a header of known column names (the unit
//! in each name), one record per data row; `#` starts a comment line.
//! Every value is checked where it is read, and a bad one is an error
//! naming its file, line, column and column name. Measured values are
//! bounded (the bounds of [`super::input`]): pressures, lengths, forces,
//! standard deviations, repeats.

use std::collections::HashMap;

use serde::Serialize;

use super::input::{
    bad_sd, beyond, MeasureError, TestKind, MAX_FORCE_N, MAX_LENGTH_MM, MAX_PRESSURE_KPA,
    MAX_REPEATS, MAX_ROWS, MAX_TOTAL_ROWS, VACUUM_KPA,
};
use crate::num::Num;
use crate::studies::Axis;

/// One marker at one pressure.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MarkerRow {
    /// The line of the file (the header is line 1).
    pub line: usize,
    /// Channel pressure (kPa, gauge).
    pub pressure_kpa: f64,
    /// The marker's name.
    pub marker: String,
    /// The marker's position along the mid-plane (mm): its distance from
    /// the root on the unloaded, unstretched finger, 0 to the length Lx.
    pub s_mm: f64,
    /// The measured point `[x, z]` (mm), in the test's frame.
    pub point_mm: [f64; 2],
    /// Standard deviation of each coordinate (mm).
    pub sd_mm: f64,
}

/// The radius of curvature at one pressure.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RadiusRow {
    /// The line of the file.
    pub line: usize,
    /// Channel pressure (kPa, gauge).
    pub pressure_kpa: f64,
    /// The measured radius (mm).
    pub radius_mm: f64,
    /// Its standard deviation (mm).
    pub sd_mm: f64,
}

/// The tip force for one displacement at one pressure.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForceRow {
    /// The line of the file.
    pub line: usize,
    /// Channel pressure (kPa, gauge).
    pub pressure_kpa: f64,
    /// The axis of force and displacement (finger frame).
    #[serde(serialize_with = "axis_name")]
    pub axis: Axis,
    /// The tip's displacement along the axis from its pressurised,
    /// unloaded position (mm).
    pub displacement_mm: f64,
    /// The mean measured force along the axis (N).
    pub force_n: f64,
    /// The standard deviation of one repeat (N).
    pub sd_n: f64,
    /// How many repeats `force_n` is the mean of.
    pub repeats: u32,
}

impl ForceRow {
    /// The standard deviation of the mean, `sd_n / sqrt(repeats)` (N).
    pub fn sd_of_mean(&self) -> f64 {
        self.sd_n / f64::from(self.repeats).sqrt()
    }
}

fn axis_name<S: serde::Serializer>(a: &Axis, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_str(a.name())
}

/// The columns of a kind of test: (name, required).
pub(crate) fn columns(kind: TestKind) -> &'static [(&'static str, bool)] {
    match kind {
        TestKind::Markers => &[
            ("pressure_kpa", true),
            ("marker", true),
            ("s_mm", true),
            ("x_mm", true),
            ("z_mm", true),
            ("sd_mm", false),
        ],
        TestKind::Radius => &[("pressure_kpa", true), ("radius_mm", true), ("sd_mm", true)],
        TestKind::Force => &[
            ("pressure_kpa", true),
            ("axis", true),
            ("displacement_mm", true),
            ("force_n", true),
            ("sd_n", true),
            ("repeats", true),
        ],
    }
}

/// What a reader needs besides the text: the file's name as shown, the
/// finger's length (markers beyond it are errors) and the default
/// standard deviation of markers (the test's `sd_mm` key).
pub(crate) struct Context<'a> {
    pub file: &'a str,
    pub length_mm: f64,
    pub default_sd_mm: Option<f64>,
    /// Rows this file may still have: [`MAX_ROWS`], or less when the
    /// manifest's other files have used up most of its total (the
    /// [`MAX_TOTAL_ROWS`] less theirs).
    pub max_rows: usize,
}

/// One record, with the header's column positions.
pub(crate) struct Record<'a> {
    ctx: &'a Context<'a>,
    line: usize,
    fields: csv::StringRecord,
    at: &'a HashMap<&'static str, usize>,
}

impl Record<'_> {
    fn err(&self, name: &str, reason: impl Into<String>) -> MeasureError {
        let col = self.at.get(name).map_or(1, |c| c + 1);
        MeasureError::at(self.ctx.file, self.line, col, name, reason)
    }

    /// The text of a column; `None` when the column is absent or the cell
    /// empty.
    fn text(&self, name: &str) -> Option<&str> {
        let i = *self.at.get(name)?;
        self.fields.get(i).filter(|s| !s.is_empty())
    }

    fn number(&self, name: &str) -> Result<f64, MeasureError> {
        let t = self
            .text(name)
            .ok_or_else(|| self.err(name, "empty: a number is required"))?;
        let x: f64 = t
            .parse()
            .map_err(|_| self.err(name, format!("{t:?} is not a number")))?;
        if !x.is_finite() {
            return Err(self.err(name, format!("{t} is not a finite number")));
        }
        Ok(x)
    }

    fn pressure(&self) -> Result<f64, MeasureError> {
        let p = self.number("pressure_kpa")?;
        if p < VACUUM_KPA {
            return Err(self.err(
                "pressure_kpa",
                format!("{p} kPa is below absolute vacuum ({VACUUM_KPA} kPa gauge)"),
            ));
        }
        if p > MAX_PRESSURE_KPA {
            return Err(self.err(
                "pressure_kpa",
                format!(
                    "{} kPa is above {} kPa, the highest measured pressure",
                    Num(p),
                    Num(MAX_PRESSURE_KPA)
                ),
            ));
        }
        Ok(p)
    }

    /// A number within `max` in magnitude (`unit` in the message).
    fn bounded(&self, name: &str, max: f64, unit: &str) -> Result<f64, MeasureError> {
        let x = self.number(name)?;
        match beyond(x, max, unit) {
            Some(why) => Err(self.err(name, why)),
            None => Ok(x),
        }
    }

    /// A length (mm) within [`MAX_LENGTH_MM`] in magnitude.
    fn length(&self, name: &str) -> Result<f64, MeasureError> {
        self.bounded(name, MAX_LENGTH_MM, "mm")
    }

    /// A standard deviation from [`super::input::MIN_SD`] to `max`.
    fn sd(&self, name: &str, max: f64, unit: &str) -> Result<f64, MeasureError> {
        let x = self.number(name)?;
        match bad_sd(x, max, unit) {
            Some(why) => Err(self.err(name, why)),
            None => Ok(x),
        }
    }

    pub(crate) fn marker(&self) -> Result<MarkerRow, MeasureError> {
        let pressure_kpa = self.pressure()?;
        let marker = self
            .text("marker")
            .ok_or_else(|| self.err("marker", "empty: a marker name is required"))?
            .to_string();
        let s_mm = self.number("s_mm")?;
        let lx = self.ctx.length_mm;
        if !(0.0..=lx).contains(&s_mm) {
            return Err(self.err(
                "s_mm",
                format!("{s_mm} mm is beyond the finger, whose mid-plane runs from 0 to {lx} mm"),
            ));
        }
        let point_mm = [self.length("x_mm")?, self.length("z_mm")?];
        let sd_mm = match (self.text("sd_mm"), self.ctx.default_sd_mm) {
            (None, Some(sd)) => sd,
            (None, None) => {
                return Err(self.err(
                    "sd_mm",
                    "no standard deviation: give the column sd_mm or the test's sd_mm key",
                ))
            }
            (Some(_), _) => self.sd("sd_mm", MAX_LENGTH_MM, "mm")?,
        };
        Ok(MarkerRow {
            line: self.line,
            pressure_kpa,
            marker,
            s_mm,
            point_mm,
            sd_mm,
        })
    }

    pub(crate) fn radius(&self) -> Result<RadiusRow, MeasureError> {
        let pressure_kpa = self.pressure()?;
        let radius_mm = self.length("radius_mm")?;
        if radius_mm <= 0.0 {
            return Err(self.err("radius_mm", format!("{radius_mm} must be positive")));
        }
        Ok(RadiusRow {
            line: self.line,
            pressure_kpa,
            radius_mm,
            sd_mm: self.sd("sd_mm", MAX_LENGTH_MM, "mm")?,
        })
    }

    pub(crate) fn force(&self) -> Result<ForceRow, MeasureError> {
        let pressure_kpa = self.pressure()?;
        let axis = match self.text("axis") {
            Some("X") => Axis::X,
            Some("Z") => Axis::Z,
            other => {
                return Err(self.err(
                    "axis",
                    format!("{:?} is not an axis: X or Z", other.unwrap_or("")),
                ))
            }
        };
        let displacement_mm = self.length("displacement_mm")?;
        if displacement_mm == 0.0 {
            return Err(self.err("displacement_mm", "must not be 0"));
        }
        let force_n = self.bounded("force_n", MAX_FORCE_N, "N")?;
        let sd_n = self.sd("sd_n", MAX_FORCE_N, "N")?;
        let t = self.text("repeats").unwrap_or("");
        let repeats = t
            .parse::<u32>()
            .ok()
            .filter(|r| (1..=MAX_REPEATS).contains(r))
            .ok_or_else(|| {
                self.err(
                    "repeats",
                    format!("{t:?} is not a whole number from 1 to {MAX_REPEATS}"),
                )
            })?;
        Ok(ForceRow {
            line: self.line,
            pressure_kpa,
            axis,
            displacement_mm,
            force_n,
            sd_n,
            repeats,
        })
    }
}

/// The rows of one test file, of the kind's type `R`.
pub(crate) fn read<R>(
    kind: TestKind,
    text: &str,
    ctx: &Context,
    parse: impl Fn(&Record) -> Result<R, MeasureError>,
    key: impl Fn(&R) -> (String, &'static str),
) -> Result<Vec<R>, MeasureError> {
    let bytes = lone_cr_as_lf(text);
    let mut lines = Lines::new(&bytes);
    let mut rdr = csv::ReaderBuilder::new()
        .trim(csv::Trim::All)
        .comment(Some(b'#'))
        .flexible(true)
        .from_reader(bytes.as_slice());
    let header = rdr
        .headers()
        .map_err(|e| csv_error(ctx.file, &e, &mut lines))?
        .clone();
    let header_line = lines.of(header.position());
    let known = columns(kind);
    let names = || known.iter().map(|c| c.0).collect::<Vec<&str>>().join(", ");
    if header.is_empty() {
        // (a file of comments and blank lines only: its first line)
        return Err(MeasureError::at(
            ctx.file,
            1,
            1,
            "header",
            format!(
                "the file is empty: a {} test starts with a header of its columns ({})",
                kind.name(),
                names()
            ),
        ));
    }
    let mut at: HashMap<&'static str, usize> = HashMap::new();
    for (i, name) in header.iter().enumerate() {
        let here = |reason: String| MeasureError::at(ctx.file, header_line, i + 1, name, reason);
        let Some(&(known_name, _)) = known.iter().find(|(n, _)| *n == name) else {
            return Err(here(format!(
                "unknown column for a {} test (its columns: {})",
                kind.name(),
                names()
            )));
        };
        if at.insert(known_name, i).is_some() {
            return Err(here("a second column of this name".into()));
        }
    }
    if let Some(&(missing, _)) = known.iter().find(|(n, req)| *req && !at.contains_key(n)) {
        return Err(MeasureError::at(
            ctx.file,
            header_line,
            header.len() + 1,
            missing,
            format!("missing column (the header has {} columns)", header.len()),
        ));
    }
    let mut rows = Vec::new();
    let mut seen: HashMap<String, usize> = HashMap::new();
    for record in rdr.records() {
        let fields = record.map_err(|e| csv_error(ctx.file, &e, &mut lines))?;
        let line = lines.of(fields.position());
        if rows.len() == ctx.max_rows {
            return Err(MeasureError::at(
                ctx.file,
                line,
                1,
                "rows",
                too_many_rows(ctx.max_rows),
            ));
        }
        if fields.len() != header.len() {
            return Err(MeasureError::at(
                ctx.file,
                line,
                fields.len().min(header.len()) + 1,
                header.get(fields.len()).unwrap_or("row"),
                format!(
                    "{} fields where the header has {}",
                    fields.len(),
                    header.len()
                ),
            ));
        }
        let record = Record {
            ctx,
            line,
            fields,
            at: &at,
        };
        let row = parse(&record)?;
        let (k, what) = key(&row);
        if let Some(first) = seen.insert(k, line) {
            return Err(record.err(
                "pressure_kpa",
                format!("duplicates row {first} (the same {what})"),
            ));
        }
        rows.push(row);
    }
    Ok(rows)
}

/// A number as a key of duplicate detection (`-0` and `0` alike).
pub(crate) fn bits(x: f64) -> u64 {
    (x + 0.0).to_bits()
}

/// Why a file's row after its first `max_rows` is refused: the limit of
/// one file ([`MAX_ROWS`]), or, when the manifest's files before it have
/// used more than `MAX_TOTAL_ROWS - MAX_ROWS` of their total
/// ([`Context::max_rows`] is then what they left), the manifest's.
fn too_many_rows(max_rows: usize) -> String {
    if max_rows >= MAX_ROWS {
        format!(
            "more than {MAX_ROWS} data rows, the limit of one file ({MAX_TOTAL_ROWS} in all the files of a manifest)"
        )
    } else {
        format!(
            "more than {max_rows} data rows: the manifest's limit is {MAX_TOTAL_ROWS} data rows in all its files, and its files before this one have {}",
            MAX_TOTAL_ROWS - max_rows
        )
    }
}

/// The text as the reader reads it: each lone CR (an old Mac line end)
/// made a LF, as the reader ends a comment line at a LF only (it would
/// read the rest of the file into the comment); of the same length, so
/// that a byte position is the text's.
fn lone_cr_as_lf(text: &str) -> Vec<u8> {
    let b = text.as_bytes();
    b.iter()
        .enumerate()
        .map(|(i, &c)| match c {
            b'\r' if b.get(i + 1) != Some(&b'\n') => b'\n',
            c => c,
        })
        .collect()
}

/// The physical line (from 1) of each record of a text read by
/// [`lone_cr_as_lf`], every line ending (LF, CRLF, lone CR) counted once.
///
/// The reader's position of a record is where it stopped after the one
/// before: before the LF of a CRLF and the blank and comment lines it skips
/// to the record, which its own line count does not include. The record's
/// line is counted here from the byte: past what the reader skips, the LFs
/// before it. Records come in order, so the count goes on from the last.
struct Lines<'a> {
    text: &'a [u8],
    /// A byte of the text and its line.
    at: usize,
    line: usize,
}

impl<'a> Lines<'a> {
    fn new(text: &'a [u8]) -> Self {
        Lines {
            text,
            at: 0,
            line: 1,
        }
    }

    /// The line of the record at the reader's position `pos` (line 1 when
    /// there is none).
    fn of(&mut self, pos: Option<&csv::Position>) -> usize {
        let Some(pos) = pos else { return 1 };
        let t = self.text;
        let mut i = usize::try_from(pos.byte()).map_or(t.len(), |b| b.min(t.len()));
        // what the reader skips before a record: line ends (and so blank
        // lines), and comment lines through their LF
        while let Some(&c) = t.get(i) {
            match c {
                b'\r' | b'\n' => i += 1,
                b'#' => {
                    i = t[i..]
                        .iter()
                        .position(|&c| c == b'\n')
                        .map_or(t.len(), |n| i + n + 1)
                }
                _ => break,
            }
        }
        if i < self.at {
            (self.at, self.line) = (0, 1);
        }
        self.line += t[self.at..i].iter().filter(|&&c| c == b'\n').count();
        self.at = i;
        self.line
    }
}

fn csv_error(file: &str, e: &csv::Error, lines: &mut Lines) -> MeasureError {
    let line = lines.of(e.position());
    let reason = match e.kind() {
        csv::ErrorKind::Utf8 { .. } => "not UTF-8 text".to_string(),
        _ => e.to_string(),
    };
    MeasureError::at(file, line, 1, "row", reason)
}

//! The model against the measurements, with no fitting: a prediction of
//! every measured value from the specimen's scene, its residual in units
//! and in standard deviations, the chi-square, the model's validity
//! verdict on every prediction, and the figures of the paper's Fig. 16(b)
//! and Fig. 18 (docs/measurements.md).
//!
//! Every number of a comparison is finite: the measurements are bounded
//! when read, a model value beyond [`MAX_MODEL_VALUE`] in magnitude (or
//! not finite) is no prediction, its row's `failure` saying so, and a
//! failed solve's residual that is not a number is said in words.

use std::collections::HashMap;

use serde::Serialize;

use super::input::TestKind;
use super::manifest::{Manifest, Specimen, Test, TestData};
use super::table::bits;
use crate::circle_fit::fit_circle;
use crate::error::Warning;
use crate::field::Field;
use crate::finger::{Load, SolveOptions};
use crate::plan::{PlannedFinger, Solved};
use crate::report::{Cell, Column, Figure, Panel, PlotAxis, Series, SeriesKind, Table};
use crate::scene::warning_text;
use crate::solve_error::SolveError;
use crate::studies::{eps0_key, tip_force_for_displacement_with_kappa, warnings_cell, Axis};

/// One measured quantity of a row against the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Residual {
    /// `x_mm`, `z_mm`, `radius_mm` or `force_n`.
    pub quantity: &'static str,
    /// Its unit.
    pub unit: &'static str,
    /// The measured value.
    pub measured: f64,
    /// Its standard deviation (for a force, of the mean of the repeats).
    pub sd: f64,
    /// The model's value (`None`: no prediction, [`Prediction::failure`]).
    pub predicted: Option<f64>,
    /// `measured - predicted`, in the unit.
    pub residual: Option<f64>,
    /// The residual in standard deviations.
    pub residual_sd: Option<f64>,
}

impl Residual {
    pub(super) fn new(
        quantity: &'static str,
        unit: &'static str,
        measured: f64,
        sd: f64,
    ) -> Residual {
        Residual {
            quantity,
            unit,
            measured,
            sd,
            predicted: None,
            residual: None,
            residual_sd: None,
        }
    }

    fn predict(&mut self, predicted: f64) {
        let r = self.measured - predicted;
        self.predicted = Some(predicted);
        self.residual = Some(r);
        self.residual_sd = Some(r / self.sd);
    }
}

/// The model's prediction of one data row.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Prediction {
    /// The row's line in its file.
    pub line: usize,
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// The marker (markers).
    pub marker: Option<String>,
    /// The marker's position along the mid-plane (mm; markers).
    pub s_mm: Option<f64>,
    /// The axis of force and displacement (forces).
    pub axis: Option<&'static str>,
    /// The tip displacement (mm; forces).
    pub displacement_mm: Option<f64>,
    /// The measured quantities and their residuals.
    pub residuals: Vec<Residual>,
    /// The model's verdict: a prediction exists and no finding puts the
    /// finger outside the model's assumptions (docs/model.md section 8).
    pub valid: bool,
    /// The model's findings on the predicting finger.
    pub warnings: Vec<Warning>,
    /// The findings as text.
    pub warning_messages: Vec<String>,
    /// Why the model has no prediction (a failed solve, a straight
    /// mid-plane without a radius).
    pub failure: Option<String>,
}

/// The model curve of a force test: one axis and displacement.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ForceCurve {
    /// The axis.
    pub axis: &'static str,
    /// The displacement (mm).
    pub displacement_mm: f64,
    /// `[pressure_kpa, force_n]` of the model.
    pub points: Vec<[f64; 2]>,
}

/// One test against the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TestComparison {
    /// The CSV file.
    pub file: String,
    /// The kind.
    pub kind: TestKind,
    /// The frame of the measured points and their residuals: `finger`,
    /// or `camera` (a markers test with a camera frame).
    pub frame: &'static str,
    /// One prediction per row, in the file's order.
    pub predictions: Vec<Prediction>,
    /// The sum of the squared residuals in standard deviations.
    pub chi_square: f64,
    /// How many residuals the chi-square sums.
    pub points: usize,
    /// Rows without a prediction.
    pub failed: usize,
    /// Rows predicted by a finger outside the model.
    pub outside_model: usize,
    /// The model's curve over the test's pressures (radius: `[pressure_kpa,
    /// radius_mm]`; empty for markers).
    pub model_curve: Vec<[f64; 2]>,
    /// The model's curves of a force test, one per axis and displacement.
    pub force_curves: Vec<ForceCurve>,
}

/// One specimen against the model.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct SpecimenComparison {
    /// The specimen's name.
    pub name: String,
    /// Its prestrain.
    pub eps0: f64,
    /// Its pressure factor (its scene's `load.kappa`, 2.5 unless given).
    pub kappa: f64,
    /// Its tests.
    pub tests: Vec<TestComparison>,
    /// The chi-square of its tests.
    pub chi_square: f64,
    /// How many residuals.
    pub points: usize,
}

/// A manifest against the model ([`compare`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Comparison {
    /// The manifest.
    pub manifest: String,
    /// The specimens.
    pub specimens: Vec<SpecimenComparison>,
    /// The chi-square of every residual.
    pub chi_square: f64,
    /// How many residuals.
    pub points: usize,
    /// Rows without a prediction.
    pub failed: usize,
    /// Rows predicted by a finger outside the model.
    pub outside_model: usize,
}

/// Points of a model curve.
const CURVE_POINTS: usize = 33;

/// Largest magnitude of a model value that is compared (mm or N). Beyond
/// it the model's answer is no prediction (a row's `failure` says so; a
/// curve leaves the point out): with the bounded measurements
/// ([`super::input::MAX_LENGTH_MM`], [`super::input::MIN_SD`], ...) every
/// residual in standard deviations, its square and the chi-square of the
/// most rows a manifest may have stay finite.
const MAX_MODEL_VALUE: f64 = 1e100;

/// Whether a model value is compared ([`MAX_MODEL_VALUE`]).
fn usable(v: f64) -> bool {
    v.abs() <= MAX_MODEL_VALUE
}

/// The model's finger of one specimen, with its unloaded solves by
/// pressure.
struct Model {
    planned: PlannedFinger,
    opts: SolveOptions,
    /// The specimen's pressure factor (its scene's `load.kappa`).
    kappa: f64,
    solved: HashMap<u64, Result<Solved, String>>,
}

impl Model {
    fn new(s: &Specimen) -> Result<Model, SolveError> {
        let planned = PlannedFinger::builder(&s.scene.actuator)
            .model(s.scene.model)
            .plan(s.scene.partition.plan())
            .build()?;
        let opts = SolveOptions {
            shape: true,
            ..s.scene.options
        };
        Ok(Model {
            planned,
            opts,
            kappa: s.scene.load.kappa,
            solved: HashMap::new(),
        })
    }

    /// The unloaded finger at `p` kPa.
    fn at(&mut self, p: f64) -> Result<&Solved, String> {
        let (planned, opts) = (&self.planned, &self.opts);
        let load = Load {
            kappa: self.kappa,
            ..Load::unloaded()
        }
        .with_pressure_kpa(p);
        self.solved
            .entry(bits(p))
            .or_insert_with(|| planned.solve(&load, opts).map_err(|e| e.to_string()))
            .as_ref()
            .map_err(Clone::clone)
    }

    /// The circle-fit radius at `p` (the paper's Sec. 6.2, as study 7).
    fn radius(&mut self, p: f64) -> Result<(f64, Vec<Warning>), String> {
        let s = self.at(p)?;
        match fit_circle(&s.solution.points) {
            Some(c) => Ok((c.radius, s.solution.warnings.clone())),
            None => Err("the model's mid-plane is straight: no circle fits it".into()),
        }
    }

    /// The mid-plane point at `s_mm` along the unstretched mid-plane.
    fn marker(&mut self, p: f64, s_mm: f64) -> Result<([f64; 2], Vec<Warning>), String> {
        let s = self.at(p)?;
        let curves = s
            .finger
            .midplane_curves(&s.solution.coefficients)
            .map_err(|e| e.to_string())?;
        let mut start = 0.0;
        for (i, c) in curves.iter().enumerate() {
            if s_mm <= start + c.length() || i + 1 == curves.len() {
                let x = (s_mm - start).clamp(0.0, c.length());
                return Ok((c.point(x), s.solution.warnings.clone()));
            }
            start += c.length();
        }
        Err("the finger has no elements".into())
    }

    /// The study 8 target solve: the tip force along `axis` that moves the
    /// tip `d` mm from its pressurised, unloaded position.
    fn force(&mut self, p: f64, axis: Axis, d: f64) -> Result<(f64, Vec<Warning>), String> {
        let finger = match self.planned.fixed() {
            Some(f) => f.clone(),
            None => self.at(p)?.finger.clone(),
        };
        // the study's names for the row's values are the CSV's columns here
        let column = |f: &Field| match f.to_string().as_str() {
            "displacement.distance" => Some(Field::key("displacement_mm")),
            "displacement.pressure_kpa" => Some(Field::key("pressure_kpa")),
            _ => None,
        };
        tip_force_for_displacement_with_kappa(&finger, p, self.kappa, axis, d)
            .map(|r| (r.force, r.solution.warnings))
            .map_err(|e| e.renamed(column, |_, v| v).to_string())
    }
}

/// A prediction from its measured quantities and the model's answer.
pub(super) fn predicted(
    line: usize,
    pressure_kpa: f64,
    mut residuals: Vec<Residual>,
    answer: Result<(Vec<f64>, Vec<Warning>), String>,
) -> Prediction {
    let answer = answer.and_then(|(values, w)| {
        match values.iter().zip(&residuals).find(|(v, _)| !usable(**v)) {
            Some((v, r)) if v.is_finite() => Err(format!(
                "the model's {} is {v:e} {}, beyond {MAX_MODEL_VALUE:e} in magnitude: not compared",
                r.quantity, r.unit
            )),
            Some((_, r)) => Err(format!(
                "the model's {} is not a finite number: not compared",
                r.quantity
            )),
            None => Ok((values, w)),
        }
    });
    let (warnings, failure) = match answer {
        Ok((values, w)) => {
            for (r, v) in residuals.iter_mut().zip(values) {
                r.predict(v);
            }
            (w, None)
        }
        Err(e) => (Vec::new(), Some(e)),
    };
    Prediction {
        line,
        pressure_kpa,
        marker: None,
        s_mm: None,
        axis: None,
        displacement_mm: None,
        residuals,
        valid: failure.is_none() && !warnings.iter().any(Warning::is_validity),
        warning_messages: warnings.iter().map(warning_text).collect(),
        warnings,
        failure,
    }
}

/// `n` points from `lo` to `hi` (both included; one point when equal,
/// none for the empty range of no rows).
fn grid(lo: f64, hi: f64, n: usize) -> Vec<f64> {
    if !(lo.is_finite() && hi.is_finite()) {
        return Vec::new();
    }
    if hi <= lo {
        return vec![lo];
    }
    (0..n)
        .map(|i| lo + (hi - lo) * i as f64 / (n - 1) as f64)
        .collect()
}

fn range(ps: impl Iterator<Item = f64>) -> (f64, f64) {
    ps.fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
        (a.min(p), b.max(p))
    })
}

fn compare_test(model: &mut Model, test: &Test, curves: bool) -> TestComparison {
    let mut model_curve = Vec::new();
    let mut force_curves = Vec::new();
    let (frame, predictions): (&str, Vec<Prediction>) = match &test.data {
        TestData::Markers { camera, rows } => {
            let preds = rows
                .iter()
                .map(|r| {
                    let res = vec![
                        Residual::new("x_mm", "mm", r.point_mm[0], r.sd_mm),
                        Residual::new("z_mm", "mm", r.point_mm[1], r.sd_mm),
                    ];
                    let answer = model.marker(r.pressure_kpa, r.s_mm).map(|(q, w)| {
                        let q = camera.map_or(q, |c| c.to_camera(q));
                        (q.to_vec(), w)
                    });
                    Prediction {
                        marker: Some(r.marker.clone()),
                        s_mm: Some(r.s_mm),
                        ..predicted(r.line, r.pressure_kpa, res, answer)
                    }
                })
                .collect();
            (if camera.is_some() { "camera" } else { "finger" }, preds)
        }
        TestData::Radius(rows) => {
            let preds = rows
                .iter()
                .map(|r| {
                    let res = vec![Residual::new("radius_mm", "mm", r.radius_mm, r.sd_mm)];
                    let answer = model.radius(r.pressure_kpa).map(|(v, w)| (vec![v], w));
                    predicted(r.line, r.pressure_kpa, res, answer)
                })
                .collect();
            let (lo, hi) = range(rows.iter().map(|r| r.pressure_kpa));
            if curves {
                model_curve = grid(lo, hi, CURVE_POINTS)
                    .into_iter()
                    .filter_map(|p| model.radius(p).ok().map(|(r, _)| [p, r]))
                    .filter(|q| usable(q[1]))
                    .collect();
            }
            ("finger", preds)
        }
        TestData::Force(rows) => {
            let preds = rows
                .iter()
                .map(|r| {
                    let res = vec![Residual::new("force_n", "N", r.force_n, r.sd_of_mean())];
                    let answer = model
                        .force(r.pressure_kpa, r.axis, r.displacement_mm)
                        .map(|(v, w)| (vec![v], w));
                    Prediction {
                        axis: Some(r.axis.name()),
                        displacement_mm: Some(r.displacement_mm),
                        ..predicted(r.line, r.pressure_kpa, res, answer)
                    }
                })
                .collect();
            let mut groups: Vec<(Axis, f64)> = Vec::new();
            for r in rows.iter().filter(|_| curves) {
                if !groups.contains(&(r.axis, r.displacement_mm)) {
                    groups.push((r.axis, r.displacement_mm));
                }
            }
            for (axis, d) in groups {
                let sel = rows
                    .iter()
                    .filter(|r| r.axis == axis && r.displacement_mm == d);
                let (lo, hi) = range(sel.map(|r| r.pressure_kpa));
                let points = grid(lo, hi, CURVE_POINTS / 2 + 1)
                    .into_iter()
                    .filter_map(|p| model.force(p, axis, d).ok().map(|(f, _)| [p, f]))
                    .filter(|q| usable(q[1]))
                    .collect();
                force_curves.push(ForceCurve {
                    axis: axis.name(),
                    displacement_mm: d,
                    points,
                });
            }
            ("finger", preds)
        }
    };
    let (chi_square, points) = chi_square(&predictions);
    TestComparison {
        file: test.file.clone(),
        kind: test.data.kind(),
        frame,
        failed: predictions.iter().filter(|p| p.failure.is_some()).count(),
        outside_model: predictions
            .iter()
            .filter(|p| p.failure.is_none() && !p.valid)
            .count(),
        predictions,
        chi_square,
        points,
        model_curve,
        force_curves,
    }
}

/// The sum of `values`, 0 (not -0, as `Sum` gives) for none: what a
/// report writes for a specimen without tests.
pub(crate) fn total(values: impl Iterator<Item = f64>) -> f64 {
    values.fold(0.0, |a, b| a + b)
}

fn chi_square(preds: &[Prediction]) -> (f64, usize) {
    let z = preds
        .iter()
        .flat_map(|p| &p.residuals)
        .filter_map(|r| r.residual_sd);
    z.fold((0.0, 0), |(c, n), z| (c + z * z, n + 1))
}

/// Every test of every specimen of `manifest` against the model: one
/// prediction per row, from the specimen's scene with no parameter
/// fitted. A row the model cannot predict (a failed solve, a straight
/// mid-plane) keeps its measured values and says why; only an actuator
/// the model cannot be built for is an error.
pub fn compare(manifest: &Manifest) -> Result<Comparison, SolveError> {
    compare_with(manifest, true)
}

/// [`compare`], with the model's curves of the figures (`model_curve`,
/// `force_curves`) or without them (empty; a check needs the rows only).
pub(crate) fn compare_with(manifest: &Manifest, curves: bool) -> Result<Comparison, SolveError> {
    let mut specimens = Vec::new();
    for s in &manifest.specimens {
        let mut model = Model::new(s)?;
        let tests: Vec<TestComparison> = s
            .tests
            .iter()
            .map(|t| compare_test(&mut model, t, curves))
            .collect();
        specimens.push(SpecimenComparison {
            name: s.name.clone(),
            eps0: s.scene.actuator.eps0(),
            kappa: s.scene.load.kappa,
            chi_square: total(tests.iter().map(|t| t.chi_square)),
            points: tests.iter().map(|t| t.points).sum(),
            tests,
        });
    }
    let tests = || specimens.iter().flat_map(|s| &s.tests);
    Ok(Comparison {
        manifest: manifest.file.clone(),
        chi_square: total(specimens.iter().map(|s| s.chi_square)),
        points: specimens.iter().map(|s| s.points).sum(),
        failed: tests().map(|t| t.failed).sum(),
        outside_model: tests().map(|t| t.outside_model).sum(),
        specimens,
    })
}

// ------------------------------------------------------------ outputs

/// The columns of `compare.csv`: one row per measured quantity.
pub const COMPARE_COLUMNS: [Column; 20] = [
    Column::new("specimen", ""),
    Column::new("eps0", ""),
    Column::new("file", ""),
    Column::new("kind", ""),
    Column::new("row", ""),
    Column::new("pressure_kpa", "kPa"),
    Column::new("marker", ""),
    Column::new("s_mm", "mm"),
    Column::new("axis", ""),
    Column::new("displacement_mm", "mm"),
    Column::new("frame", ""),
    Column::new("quantity", ""),
    Column::new("measured", ""),
    Column::new("sd", ""),
    Column::new("predicted", ""),
    Column::new("residual", ""),
    Column::new("residual_sd", ""),
    Column::new("valid", ""),
    Column::new("warnings", ""),
    Column::new("note", ""),
];

/// The comparison as one table (`compare.csv`): a row per measured
/// quantity (a marker has two, `x_mm` and `z_mm`); `quantity` names it
/// with its unit, which `measured`, `sd`, `predicted` and `residual` are
/// in.
pub fn table(c: &Comparison) -> Table {
    let mut t = Table::new("compare", &COMPARE_COLUMNS);
    for s in &c.specimens {
        for test in &s.tests {
            for p in &test.predictions {
                for r in &p.residuals {
                    t.push(vec![
                        s.name.as_str().into(),
                        s.eps0.into(),
                        test.file.as_str().into(),
                        test.kind.name().into(),
                        (p.line as f64).into(),
                        p.pressure_kpa.into(),
                        p.marker.as_deref().map_or(Cell::Empty, Cell::from),
                        p.s_mm.into(),
                        p.axis.map_or(Cell::Empty, Cell::from),
                        p.displacement_mm.into(),
                        test.frame.into(),
                        r.quantity.into(),
                        r.measured.into(),
                        r.sd.into(),
                        r.predicted.into(),
                        r.residual.into(),
                        r.residual_sd.into(),
                        p.valid.into(),
                        warnings_cell(&p.warnings),
                        p.failure.clone().map_or(Cell::Empty, Cell::from),
                    ]);
                }
            }
        }
    }
    t
}

/// Measured points with their error bars (one short line per point).
fn measured(panel: &mut Panel, key: &str, label: String, pts: &[(f64, f64, f64)]) {
    panel.series.push(
        Series::new(
            key,
            SeriesKind::Points,
            pts.iter().map(|&(x, y, _)| [x, y]).collect(),
        )
        .label(label),
    );
    for &(x, y, sd) in pts {
        panel.series.push(Series::new(
            key,
            SeriesKind::Line,
            vec![[x, y - sd], [x, y + sd]],
        ));
    }
}

/// The measured values of a test's predictions as (pressure, value, sd).
fn data(test: &TestComparison, keep: impl Fn(&Prediction) -> bool) -> Vec<(f64, f64, f64)> {
    test.predictions
        .iter()
        .filter(|p| keep(p))
        .filter_map(|p| {
            p.residuals
                .first()
                .map(|r| (p.pressure_kpa, r.measured, r.sd))
        })
        .collect()
}

/// The names of every figure [`figures`] may draw.
pub const FIGURE_STEMS: [&str; 2] = ["compare_radius", "compare_force"];

/// The figures: `compare_radius` (radius of curvature against pressure,
/// the data with error bars of one standard deviation and the model's
/// curve, as the paper's Fig. 16(b)) and `compare_force` (the tip force
/// against pressure, error bars of one standard deviation of the mean,
/// as Fig. 18), each when the manifest has such tests.
pub fn figures(c: &Comparison) -> Vec<(&'static str, Figure)> {
    let [radius_stem, force_stem] = FIGURE_STEMS;
    let mut radius = Panel::new(
        "Radius of curvature against pressure (bars: ±1 sd)",
        PlotAxis::new("pressure P", "kPa"),
        PlotAxis::new("radius R", "mm"),
    );
    radius.y.include_zero = true;
    let mut force = Panel::new(
        "Tip force against pressure (bars: ±1 sd of the mean)",
        PlotAxis::new("pressure P", "kPa"),
        PlotAxis::new("tip force", "N"),
    );
    force.y.include_zero = true;
    for s in &c.specimens {
        let key = eps0_key(s.eps0);
        for t in s.tests.iter().filter(|t| !t.predictions.is_empty()) {
            match t.kind {
                TestKind::Radius => {
                    measured(
                        &mut radius,
                        &key,
                        format!("{}: measured", s.name),
                        &data(t, |_| true),
                    );
                    radius.series.push(
                        Series::new(key.clone(), SeriesKind::Line, t.model_curve.clone())
                            .label(format!("{}: model (ε0 = {})", s.name, s.eps0)),
                    );
                }
                TestKind::Force => {
                    for fc in &t.force_curves {
                        let what = format!("+{} {} mm", fc.axis, fc.displacement_mm);
                        let pts = data(t, |p| {
                            p.axis == Some(fc.axis) && p.displacement_mm == Some(fc.displacement_mm)
                        });
                        measured(
                            &mut force,
                            &key,
                            format!("{}, {what}: measured", s.name),
                            &pts,
                        );
                        force.series.push(
                            Series::new(key.clone(), SeriesKind::Line, fc.points.clone())
                                .label(format!("{}, {what}: model", s.name)),
                        );
                    }
                }
                TestKind::Markers => {}
            }
        }
    }
    let mut out = Vec::new();
    if !radius.series.is_empty() {
        out.push((
            radius_stem,
            Figure::row(
                "fpc compare: radius of curvature against pressure (as the paper's Fig. 16(b))",
                [1000, 600],
                vec![radius],
            ),
        ));
    }
    if !force.series.is_empty() {
        out.push((
            force_stem,
            Figure::row(
                "fpc compare: tip force against pressure (as the paper's Fig. 18)",
                [1000, 600],
                vec![force],
            ),
        ));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_specimen_without_tests_has_a_chi_square_of_plus_zero() {
        // `Sum` of no f64 is -0.0, which the reports wrote as "-0.0"
        assert!(total(std::iter::empty()).is_sign_positive());
        let m = Manifest::parse(
            "[[specimen]]\nname = \"a\"\n",
            "m.toml",
            std::path::Path::new("."),
        )
        .unwrap();
        let c = compare(&m).unwrap();
        assert_eq!(c.specimens.len(), 1);
        assert!(c.specimens[0].chi_square.is_sign_positive());
        assert!(c.chi_square.is_sign_positive());
        let json = serde_json::to_string(&c).unwrap();
        assert!(!json.contains("-0.0"), "{json}");
    }
}

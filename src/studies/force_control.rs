//! Study 4 (Sec. 5.1.2): force control by pressure.

use serde::Serialize;

use super::bands::{exact_bands, BandParams, BAND_LABEL};
use super::info::StudyInfo;
use super::options::{section5_gripper, StudyOptions, SweepStop, SECTION5_EPS0};
use super::output::*;
use crate::actuator::Actuator;
use crate::error::Warning;
use crate::gripper::{Grasp, Gripper, Invalid};
use crate::sensitivity::{Covariance, GraspKind, GraspSensitivity, GripperParam, Param};
use crate::solve_error::SolveError;

/// One pressure of the force-control study.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceControlRow {
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Normal force `F` that holds the cuboid (N).
    pub normal: f64,
    /// Finger height `h` (mm).
    pub height: f64,
    /// Gap between the tips (mm).
    pub tip_gap: f64,
    /// True when `F >= 0` and `f <= mu F`.
    pub friction_ok: bool,
    /// True when the grasp is valid (the one verdict,
    /// [`crate::gripper::Verdict`]).
    pub valid: bool,
    /// The first reason it is not (`None`: valid).
    pub invalid: Option<Invalid>,
    /// An element is bent backwards.
    pub reversed: bool,
    /// The grasp's validity findings.
    pub warnings: Vec<Warning>,
    /// With a covariance ([`study4_force_control_with`]): 1-sigma of the
    /// normal force, the height and the tip gap; `None` without one, or
    /// when the grasp's sensitivities failed (`sd_note` says why).
    pub sd: Option<ForceControlSd>,
    /// Why a row of a study with a covariance has no `sd`.
    pub sd_note: Option<String>,
}

/// 1-sigma of a row of study 4 from a covariance, by first-order
/// propagation through the grasp's exact sensitivities
/// ([`crate::Gripper::grasp_sensitivities`], force control).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ForceControlSd {
    /// Of the normal force F (N).
    pub normal: f64,
    /// Of the finger height h (mm).
    pub height: f64,
    /// Of the tip gap (mm).
    pub tip_gap: f64,
}

/// Study 4 result.
#[derive(Debug, Clone, PartialEq)]
pub struct ForceControl {
    /// Cuboid size (mm).
    pub size: f64,
    /// Friction per finger (N).
    pub friction: f64,
    /// One row per pressure, 0 to 100 kPa in steps of 10.
    pub rows: Vec<ForceControlRow>,
    /// Set when the pressure sweep stopped early.
    pub stopped: Option<SweepStop>,
}

/// Study 4 (Sec. 5.1.2): the Sec. 5 gripper holds a cuboid of d = 100 mm
/// with f = 0.3 N per finger; for each pressure, the normal force and the
/// finger height. Every pressure keeps its row: in strict mode a grasp
/// bent backwards is marked not valid.
pub fn study4_force_control(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<ForceControl, SolveError> {
    study4_force_control_with(actuator, opts, None)
}

/// [`study4_force_control`], and with a covariance of the actuator's
/// parameters each row's 1-sigma ([`ForceControlRow::sd`]) by first-order
/// propagation through the grasp's exact sensitivities. The gripper's
/// prestrain (0.25) is the study's own: its variance is not propagated
/// (`crate::studies::not_propagated`).
pub fn study4_force_control_with(
    actuator: &Actuator,
    opts: &StudyOptions,
    covariance: Option<&Covariance>,
) -> Result<ForceControl, SolveError> {
    let g = section5_gripper(actuator, opts)?;
    let bands = covariance.map(BandParams::new);
    let act = actuator.with_eps0(SECTION5_EPS0)?;
    let (size, friction) = (100.0, 0.3);
    let mut rows = Vec::new();
    let mut stopped = None;
    let mut warm: Option<Grasp> = None;
    for i in 0..=10 {
        let p = 10.0 * i as f64;
        match g.force_control(p, size, friction, warm.as_ref()) {
            Ok(gr) => {
                let (sd, sd_note) = match &bands {
                    Some(b) => {
                        let kind = GraspKind::ForceControl { d: size, friction };
                        match row_sd(&g, &act, &gr, kind, b) {
                            Ok(sd) => (Some(sd), None),
                            Err(e) => (None, Some(format!("no error bars: {e}"))),
                        }
                    }
                    None => (None, None),
                };
                rows.push(ForceControlRow {
                    pressure_kpa: p,
                    normal: gr.normal,
                    height: gr.height,
                    tip_gap: gr.tip_gap,
                    friction_ok: gr.friction_ok(g.mu()),
                    valid: gr.is_valid(),
                    invalid: gr.invalid(),
                    reversed: gr.is_reversed(),
                    warnings: gr.warnings.clone(),
                    sd,
                    sd_note,
                });
                warm = Some(gr);
            }
            Err(e) => {
                stopped = Some(SweepStop::failed(p, e.to_string()));
                break;
            }
        }
    }
    Ok(ForceControl {
        size,
        friction,
        rows,
        stopped,
    })
}

/// The 1-sigma of a grasp's outputs (module `bands`).
fn row_sd(
    g: &Gripper,
    act: &Actuator,
    grasp: &Grasp,
    kind: GraspKind,
    b: &BandParams,
) -> Result<ForceControlSd, SolveError> {
    let params: Vec<GripperParam> = b
        .params()
        .into_iter()
        .filter_map(|p| match p {
            Param::Actuator(a) => Some(GripperParam::Actuator(a)),
            _ => None,
        })
        .collect();
    let rows = g.grasp_sensitivities(act, grasp, kind, &params)?.rows;
    let s = |f: fn(&GraspSensitivity) -> f64| b.sigma(&rows.iter().map(f).collect::<Vec<_>>());
    Ok(ForceControlSd {
        normal: s(|r| r.normal),
        height: s(|r| r.height),
        tip_gap: s(|r| r.tip_gap),
    })
}

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 4,
    key: "force_control",
    title: "Force control by pressure",
    description: "The same gripper holds a cuboid of d = 100 mm with friction f = 0.3 N per finger; for each pressure, the normal force F that holds it and the finger height h (Sec. 5.1.2).",
    run: |act, opts, cov| {
        Ok(output(
            Some(&study4_force_control_with(act, opts, cov)?),
            opts.mu,
            cov.is_some(),
        ))
    },
    has_bands: true,
    empty: || output(None, StudyOptions::default().mu, false),
};

const COLUMNS: [Column; 5] = [
    Column::new("pressure_kpa", "kPa"),
    Column::new("F_n", "N"),
    Column::new("h_mm", "mm"),
    Column::new("tip_gap_mm", "mm"),
    Column::new("friction_ok", ""),
];

/// The 1-sigma columns, with a covariance (`bands`).
const SD_COLUMNS: [Column; 3] = [
    Column::new("F_n_sd", "N"),
    Column::new("h_mm_sd", "mm"),
    Column::new("tip_gap_mm_sd", "mm"),
];

/// One entry of `force_control`.
#[derive(Serialize)]
struct Row {
    pressure_kpa: f64,
    #[serde(rename = "F_n")]
    f_n: f64,
    h_mm: f64,
    tip_gap_mm: f64,
    friction_ok: bool,
    /// With a covariance: the 1-sigma of F, h (null where none).
    #[serde(rename = "F_n_sd", skip_serializing_if = "Option::is_none")]
    f_n_sd: Option<Option<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    h_mm_sd: Option<Option<f64>>,
}

#[derive(Serialize)]
struct Case {
    d_mm: f64,
    f_n: f64,
    stopped: Option<StopEntry>,
}

#[derive(Serialize)]
struct Summary {
    force_control: Vec<Row>,
    force_control_case: Option<Case>,
}

/// The outputs of study 4 (`None`: the empty outputs); `with_sd`: the
/// rows' 1-sigma too (columns `<column>_sd`, a band, summary entries).
pub(crate) fn output(fc: Option<&ForceControl>, mu: f64, with_sd: bool) -> StudyOutput {
    let lead: Vec<Column> = if with_sd {
        COLUMNS.iter().chain(&SD_COLUMNS).copied().collect()
    } else {
        COLUMNS.to_vec()
    };
    let mut a = Assembly::new(
        &[("study4", &columns(&lead, &GRASP_TAIL))],
        &["P (kPa)", "F (N)", "h (mm)", "f ≤ μF", "valid"],
    );
    let Some(fc) = fc else {
        let summary = Summary {
            force_control: Vec::new(),
            force_control_case: None,
        };
        return a.empty(&summary);
    };
    let yes = |b: bool| if b { "yes" } else { "no" }.to_string();
    for r in &fc.rows {
        let mut lead = vec![
            r.pressure_kpa.into(),
            r.normal.into(),
            r.height.into(),
            r.tip_gap.into(),
            r.friction_ok.into(),
        ];
        if with_sd {
            lead.extend([
                r.sd.map(|s| s.normal).into(),
                r.sd.map(|s| s.height).into(),
                r.sd.map(|s| s.tip_gap).into(),
            ]);
        }
        a.grasp(0, lead, r.reversed, r.invalid.as_ref(), &r.warnings);
        if let Some(n) = &r.sd_note {
            if let Some(row) = a.tables[0].rows.last_mut() {
                let at = row.len() - 1;
                row[at] = n.clone().into();
            }
        }
        a.overview.push(vec![
            fmt(r.pressure_kpa, 0),
            fmt(r.normal, 3),
            fmt(r.height, 1),
            yes(r.friction_ok),
            yes(r.valid),
        ]);
    }
    if let Some(s) = &fc.stopped {
        a.stop(
            0,
            vec![],
            "pressure_kpa",
            "force control",
            StopAt::Kpa,
            s,
            true,
        );
    }
    let summary = Summary {
        force_control: fc
            .rows
            .iter()
            .map(|r| Row {
                pressure_kpa: r.pressure_kpa,
                f_n: r.normal,
                h_mm: r.height,
                tip_gap_mm: r.tip_gap,
                friction_ok: r.friction_ok,
                f_n_sd: with_sd.then(|| r.sd.map(|s| s.normal)),
                h_mm_sd: with_sd.then(|| r.sd.map(|s| s.height)),
            })
            .collect(),
        force_control_case: Some(Case {
            d_mm: fc.size,
            f_n: fc.friction,
            stopped: stop_entry(&fc.stopped, StopAt::Kpa),
        }),
    };
    a.strict_dropped = fc
        .rows
        .iter()
        .filter(|r| matches!(r.invalid, Some(Invalid::CurvatureReversal { .. })))
        .count();
    let mut out = a.finish(figure(fc, mu, with_sd), &summary);
    if with_sd {
        out.bands = exact_bands(&SD_COLUMNS);
    }
    out
}

/// Normal force and finger height against pressure; `with_sd`: their
/// 1-sigma bands.
fn figure(fc: &ForceControl, mu: f64, with_sd: bool) -> Figure {
    let band = |key: &str, y: fn(&ForceControlRow) -> f64, sd: fn(&ForceControlSd) -> f64| {
        let (at, s): (Vec<[f64; 2]>, Vec<f64>) = fc
            .rows
            .iter()
            .map(|r| ([r.pressure_kpa, y(r)], r.sd.as_ref().map_or(f64::NAN, sd)))
            .unzip();
        Series::spread(key, &at, &s, [f64::MIN, f64::MAX]).map(|s| s.label(BAND_LABEL))
    };
    let mut p = Panel::new(
        "Normal force",
        PlotAxis::new("pressure P", "kPa"),
        PlotAxis::new("normal force F", "N"),
    );
    p.y.include_zero = true;
    if with_sd {
        p.series
            .extend(band("normal force", |r| r.normal, |s| s.normal));
    }
    let bent = pts(fc
        .rows
        .iter()
        .filter(|r| r.reversed)
        .map(|r| (r.pressure_kpa, r.normal)));
    p.curve(
        Series::new(
            "normal force",
            SeriesKind::LinePoints,
            pts(fc.rows.iter().map(|r| (r.pressure_kpa, r.normal))),
        )
        .label("F holding the cuboid"),
        bent,
    );
    let slips = pts(fc
        .rows
        .iter()
        .filter(|r| !r.friction_ok)
        .map(|r| (r.pressure_kpa, r.normal)));
    if !slips.is_empty() {
        p.series
            .push(Series::new("slips", SeriesKind::Hollow, slips).label("f > μF: slips"));
    }
    p.hlines.push(RefLine {
        at: fc.friction / mu,
        label: format!("F = f/μ = {:.2} N (friction limit)", fc.friction / mu),
    });
    if let Some(s) = &fc.stopped {
        p.notes.push(format!("sweep stopped at {:.1} kPa", s.at));
    }
    let mut h = Panel::new(
        "Finger height",
        PlotAxis::new("pressure P", "kPa"),
        PlotAxis::new("finger height h", "mm"),
    );
    if with_sd {
        h.series.extend(band("height", |r| r.height, |s| s.height));
    }
    h.series.push(
        Series::new(
            "height",
            SeriesKind::LinePoints,
            pts(fc.rows.iter().map(|r| (r.pressure_kpa, r.height))),
        )
        .label("h = tip Zg"),
    );
    Figure::row(
        format!(
            "Study 4: force control by pressure (cuboid d = {} mm, f = {} N per finger)",
            fc.size, fc.friction
        ),
        [1200, 560],
        vec![p, h],
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(p: f64, reversed: bool) -> ForceControlRow {
        ForceControlRow {
            pressure_kpa: p,
            normal: 1.0 - 0.01 * p,
            height: 50.0,
            tip_gap: 100.0,
            friction_ok: true,
            valid: !reversed,
            invalid: reversed.then_some(Invalid::CurvatureReversal {
                element: 1,
                curvature: -0.01,
            }),
            reversed,
            warnings: if reversed {
                vec![Warning::CurvatureReversal {
                    element: 1,
                    curvature: -0.01,
                }]
            } else {
                Vec::new()
            },
            sd: None,
            sd_note: None,
        }
    }

    #[test]
    fn rows_then_the_stop() {
        let fc = ForceControl {
            size: 100.0,
            friction: 0.3,
            rows: vec![row(0.0, false), row(10.0, true)],
            stopped: Some(SweepStop::failed(20.0, "solve failed: test".into())),
        };
        let out = output(Some(&fc), 0.6, false);
        let t = &out.tables[0];
        assert_eq!(t.rows.len(), 3);
        assert_eq!(t.cell(1, "valid"), Some(&Cell::Bool(false)));
        assert_eq!(t.cell(2, "pressure_kpa"), Some(&Cell::Num(20.0)));
        assert_eq!(t.cell(2, "status"), Some(&Cell::from("stopped")));
        assert_eq!(out.points, 2);
        assert_eq!(out.warnings_by_kind["curvature_reversal"], 1);
        assert_eq!(out.strict_dropped, 1);
        assert_eq!(out.stops[0].at, StopAt::Kpa(20.0));
        let summary: serde_json::Map<_, _> = out.summary.into_iter().collect();
        assert_eq!(summary["force_control"].as_array().map(Vec::len), Some(2));
        assert_eq!(summary["force_control"][1]["F_n"], serde_json::json!(0.9));
        assert_eq!(
            summary["force_control_case"]["stopped"]["at_kpa"],
            serde_json::json!(20.0)
        );
        // the F panel marks the grasp bent backwards
        let f = &out.figure.rows[0][0];
        assert!(f
            .series
            .iter()
            .any(|s| s.kind == SeriesKind::BentBackwards && s.points == vec![[10.0, 0.9]]));
    }
}

//! Study 7 (Sec. 6.2): radius of curvature against pressure.

use serde::Serialize;

use super::bands::{exact_bands, BandParams, BAND_LABEL};
use super::info::StudyInfo;
use super::options::{StudyOptions, SweepStop};
use super::output::*;
use crate::actuator::Actuator;
use crate::circle_fit::fit_circle;
use crate::coefficients::Coefficients;
use crate::error::Warning;
use crate::finger::{Finger, Load, Solution, SolveOptions, Solver};
use crate::sensitivity::{radius_rows, Covariance};
use crate::solve_error::SolveError;

/// One pressure of the curvature study.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvatureRow {
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Circle-fit radius of the mid-plane (mm; `None`: nearly straight).
    pub radius: Option<f64>,
    /// Signed curvature `1/radius` (1/mm): positive while the finger
    /// curls towards its prestressed side (-Z), negative once pressure has
    /// reversed the curl, 0 when straight.
    pub curvature: f64,
    /// Angle of the tip tangent (rad).
    pub end_angle: f64,
    /// Tip in the finger frame (mm).
    pub tip: [f64; 2],
    /// The finger's validity findings.
    pub warnings: Vec<Warning>,
    /// 1-sigma of the row's outputs, with a covariance
    /// ([`study7_curvature_with`]); `None` without one, or when this
    /// point's sensitivities failed (`sd_note` says why).
    pub sd: Option<CurvatureSd>,
    /// Why a row of a study with a covariance has no `sd`.
    pub sd_note: Option<String>,
}

/// 1-sigma of a row of study 7 from a covariance, by first-order
/// propagation through the exact sensitivities of its equilibrium.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CurvatureSd {
    /// Of the circle-fit radius (mm; `None` when the row has none).
    pub radius: Option<f64>,
    /// Of the signed curvature (1/mm): the radius' over `R^2`.
    pub curvature: Option<f64>,
    /// Of the end angle (rad).
    pub end_angle: f64,
    /// Of the tip (X, Z) (mm).
    pub tip: [f64; 2],
}

impl CurvatureRow {
    /// True once the curl has reversed (past flat).
    pub fn reversed(&self) -> bool {
        self.curvature < 0.0
    }
}

/// Radius of curvature versus pressure for one prestrain.
#[derive(Debug, Clone, PartialEq)]
pub struct CurvatureCurve {
    /// Prestrain.
    pub eps0: f64,
    /// One row per pressure.
    pub rows: Vec<CurvatureRow>,
    /// Set when the sweep stopped early.
    pub stopped: Option<SweepStop>,
}

/// Study 7 (Sec. 6.2): unloaded fingers of eps0 in {0.15, 0.25, 0.4},
/// pressure from 0 to 400 kPa, circle-fit radius with its side.
pub fn study7_curvature(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<Vec<CurvatureCurve>, SolveError> {
    study7_curvature_with(actuator, opts, None)
}

/// [`study7_curvature`], and with a covariance of the actuator's
/// parameters each row's 1-sigma ([`CurvatureRow::sd`]) by first-order
/// propagation through the exact sensitivities of its equilibrium: the
/// tip and end angle's ([`crate::Finger::sensitivities`]), the radius'
/// through the shape samples and the circle fit's own derivative. The
/// prestrain of each curve and `load.kappa` are the study's own: their
/// variances are not propagated (`crate::studies::not_propagated`).
pub fn study7_curvature_with(
    actuator: &Actuator,
    opts: &StudyOptions,
    covariance: Option<&Covariance>,
) -> Result<Vec<CurvatureCurve>, SolveError> {
    opts.validate()?;
    let bands = covariance.map(BandParams::new);
    let sopts = SolveOptions {
        stability: false,
        ..SolveOptions::default()
    };
    let mut out = Vec::new();
    for eps0 in [0.15, 0.25, 0.4] {
        let finger = opts.finger(actuator, eps0)?;
        let act = actuator.with_eps0(eps0)?;
        let mut solver = Solver::new(&finger);
        let mut rows = Vec::new();
        let mut stopped = None;
        let mut guess: Option<Coefficients> = None;
        for i in 0..opts.pressure_points {
            let p = 400.0 * i as f64 / (opts.pressure_points - 1) as f64;
            let load = Load::unloaded().with_pressure_kpa(p);
            match solver.solve(&load, guess.as_ref(), &sopts) {
                Ok(sol) => {
                    let mut row = curvature_row(p, &sol);
                    if let Some(b) = &bands {
                        match row_sd(&finger, &act, &sol, &load, b, sopts.samples_per_element) {
                            Ok(sd) => row.sd = Some(sd),
                            Err(e) => row.sd_note = Some(format!("no error bars: {e}")),
                        }
                    }
                    rows.push(row);
                    guess = Some(sol.coefficients);
                }
                Err(e) => {
                    stopped = Some(SweepStop::failed(p, e.to_string()));
                    break;
                }
            }
        }
        out.push(CurvatureCurve {
            eps0,
            rows,
            stopped,
        });
    }
    Ok(out)
}

/// The 1-sigma of a row's outputs (module `bands`).
fn row_sd(
    finger: &Finger,
    act: &Actuator,
    sol: &Solution,
    load: &Load,
    b: &BandParams,
    per: usize,
) -> Result<CurvatureSd, SolveError> {
    let sens = finger.sensitivities(act, sol, load, &b.params())?;
    let col = |f: &dyn Fn(&crate::sensitivity::Sensitivity) -> f64| -> Vec<f64> {
        sens.rows.iter().map(f).collect()
    };
    let radius =
        radius_rows(finger, &sol.coefficients, &sens, per)?.map(|(c, d)| (c.radius, b.sigma(&d)));
    Ok(CurvatureSd {
        radius: radius.map(|r| r.1),
        curvature: radius.map(|(r, s)| s / (r * r)),
        end_angle: b.sigma(&col(&|r| r.end_angle)),
        tip: [b.sigma(&col(&|r| r.tip[0])), b.sigma(&col(&|r| r.tip[1]))],
    })
}

fn curvature_row(pressure_kpa: f64, sol: &Solution) -> CurvatureRow {
    // the side of the fitted circle's centre with respect to the root
    // tangent (the X axis): below it, the finger curls towards -Z
    let circle = fit_circle(&sol.points);
    let curvature = match circle {
        Some(c) if c.radius > 0.0 && c.center[1] != 0.0 => -c.center[1].signum() / c.radius,
        _ => 0.0,
    };
    CurvatureRow {
        pressure_kpa,
        radius: circle.map(|c| c.radius),
        curvature,
        end_angle: sol.end_angle,
        tip: sol.tip,
        warnings: sol.warnings.clone(),
        sd: None,
        sd_note: None,
    }
}

// ------------------------------------------------------------ outputs

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 7,
    key: "curvature",
    title: "Curvature against pressure",
    description: "Unloaded fingers, eps0 in {0.15, 0.25, 0.4}, pressure 0 to 400 kPa: radius of curvature by circle fit; past flat the curl reverses (Sec. 6.2).",
    run: |act, opts, cov| {
        Ok(output(
            &study7_curvature_with(act, opts, cov)?,
            cov.is_some(),
        ))
    },
    has_bands: true,
    empty: || output(&[], false),
};

/// Largest radius drawn in study 7 (mm): near flat the radius diverges.
pub(crate) const STUDY7_RADIUS_CAP_MM: f64 = 1000.0;

const COLUMNS: [Column; 8] = [
    Column::new("eps0", ""),
    Column::new("pressure_kpa", "kPa"),
    Column::new("radius_mm", "mm"),
    Column::new("curvature_per_mm", "1/mm"),
    Column::new("reversed", ""),
    Column::new("end_angle_rad", "rad"),
    Column::new("tip_x_mm", "mm"),
    Column::new("tip_z_mm", "mm"),
];

/// The 1-sigma columns, with a covariance (`bands`).
const SD_COLUMNS: [Column; 5] = [
    Column::new("radius_mm_sd", "mm"),
    Column::new("curvature_per_mm_sd", "1/mm"),
    Column::new("end_angle_rad_sd", "rad"),
    Column::new("tip_x_mm_sd", "mm"),
    Column::new("tip_z_mm_sd", "mm"),
];

#[derive(Serialize)]
struct Point {
    pressure_kpa: f64,
    radius_mm: Option<f64>,
    curvature_per_mm: f64,
    reversed: bool,
    /// With a covariance: the radius' 1-sigma (null where none).
    #[serde(skip_serializing_if = "Option::is_none")]
    radius_mm_sd: Option<Option<f64>>,
    /// With a covariance: the curvature's 1-sigma.
    #[serde(skip_serializing_if = "Option::is_none")]
    curvature_per_mm_sd: Option<Option<f64>>,
}

/// One entry of `radius_vs_pressure`.
#[derive(Serialize)]
struct Curve {
    eps0: f64,
    reversed: bool,
    reversed_from_kpa: Option<f64>,
    points: Vec<Point>,
    stopped: Option<StopEntry>,
}

#[derive(Serialize)]
struct Summary {
    radius_vs_pressure: Vec<Curve>,
}

/// The outputs of study 7 from its curves; `with_sd`: its rows' 1-sigma
/// too (columns `<column>_sd`, bands, summary entries).
pub(crate) fn output(curves: &[CurvatureCurve], with_sd: bool) -> StudyOutput {
    let lead: Vec<Column> = if with_sd {
        COLUMNS.iter().chain(&SD_COLUMNS).copied().collect()
    } else {
        COLUMNS.to_vec()
    };
    let mut a = Assembly::new(
        &[("study7", &columns(&lead, &STATE_TAIL))],
        &[
            "eps0",
            "R at 0 kPa (mm)",
            "R at the last pressure (mm)",
            "last pressure (kPa)",
            "curl reversed from (kPa)",
        ],
    );
    let mut list = Vec::new();
    for c in curves {
        for r in &c.rows {
            let mut lead = vec![
                c.eps0.into(),
                r.pressure_kpa.into(),
                r.radius.into(),
                r.curvature.into(),
                r.reversed().into(),
                r.end_angle.into(),
                r.tip[0].into(),
                r.tip[1].into(),
            ];
            if with_sd {
                let sd = r.sd.as_ref();
                lead.extend([
                    sd.and_then(|s| s.radius).into(),
                    sd.and_then(|s| s.curvature).into(),
                    sd.map(|s| s.end_angle).into(),
                    sd.map(|s| s.tip[0]).into(),
                    sd.map(|s| s.tip[1]).into(),
                ]);
            }
            let note = match (&r.sd_note, r.radius) {
                (Some(n), _) => n.clone().into(),
                (None, None) => "straight".into(),
                (None, Some(_)) => Cell::Empty,
            };
            a.state(0, lead, &r.warnings, note);
        }
        if let Some(s) = &c.stopped {
            let case = format!("eps0 = {}", c.eps0);
            a.stop(
                0,
                vec![("eps0", c.eps0.into())],
                "pressure_kpa",
                &case,
                StopAt::Kpa,
                s,
                true,
            );
        }
        let reversed_from = c.rows.iter().find(|r| r.reversed()).map(|r| r.pressure_kpa);
        list.push(Curve {
            eps0: c.eps0,
            reversed: reversed_from.is_some(),
            reversed_from_kpa: reversed_from,
            points: c
                .rows
                .iter()
                .map(|r| Point {
                    pressure_kpa: r.pressure_kpa,
                    radius_mm: r.radius,
                    curvature_per_mm: r.curvature,
                    reversed: r.reversed(),
                    radius_mm_sd: with_sd.then(|| r.sd.and_then(|s| s.radius)),
                    curvature_per_mm_sd: with_sd.then(|| r.sd.and_then(|s| s.curvature)),
                })
                .collect(),
            stopped: stop_entry(&c.stopped, StopAt::Kpa),
        });
        let (first, last) = (c.rows.first(), c.rows.last());
        a.overview.push(vec![
            c.eps0.to_string(),
            fmt_opt(first.and_then(|r| r.radius), 1),
            match last {
                Some(r) if r.reversed() => format!("{} (reversed)", fmt_opt(r.radius, 1)),
                Some(r) => fmt_opt(r.radius, 1),
                None => "–".into(),
            },
            fmt_opt(last.map(|r| r.pressure_kpa), 0),
            reversed_from.map_or("not reversed".into(), |p| fmt_opt(Some(p), 0)),
        ]);
    }
    let summary = Summary {
        radius_vs_pressure: list,
    };
    let mut out = a.finish(figure(curves, with_sd), &summary);
    if with_sd {
        out.bands = exact_bands(&SD_COLUMNS);
    }
    out
}

/// Radius and signed curvature against pressure; `with_sd`: each curve's
/// 1-sigma band.
fn figure(curves: &[CurvatureCurve], with_sd: bool) -> Figure {
    let mut p = Panel::new(
        "Radius of curvature (circle fit)",
        PlotAxis::new("pressure P", "kPa"),
        PlotAxis::new("radius R", "mm"),
    );
    p.y.include_zero = true;
    let mut capped = 0;
    for c in curves {
        let key = eps0_key(c.eps0);
        let pick = |rev: bool| {
            pts(c
                .rows
                .iter()
                .filter(|r| r.reversed() == rev)
                .filter_map(|r| r.radius.map(|rad| (r.pressure_kpa, rad)))
                .filter(|q| q.1 <= STUDY7_RADIUS_CAP_MM))
        };
        capped += c
            .rows
            .iter()
            .filter(|r| r.radius.is_some_and(|x| x > STUDY7_RADIUS_CAP_MM))
            .count();
        if with_sd {
            // the band of the curve drawn (not reversed, below the cap),
            // held inside the axis' drawn range
            let (at, sd): (Vec<[f64; 2]>, Vec<f64>) = c
                .rows
                .iter()
                .filter(|r| !r.reversed())
                .filter_map(|r| {
                    let rad = r.radius.filter(|&x| x <= STUDY7_RADIUS_CAP_MM)?;
                    let s = r.sd.and_then(|s| s.radius).unwrap_or(f64::NAN);
                    Some(([r.pressure_kpa, rad], s))
                })
                .unzip();
            p.series.extend(
                Series::spread(key.clone(), &at, &sd, [0.0, STUDY7_RADIUS_CAP_MM])
                    .map(|s| s.label(BAND_LABEL)),
            );
        }
        p.series.push(
            Series::new(key.clone(), SeriesKind::LinePoints, pick(false))
                .label(format!("ε0 = {}", c.eps0)),
        );
        let rev = pick(true);
        if !rev.is_empty() {
            p.series.push(
                Series::new(key, SeriesKind::Cross, rev)
                    .label(format!("ε0 = {}: reversed curl", c.eps0)),
            );
        }
        if let Some(s) = &c.stopped {
            p.notes
                .push(format!("ε0 = {}: stopped at {:.0} kPa", c.eps0, s.at));
        }
    }
    if capped > 0 {
        p.notes.push(format!(
            "{capped} points with R > {STUDY7_RADIUS_CAP_MM} mm (nearly flat) not drawn"
        ));
    }
    let mut k = Panel::new(
        "Signed curvature (> 0: curls to the prestressed side)",
        PlotAxis::new("pressure P", "kPa"),
        PlotAxis::new("curvature 1/R", "1/mm"),
    );
    for c in curves.iter().filter(|_| with_sd) {
        let (at, sd): (Vec<[f64; 2]>, Vec<f64>) = c
            .rows
            .iter()
            .map(|r| {
                let s = r.sd.and_then(|s| s.curvature).unwrap_or(f64::NAN);
                ([r.pressure_kpa, r.curvature], s)
            })
            .unzip();
        k.series.extend(
            Series::spread(eps0_key(c.eps0), &at, &sd, [f64::MIN, f64::MAX])
                .map(|s| s.label(BAND_LABEL)),
        );
    }
    for c in curves {
        k.series.push(
            Series::new(
                eps0_key(c.eps0),
                SeriesKind::LinePoints,
                pts(c.rows.iter().map(|r| (r.pressure_kpa, r.curvature))),
            )
            .label(format!("ε0 = {}", c.eps0)),
        );
    }
    k.hlines.push(RefLine {
        at: 0.0,
        label: "flat".into(),
    });
    Figure::row(
        "Study 7: curvature against pressure (unloaded fingers)",
        [1200, 580],
        vec![p, k],
    )
}

//! Study 7 (Sec. 6.2): radius of curvature against pressure.

use serde::Serialize;

use super::info::StudyInfo;
use super::options::{StudyOptions, SweepStop};
use super::output::*;
use crate::actuator::Actuator;
use crate::circle_fit::fit_circle;
use crate::coefficients::Coefficients;
use crate::error::Warning;
use crate::finger::{Load, Solution, SolveOptions, Solver};
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
    opts.validate()?;
    let sopts = SolveOptions {
        stability: false,
        ..SolveOptions::default()
    };
    let mut out = Vec::new();
    for eps0 in [0.15, 0.25, 0.4] {
        let finger = opts.finger(actuator, eps0)?;
        let mut solver = Solver::new(&finger);
        let mut rows = Vec::new();
        let mut stopped = None;
        let mut guess: Option<Coefficients> = None;
        for i in 0..opts.pressure_points {
            let p = 400.0 * i as f64 / (opts.pressure_points - 1) as f64;
            let load = Load::unloaded().with_pressure_kpa(p);
            match solver.solve(&load, guess.as_ref(), &sopts) {
                Ok(sol) => {
                    rows.push(curvature_row(p, &sol));
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
    }
}

// ------------------------------------------------------------ outputs

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 7,
    key: "curvature",
    title: "Curvature against pressure",
    description: "Unloaded fingers, eps0 in {0.15, 0.25, 0.4}, pressure 0 to 400 kPa: radius of curvature by circle fit; past flat the curl reverses (Sec. 6.2).",
    run: |act, opts| Ok(output(&study7_curvature(act, opts)?)),
    empty: || output(&[]),
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

#[derive(Serialize)]
struct Point {
    pressure_kpa: f64,
    radius_mm: Option<f64>,
    curvature_per_mm: f64,
    reversed: bool,
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

/// The outputs of study 7 from its curves.
pub(crate) fn output(curves: &[CurvatureCurve]) -> StudyOutput {
    let mut a = Assembly::new(
        &[("study7", &columns(&COLUMNS, &STATE_TAIL))],
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
            let lead = vec![
                c.eps0.into(),
                r.pressure_kpa.into(),
                r.radius.into(),
                r.curvature.into(),
                r.reversed().into(),
                r.end_angle.into(),
                r.tip[0].into(),
                r.tip[1].into(),
            ];
            let note = if r.radius.is_none() {
                "straight".into()
            } else {
                Cell::Empty
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
    a.finish(figure(curves), &summary)
}

/// Radius and signed curvature against pressure.
fn figure(curves: &[CurvatureCurve]) -> Figure {
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

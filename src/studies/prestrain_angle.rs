//! Study 1 (Sec. 4.1): prestrain x mounting angle.

use serde::Serialize;

use super::bands::BandParams;
use super::info::StudyInfo;
use super::lift::{
    add_lift_curve, lift_bands, lift_columns, lift_curve_with, lift_rows, CurveSummary, LiftCurve,
};
use super::options::{StudyOptions, PAPER_ANGLES, PAPER_EPS0};
use super::output::*;
use crate::actuator::Actuator;
use crate::sensitivity::Covariance;
use crate::solve_error::SolveError;

/// Study 1 (Sec. 4.1): prestrain x mounting angle, overlap 0, grasping
/// angle 0, `f = mu F`: one curve per (eps0 in [`PAPER_EPS0`], a in
/// [`PAPER_ANGLES`]), eps0-major.
pub fn study1_prestrain_angle(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<Vec<LiftCurve>, SolveError> {
    study1_prestrain_angle_with(actuator, opts, None)
}

/// [`study1_prestrain_angle`], and with a covariance of the actuator's
/// parameters the 1-sigma of every curve's d_max and of every grasp's
/// outputs at its size ([`LiftCurve::d_max_sd`], `LiftPoint::sd`), by
/// first-order propagation through exact sensitivities. The prestrain of
/// each curve is the study's own: its variance is not propagated
/// (`crate::studies::not_propagated`). Curves whose rest shape curls past
/// its tip (eps0 = 0.4) have none, and say why.
pub fn study1_prestrain_angle_with(
    actuator: &Actuator,
    opts: &StudyOptions,
    covariance: Option<&Covariance>,
) -> Result<Vec<LiftCurve>, SolveError> {
    opts.validate()?;
    let bands = covariance.map(BandParams::new);
    let mut curves = Vec::new();
    for eps0 in PAPER_EPS0 {
        let act = actuator.with_eps0(eps0)?;
        for a in PAPER_ANGLES {
            curves.push((eps0, act.clone(), opts.gripper(actuator, eps0, a, 0.0)?));
        }
    }
    // the nine curves are independent: on every core, in order
    Ok(crate::cancel::par_map(&curves, |(eps0, act, g)| {
        let b = bands.as_ref().map(|b| (act, b));
        lift_curve_with(g, *eps0, opts.sweep_points, b)
    }))
}

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 1,
    key: "prestrain_angle",
    title: "Prestrain × mounting angle",
    description: "eps0 in {0.4, 0.25, 0.15} × a in {π/2, π/2.5, π/3}, no overlap (l = 2 l0), grasping angle b = 0, full friction f = μF: unloaded finger shapes in the gripper frame, the max lifting force f_v against the grasping size d, and d_max = l + 2 Lx cos a against a (Sec. 4.1).",
    run: |act, opts, cov| {
        Ok(output(
            &study1_prestrain_angle_with(act, opts, cov)?,
            cov.is_some(),
        ))
    },
    has_bands: true,
    empty: || output(&[], false),
};

const LEAD: [Column; 2] = [Column::new("eps0", ""), Column::new("angle_rad", "rad")];
const SHAPE_COLUMNS: [Column; 6] = [
    LEAD[0],
    LEAD[1],
    Column::new("xg_mm", "mm"),
    Column::new("zg_mm", "mm"),
    STATUS,
    NOTE,
];

/// One entry of `dmax_mm`.
#[derive(Serialize)]
struct DmaxRow {
    eps0: f64,
    angle_rad: f64,
    #[serde(flatten)]
    curve: CurveSummary,
}

#[derive(Serialize)]
struct Summary {
    dmax_mm: Vec<DmaxRow>,
}

/// The outputs of study 1 from its curves; `with_sd`: their 1-sigma too.
pub(crate) fn output(curves: &[LiftCurve], with_sd: bool) -> StudyOutput {
    let mut a = Assembly::new(
        &[
            ("study1", &lift_columns(LEAD, with_sd)),
            ("study1_shapes", &SHAPE_COLUMNS),
        ],
        &[
            "eps0",
            "a",
            "l0 (mm)",
            "l (mm)",
            "d_max (mm)",
            "swept to d (mm)",
            "max f_v (N)",
        ],
    );
    for c in curves {
        let (eps0, angle) = (c.eps0.into(), c.mounting_angle.into());
        let case = format!("eps0 = {}, a = {}", c.eps0, angle_name(c.mounting_angle));
        lift_rows(&mut a, c, [eps0, angle], &case, with_sd);
        for q in &c.rest_shape {
            a.row(
                1,
                vec![
                    c.eps0.into(),
                    c.mounting_angle.into(),
                    q[0].into(),
                    q[1].into(),
                ],
            );
        }
        a.overview.push(vec![
            c.eps0.to_string(),
            angle_name(c.mounting_angle),
            fmt(c.l0, 1),
            fmt(c.palm, 1),
            fmt(c.d_max, 1),
            fmt(c.reached(), 1),
            fmt_opt(c.peak_lift(), 3),
        ]);
    }
    let summary = Summary {
        dmax_mm: curves
            .iter()
            .map(|c| DmaxRow {
                eps0: c.eps0,
                angle_rad: c.mounting_angle,
                curve: CurveSummary::of(c, with_sd),
            })
            .collect(),
    };
    let mut out = a.finish(figure(curves, with_sd), &summary);
    if with_sd {
        out.bands = lift_bands();
    }
    out
}

/// Finger shapes per mounting angle, max f_v against d per prestrain,
/// d_max against a.
fn figure(curves: &[LiftCurve], with_sd: bool) -> Figure {
    let mut top = Vec::new();
    for a in PAPER_ANGLES {
        let mut p = Panel::new(
            format!("Unloaded fingers, a = {}", angle_name(a)),
            PlotAxis::new("Xg", "mm"),
            PlotAxis::new("−Zg, the gripper points down", "mm"),
        );
        p.equal_aspect = true;
        p.legend = Corner::LowerRight;
        for c in curves.iter().filter(|c| c.mounting_angle == a) {
            let key = eps0_key(c.eps0);
            let shape: Vec<[f64; 2]> = c.rest_shape.iter().map(|q| [q[0], -q[1]]).collect();
            let mirror = shape.iter().map(|q| [-q[0], q[1]]).collect();
            p.series.push(
                Series::new(key.clone(), SeriesKind::Line, shape).label(format!("ε0 = {}", c.eps0)),
            );
            p.series
                .push(Series::new(key.clone(), SeriesKind::Dashed, mirror));
            p.series.push(Series::new(
                key,
                SeriesKind::Points,
                vec![[0.5 * c.palm, 0.0], [-0.5 * c.palm, 0.0]],
            ));
        }
        // what the dashes and dots are: entries without data, in a
        // neutral colour
        p.series.push(
            Series::new(NEUTRAL, SeriesKind::Dashed, Vec::new())
                .label("opposite finger (mirror image)"),
        );
        p.series.push(
            Series::new(NEUTRAL, SeriesKind::Points, Vec::new()).label("finger mount (palm end)"),
        );
        p.hlines.push(RefLine {
            at: 0.0,
            label: String::new(),
        });
        top.push(p);
    }
    let mut bottom = Vec::new();
    for eps0 in PAPER_EPS0 {
        let mut p = Panel::new(
            format!("Max lifting force, ε0 = {eps0}"),
            PlotAxis::new("grasping size d", "mm"),
            PlotAxis::new("max f_v", "N"),
        );
        p.y.include_zero = true;
        // a curve that shoots up at its last points must not squash the others
        p.y_clip = Some(Clip::OUTLIERS);
        p.legend = Corner::UpperLeft;
        for c in curves.iter().filter(|c| c.eps0 == eps0) {
            let name = angle_name(c.mounting_angle);
            add_lift_curve(
                &mut p,
                c,
                SeriesKind::Line,
                angle_key(c.mounting_angle),
                format!("a = {name}"),
                with_sd,
            );
            if let Some(s) = &c.stopped {
                p.notes
                    .push(format!("a = {name}: stopped at d = {:.1} mm", s.at));
            }
        }
        bottom.push(p);
    }
    let mut p = Panel::new(
        "Largest grasping size",
        PlotAxis::new("mounting angle a", "deg"),
        PlotAxis::new("d_max", "mm"),
    );
    for eps0 in PAPER_EPS0 {
        let points = pts(curves
            .iter()
            .filter(|c| c.eps0 == eps0)
            .map(|c| (c.mounting_angle.to_degrees(), c.d_max)));
        p.series.push(
            Series::new(eps0_key(eps0), SeriesKind::LinePoints, points)
                .label(format!("ε0 = {eps0}")),
        );
    }
    bottom.push(p);
    Figure {
        title: "Study 1: prestrain × mounting angle (g = 0, b = 0, f = μF)".into(),
        size: [1600, 1000],
        rows: vec![top, bottom],
    }
}

//! Study 2 (Sec. 4.2): the overlap of the fingers at rest.

use serde::Serialize;

use super::bands::BandParams;
use super::info::StudyInfo;
use super::lift::{
    add_lift_curve, lift_bands, lift_columns, lift_curve_with, lift_rows, CurveSummary, LiftCurve,
};
use super::options::{StudyOptions, PAPER_ANGLES, PAPER_OVERLAPS};
use super::output::*;
use crate::actuator::Actuator;
use crate::sensitivity::Covariance;
use crate::solve_error::SolveError;

/// Study 2 (Sec. 4.2): overlap, eps0 = 0.25: one curve per (a in
/// [`PAPER_ANGLES`], g in [`PAPER_OVERLAPS`]), angle-major. Each curve's
/// `d_max` is `2 (l0 - g + Lx cos a)`.
pub fn study2_overlap(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<Vec<LiftCurve>, SolveError> {
    study2_overlap_with(actuator, opts, None)
}

/// [`study2_overlap`], and with a covariance of the actuator's parameters
/// the 1-sigma of every curve's d_max and of every grasp's outputs at its
/// size, by first-order propagation through exact sensitivities (the
/// prestrain, 0.25, is the study's own: not propagated).
pub fn study2_overlap_with(
    actuator: &Actuator,
    opts: &StudyOptions,
    covariance: Option<&Covariance>,
) -> Result<Vec<LiftCurve>, SolveError> {
    opts.validate()?;
    let bands = covariance.map(BandParams::new);
    let act = actuator.with_eps0(0.25)?;
    let mut grippers = Vec::new();
    for a in PAPER_ANGLES {
        for g in PAPER_OVERLAPS {
            grippers.push(opts.gripper(actuator, 0.25, a, g)?);
        }
    }
    // the nine curves are independent: on every core, in order
    Ok(crate::cancel::par_map(&grippers, |gr| {
        let b = bands.as_ref().map(|b| (&act, b));
        lift_curve_with(gr, 0.25, opts.sweep_points, b)
    }))
}

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 2,
    key: "overlap",
    title: "Overlap",
    description: "eps0 = 0.25, a in {π/2, π/2.5, π/3}, overlap g in {0, 10, 20} mm: max f_v against d per overlap, and d_max = 2 (l0 − g + Lx cos a) against g (Sec. 4.2).",
    run: |act, opts, cov| Ok(output(&study2_overlap_with(act, opts, cov)?, cov.is_some())),
    has_bands: true,
    empty: || output(&[], false),
};

const LEAD: [Column; 2] = [Column::new("angle_rad", "rad"), Column::new("g_mm", "mm")];

/// One entry of `overlap_dmax_mm`.
#[derive(Serialize)]
struct OverlapRow {
    angle_rad: f64,
    g_mm: f64,
    #[serde(flatten)]
    curve: CurveSummary,
}

#[derive(Serialize)]
struct Summary {
    overlap_dmax_mm: Vec<OverlapRow>,
}

/// The outputs of study 2 from its curves; `with_sd`: their 1-sigma too.
pub(crate) fn output(curves: &[LiftCurve], with_sd: bool) -> StudyOutput {
    let mut a = Assembly::new(
        &[("study2", &lift_columns(LEAD, with_sd))],
        &[
            "a",
            "g (mm)",
            "l (mm)",
            "d_max (mm)",
            "swept to d (mm)",
            "max f_v (N)",
        ],
    );
    for c in curves {
        let case = format!("a = {}, g = {} mm", angle_name(c.mounting_angle), c.overlap);
        lift_rows(
            &mut a,
            c,
            [c.mounting_angle.into(), c.overlap.into()],
            &case,
            with_sd,
        );
        a.overview.push(vec![
            angle_name(c.mounting_angle),
            fmt(c.overlap, 0),
            fmt(c.palm, 1),
            fmt(c.d_max, 1),
            fmt(c.reached(), 1),
            fmt_opt(c.peak_lift(), 3),
        ]);
    }
    let summary = Summary {
        overlap_dmax_mm: curves
            .iter()
            .map(|c| OverlapRow {
                angle_rad: c.mounting_angle,
                g_mm: c.overlap,
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

/// f_v against d per overlap (one panel per mounting angle), d_max against g.
fn figure(curves: &[LiftCurve], with_sd: bool) -> Figure {
    let mut panels = Vec::new();
    for a in PAPER_ANGLES {
        let mut p = Panel::new(
            format!("Max lifting force, a = {}", angle_name(a)),
            PlotAxis::new("grasping size d", "mm"),
            PlotAxis::new("max f_v", "N"),
        );
        p.y.include_zero = true;
        p.legend = Corner::UpperLeft;
        for c in curves.iter().filter(|c| c.mounting_angle == a) {
            add_lift_curve(
                &mut p,
                c,
                SeriesKind::Line,
                overlap_key(c.overlap),
                format!("g = {} mm", c.overlap),
                with_sd,
            );
            if let Some(s) = &c.stopped {
                p.notes.push(format!(
                    "g = {} mm: sweep stopped at d = {:.1} mm",
                    c.overlap, s.at
                ));
            }
        }
        panels.push(p);
    }
    let mut p = Panel::new(
        "Largest grasping size",
        PlotAxis::new("overlap g", "mm"),
        PlotAxis::new("d_max", "mm"),
    );
    for a in PAPER_ANGLES {
        let points = pts(curves
            .iter()
            .filter(|c| c.mounting_angle == a)
            .map(|c| (c.overlap, c.d_max)));
        p.series.push(
            Series::new(angle_key(a), SeriesKind::LinePoints, points)
                .label(format!("a = {}", angle_name(a))),
        );
    }
    panels.push(p);
    let second = panels.split_off(2);
    Figure {
        title: "Study 2: overlap g (ε0 = 0.25, b = 0, f = μF)".into(),
        size: [1200, 900],
        rows: vec![panels, second],
    }
}

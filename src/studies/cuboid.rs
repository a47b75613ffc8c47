//! Study 3 (Sec. 5.1.1): the cuboid grasping region of the Sec. 5 gripper.

use serde::Serialize;

use super::bands::{exact_bands, BandParams};
use super::info::StudyInfo;
use super::lift::{add_lift_curve, lift_curve_with, sd_note, LiftCurve};
use super::options::{section5_gripper, StudyOptions, SECTION5_EPS0};
use super::output::*;
use crate::actuator::Actuator;
use crate::sensitivity::Covariance;
use crate::solve_error::SolveError;

/// Study 3 result: the cuboid grasping region, under the max lifting force
/// versus grasping size curve.
#[derive(Debug, Clone, PartialEq)]
pub struct CuboidRegion {
    /// The boundary curve.
    pub curve: LiftCurve,
}

impl CuboidRegion {
    /// True when a cuboid of size `d` (mm) needing lifting force `lift`
    /// (N per finger) lies in the region: `d` within the swept sizes and
    /// `0 <= lift <= max f_v(d)`.
    pub fn contains(&self, d: f64, lift: f64) -> bool {
        d > 0.0 && lift >= 0.0 && self.curve.max_lift(d).is_some_and(|m| lift <= m)
    }
}

/// Study 3 (Sec. 5.1.1): the cuboid grasping region of the Sec. 5 gripper
/// (grasping angle 0).
pub fn study3_cuboid_region(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<CuboidRegion, SolveError> {
    study3_cuboid_region_with(actuator, opts, None)
}

/// [`study3_cuboid_region`], and with a covariance of the actuator's
/// parameters the boundary's 1-sigma (d_max's and every point's, as study
/// 2's curves have them: the region's edge is study 2's curve at
/// a = pi/3, g = 20 mm). The prestrain is the study's own (0.25).
pub fn study3_cuboid_region_with(
    actuator: &Actuator,
    opts: &StudyOptions,
    covariance: Option<&Covariance>,
) -> Result<CuboidRegion, SolveError> {
    let g = section5_gripper(actuator, opts)?;
    let bands = covariance.map(BandParams::new);
    let act = actuator.with_eps0(SECTION5_EPS0)?;
    let b = bands.as_ref().map(|b| (&act, b));
    Ok(CuboidRegion {
        curve: lift_curve_with(&g, SECTION5_EPS0, opts.sweep_points, b),
    })
}

/// The cuboid tested against the study-3 region: d (mm), f_v (N per finger).
pub const CUBOID_TEST: (f64, f64) = (100.0, 0.3);

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 3,
    key: "cuboid_region",
    title: "Cuboid grasping region",
    description: "The Sec. 5 gripper (eps0 = 0.25, a = π/3, g = 20 mm), b = 0: cuboids of size d needing lifting force f_v per finger can be held when the point lies under the max f_v curve (Sec. 5.1.1).",
    run: |act, opts, cov| {
        Ok(output(
            Some(&study3_cuboid_region_with(act, opts, cov)?),
            cov.is_some(),
        ))
    },
    has_bands: true,
    empty: || output(None, false),
};

const COLUMNS: [Column; 5] = [
    Column::new("d_mm", "mm"),
    Column::new("tip_gap_mm", "mm"),
    Column::new("F_n", "N"),
    Column::new("fv_max_n", "N"),
    Column::new("h_mm", "mm"),
];

/// The 1-sigma columns, with a covariance (`bands`).
const SD_COLUMNS: [Column; 3] = [
    Column::new("F_n_sd", "N"),
    Column::new("fv_max_n_sd", "N"),
    Column::new("h_mm_sd", "mm"),
];

#[derive(Serialize)]
struct RegionSummary {
    test_d_mm: f64,
    test_fv_n: f64,
    max_fv_at_test_d_n: Option<f64>,
    d_min_mm: Option<f64>,
    reached_mm: f64,
    dmax_mm: f64,
    /// With a covariance: d_max's 1-sigma (null where there is none).
    #[serde(skip_serializing_if = "Option::is_none")]
    dmax_mm_sd: Option<Option<f64>>,
    palm_mm: f64,
    l0_mm: f64,
    stopped: Option<StopEntry>,
}

#[derive(Serialize)]
struct Summary {
    cuboid_region_contains: Option<bool>,
    cuboid_region: Option<RegionSummary>,
}

/// The outputs of study 3 (`None`: the empty outputs); `with_sd`: the
/// boundary's 1-sigma too (columns `<column>_sd`, a band, d_max's sd).
pub(crate) fn output(region: Option<&CuboidRegion>, with_sd: bool) -> StudyOutput {
    let lead: Vec<Column> = if with_sd {
        COLUMNS.iter().chain(&SD_COLUMNS).copied().collect()
    } else {
        COLUMNS.to_vec()
    };
    let mut a = Assembly::new(
        &[("study3", &columns(&lead, &GRASP_TAIL))],
        &["quantity", "value"],
    );
    let Some(region) = region else {
        let summary = Summary {
            cuboid_region_contains: None,
            cuboid_region: None,
        };
        return a.empty(&summary);
    };
    let c = &region.curve;
    for p in &c.points {
        let mut row = [p.size, p.tip_gap, p.normal, p.lift, p.height]
            .map(Cell::from)
            .to_vec();
        if with_sd {
            row.extend([
                p.sd.map(|s| s.normal).into(),
                p.sd.map(|s| s.lift).into(),
                p.sd.map(|s| s.height).into(),
            ]);
        }
        a.grasp(0, row, p.reversed, p.invalid.as_ref(), &p.warnings);
        if with_sd {
            sd_note(&mut a, p);
        }
    }
    if let Some(s) = &c.stopped {
        a.stop(0, vec![], "d_mm", "cuboid region", StopAt::Mm, s, true);
    }
    let (d, fv) = CUBOID_TEST;
    let contains = region.contains(d, fv);
    let at_test = c.max_lift(d);
    let d_min = c.points.first().map(|p| p.size);
    let summary = Summary {
        cuboid_region_contains: Some(contains),
        cuboid_region: Some(RegionSummary {
            test_d_mm: d,
            test_fv_n: fv,
            max_fv_at_test_d_n: at_test,
            d_min_mm: d_min,
            reached_mm: c.reached(),
            dmax_mm: c.d_max,
            dmax_mm_sd: with_sd.then_some(c.d_max_sd),
            palm_mm: c.palm,
            l0_mm: c.l0,
            stopped: stop_entry(&c.stopped, StopAt::Mm),
        }),
    };
    a.overview.push(vec![
        format!("cuboid d = {d} mm, f_v = {fv} N inside the region"),
        if contains { "yes" } else { "no" }.into(),
    ]);
    a.overview.push(vec![
        format!("max f_v at d = {d} mm (N)"),
        fmt_opt(at_test, 3),
    ]);
    a.overview.push(vec![
        "grasping sizes swept (mm)".into(),
        format!("{} to {}", fmt_opt(d_min, 1), fmt(c.reached(), 1)),
    ]);
    a.overview.push(vec!["d_max (mm)".into(), fmt(c.d_max, 1)]);
    a.overview.push(vec![
        "palm l / reach l0 (mm)".into(),
        format!("{} / {}", fmt(c.palm, 1), fmt(c.l0, 1)),
    ]);
    a.strict_dropped = c.dropped;
    a.design(&c.warnings);
    let mut out = a.finish(figure(region, with_sd), &summary);
    if with_sd {
        out.bands = exact_bands(&SD_COLUMNS);
    }
    out
}

/// The region under the curve and the test cuboid; `with_sd`: the
/// boundary's 1-sigma band.
fn figure(region: &CuboidRegion, with_sd: bool) -> Figure {
    let c = &region.curve;
    let (d, fv) = CUBOID_TEST;
    let mut p = Panel::new(
        "Region under the max lifting force curve",
        PlotAxis::new("grasping size d", "mm"),
        PlotAxis::new("lifting force f_v per finger", "N"),
    );
    p.y.include_zero = true;
    let (kind, label) = (SeriesKind::Area, "grasping region");
    add_lift_curve(&mut p, c, kind, "region".into(), label.into(), with_sd);
    let inside = region.contains(d, fv);
    p.series.push(
        Series::new("cuboid", SeriesKind::Cross, vec![[d, fv]]).label(format!(
            "cuboid d = {d} mm, f_v = {fv} N ({})",
            if inside { "inside" } else { "outside" }
        )),
    );
    p.vlines.push(RefLine {
        at: c.d_max,
        label: format!("d_max = {:.1} mm", c.d_max),
    });
    p.notes.push(format!(
        "palm l = {:.1} mm, reach l0 = {:.1} mm",
        c.palm, c.l0
    ));
    if let Some(s) = &c.stopped {
        p.notes.push(format!("sweep stopped at d = {:.1} mm", s.at));
    }
    Figure::row(
        "Study 3: cuboid grasping region (ε0 = 0.25, a = π/3, g = 20 mm, b = 0)",
        [1000, 620],
        vec![p],
    )
}

//! Study 6 (Sec. 5.2.2): the grasping angles that hold a sphere.

use serde::Serialize;

use super::bands::{exact_bands, BandParams, BAND_LABEL};
use super::info::StudyInfo;
use super::options::{section5_gripper, StudyOptions, SECTION5_EPS0};
use super::output::*;
use crate::actuator::Actuator;
use crate::gripper::{grasping_angle_range, AngleSample, Grasp, Gripper, Invalid, ViableAngles};
use crate::sensitivity::{Covariance, GraspKind, GraspSensitivity, GripperParam, Param};
use crate::solve_error::SolveError;

/// The sphere of study 6: radius (mm) and lifting force per finger (N).
const SPHERE: (f64, f64) = (50.0, 0.5);

/// Study 6 (Sec. 5.2.2): the grasping angles that hold a sphere of
/// r = 50 mm with f_v = 0.5 N per finger (Sec. 5 gripper).
pub fn study6_viable_angles(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<ViableAngles, SolveError> {
    let g = section5_gripper(actuator, opts)?;
    g.viable_angle_range(0.0, SPHERE.0, SPHERE.1, opts.angle_samples)
}

/// 1-sigma of study 6 from a covariance ([`study6_viable_angles_with`]).
#[derive(Debug, Clone, PartialEq)]
pub struct ViableSd {
    /// One entry per scanned angle: the 1-sigma of its grasp's normal
    /// force, friction and f/F, or why it has none (the angle did not
    /// solve, or its sensitivities failed).
    pub scan: Vec<Result<AngleSd, String>>,
    /// One pair per viable interval: the 1-sigma (rad) of its two ends,
    /// or why an end has none. An end where the grasp reaches the
    /// friction cone (`f = mu F`) or lets go of friction (`f = 0`) moves
    /// as `db/dp = -(dm/dp) / (dm/db)`, `m` that margin; an end at the
    /// scan's own limit `-arctan mu` does not move (0); an end held by
    /// another validity finding has none.
    pub intervals: Vec<[Result<f64, String>; 2]>,
}

/// 1-sigma of a grasp of the study-6 scan, at its grasping angle held
/// fixed, by first-order propagation through its exact sensitivities
/// ([`Gripper::grasp_sensitivities`], a sphere at a given lift).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AngleSd {
    /// Of the normal force F (N).
    pub normal: f64,
    /// Of the friction f (N).
    pub friction: f64,
    /// Of the friction needed, f/F (`None` where F = 0).
    pub ratio: Option<f64>,
}

/// [`study6_viable_angles`], and with a covariance of the actuator's
/// parameters the 1-sigma of each scanned grasp and of the viable
/// intervals' ends ([`ViableSd`]) by first-order propagation through the
/// grasps' exact sensitivities. The gripper's prestrain (0.25) is the
/// study's own: its variance is not propagated
/// (`crate::studies::not_propagated`).
pub fn study6_viable_angles_with(
    actuator: &Actuator,
    opts: &StudyOptions,
    covariance: Option<&Covariance>,
) -> Result<(ViableAngles, Option<ViableSd>), SolveError> {
    let g = section5_gripper(actuator, opts)?;
    let v = g.viable_angle_range(0.0, SPHERE.0, SPHERE.1, opts.angle_samples)?;
    let Some(b) = covariance.map(BandParams::new) else {
        return Ok((v, None));
    };
    let act = actuator.with_eps0(SECTION5_EPS0)?;
    let (r, lift) = (v.radius, v.lift);
    let kind = GraspKind::Sphere { radius: r, lift };
    let why = |e: SolveError| format!("no error bars: {e}");
    // each scanned angle's grasp re-solved (the scan keeps its forces
    // only), warm-started along the scan as the scan itself is
    let mut grasps: Vec<Option<Grasp>> = Vec::with_capacity(v.scan.len());
    let mut scan = Vec::with_capacity(v.scan.len());
    let mut warm: Option<Grasp> = None;
    for s in &v.scan {
        if let Some(f) = &s.failure {
            scan.push(Err(format!("no error bars: the angle did not solve ({f})")));
            grasps.push(None);
            continue;
        }
        let solved = g
            .sphere_grasp(0.0, r, lift, s.beta, warm.as_ref())
            .map_err(why)
            .and_then(|sg| {
                let close = |a: f64, b: f64| (a - b).abs() <= 1e-6 * (a.abs().max(b.abs()) + 1e-9);
                if close(sg.grasp.normal, s.normal) && close(sg.grasp.friction, s.friction) {
                    Ok(sg.grasp)
                } else {
                    Err(format!(
                        "no error bars: the grasp re-solved at b = {:.6} rad holds F = {:.9} N, not the scan's {:.9} N",
                        s.beta, sg.grasp.normal, s.normal
                    ))
                }
            });
        match solved {
            Ok(gr) => {
                scan.push(
                    derivatives(&g, &act, &gr, kind, &b, false)
                        .map(|(d, _)| angle_sd(&gr, &d, &b))
                        .map_err(why),
                );
                warm = Some(gr.clone());
                grasps.push(Some(gr));
            }
            Err(e) => {
                scan.push(Err(e));
                grasps.push(None);
            }
        }
    }
    // the ends: each solved at its angle, warm from the nearest scanned grasp
    let lo = grasping_angle_range(g.mu())[0];
    let end = |beta: f64| -> Result<f64, String> {
        if beta == lo {
            return Ok(0.0);
        }
        let near = v
            .scan
            .iter()
            .zip(&grasps)
            .filter_map(|(s, gr)| gr.as_ref().map(|gr| ((s.beta - beta).abs(), gr)))
            .min_by(|a, b| a.0.total_cmp(&b.0))
            .map(|(_, gr)| gr);
        let gr = g.sphere_grasp(0.0, r, lift, beta, near).map_err(why)?.grasp;
        let (rows, beta_row) = derivatives(&g, &act, &gr, kind, &b, true).map_err(why)?;
        let Some(fb) = beta_row else {
            return Err("no error bars: no derivative in the grasping angle".into());
        };
        let mu = g.mu();
        // the margins that can end a viable interval, and how far in b
        // each is from its zero
        let margins: [(f64, f64, Margin); 2] = [
            (
                mu * gr.normal - gr.friction,
                mu * fb.normal - fb.friction,
                |d, mu| mu * d.normal - d.friction,
            ),
            (gr.friction, fb.friction, |d, _| d.friction),
        ];
        let (m, mb, dm) = margins
            .iter()
            .copied()
            .min_by(|a, b| (a.0 / a.1).abs().total_cmp(&(b.0 / b.1).abs()))
            .unwrap_or(margins[0]);
        if !(mb != 0.0 && mb.is_finite() && (m / mb).abs() <= ENDS_AT_MARGIN_RAD) {
            return Err(format!(
                "no error bars: the end at b = {beta:.6} rad is held by a validity finding other than the friction cone or f = 0"
            ));
        }
        let d: Vec<f64> = rows
            .iter()
            .map(|r| r.as_ref().map_or(0.0, |r| -dm(r, mu) / mb))
            .collect();
        Ok(b.sigma(&d))
    };
    let intervals = v
        .intervals
        .iter()
        .map(|iv| [end(iv[0]), end(iv[1])])
        .collect();
    Ok((v, Some(ViableSd { scan, intervals })))
}

/// A margin's derivative along a parameter from the grasp's row there,
/// at friction coefficient `mu`.
type Margin = fn(&GraspSensitivity, f64) -> f64;

/// How close (rad) an interval's end must be to a margin's zero for that
/// margin to hold it: the ends are bisected to
/// `VIABLE_BETA_TOL` (1e-9 rad, src/gripper/sphere.rs).
const ENDS_AT_MARGIN_RAD: f64 = 1e-6;

/// A grasp's sensitivities along each propagated parameter (`None` where
/// the parameter is not the actuator's: it counts 0), in
/// [`BandParams::params`]' order, and with `beta` the one along the
/// grasping angle.
#[allow(clippy::type_complexity)]
fn derivatives(
    g: &Gripper,
    act: &Actuator,
    grasp: &Grasp,
    kind: GraspKind,
    b: &BandParams,
    beta: bool,
) -> Result<(Vec<Option<GraspSensitivity>>, Option<GraspSensitivity>), SolveError> {
    let propagated = b.params();
    let mut params: Vec<GripperParam> = propagated
        .iter()
        .filter_map(|p| match p {
            Param::Actuator(a) => Some(GripperParam::Actuator(*a)),
            _ => None,
        })
        .collect();
    if beta {
        params.push(GripperParam::Beta);
    }
    let rows = g.grasp_sensitivities(act, grasp, kind, &params)?.rows;
    let along = propagated
        .iter()
        .map(|p| match p {
            Param::Actuator(a) => rows
                .iter()
                .find(|r| r.param == GripperParam::Actuator(*a))
                .cloned(),
            _ => None,
        })
        .collect();
    let fb = rows.iter().find(|r| r.param == GripperParam::Beta).cloned();
    Ok((along, fb))
}

/// The 1-sigma of a scanned grasp's F, f and f/F.
fn angle_sd(gr: &Grasp, d: &[Option<GraspSensitivity>], b: &BandParams) -> AngleSd {
    let s = |f: &dyn Fn(&GraspSensitivity) -> f64| {
        b.sigma(
            &d.iter()
                .map(|r| r.as_ref().map_or(0.0, f))
                .collect::<Vec<_>>(),
        )
    };
    let (fn_, ff) = (gr.normal, gr.friction);
    AngleSd {
        normal: s(&|r| r.normal),
        friction: s(&|r| r.friction),
        ratio: (fn_ != 0.0).then(|| s(&|r| (r.friction * fn_ - ff * r.normal) / (fn_ * fn_))),
    }
}

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 6,
    key: "viable_angles",
    title: "Viable grasping angles",
    description: "A sphere r = 50 mm needing f_v = 0.5 N per finger: the grasping angles b at which some F with 0 ≤ f ≤ μF holds it validly (Sec. 5.2.2).",
    run,
    has_bands: true,
    empty: || output(None, StudyOptions::default().mu, None),
};

fn run(
    act: &Actuator,
    opts: &StudyOptions,
    cov: Option<&Covariance>,
) -> Result<StudyOutput, SolveError> {
    let (v, sd) = study6_viable_angles_with(act, opts, cov)?;
    Ok(output(Some(&v), opts.mu, sd.as_ref()))
}

const COLUMNS: [Column; 5] = [
    Column::new("beta_rad", "rad"),
    Column::new("F_n", "N"),
    Column::new("f_n", "N"),
    Column::new("f_over_F", ""),
    Column::new("viable", ""),
];

/// The 1-sigma columns, with a covariance (`bands`).
const SD_COLUMNS: [Column; 3] = [
    Column::new("F_n_sd", "N"),
    Column::new("f_n_sd", "N"),
    Column::new("f_over_F_sd", ""),
];

#[derive(Serialize)]
struct ViableSummary {
    r_mm: f64,
    fv_n: f64,
    intervals_rad: Vec<[f64; 2]>,
    samples: usize,
    viable_samples: usize,
    failed_samples: usize,
    /// With a covariance: the 1-sigma (rad) of each interval's ends
    /// (null where none).
    #[serde(skip_serializing_if = "Option::is_none")]
    intervals_sd_rad: Option<Vec<[Option<f64>; 2]>>,
}

#[derive(Serialize)]
struct Summary {
    sphere_beta_range_rad: Option<[f64; 2]>,
    sphere_viable_angles: Option<ViableSummary>,
}

/// The outputs of study 6 (`None`: the empty outputs); with `sd` the
/// 1-sigma too (columns `<column>_sd`, bands, the intervals' ends' in the
/// summary).
pub(crate) fn output(v: Option<&ViableAngles>, mu: f64, sd: Option<&ViableSd>) -> StudyOutput {
    let lead: Vec<Column> = if sd.is_some() {
        COLUMNS.iter().chain(&SD_COLUMNS).copied().collect()
    } else {
        COLUMNS.to_vec()
    };
    let mut a = Assembly::new(
        &[("study6", &columns(&lead, &GRASP_TAIL))],
        &["quantity", "value"],
    );
    let Some(v) = v else {
        let summary = Summary {
            sphere_beta_range_rad: None,
            sphere_viable_angles: None,
        };
        return a.empty(&summary);
    };
    let mut failed = 0;
    for (i, s) in v.scan.iter().enumerate() {
        let row_sd = sd.and_then(|d| d.scan.get(i));
        let Some(why) = &s.failure else {
            let ratio = (s.normal != 0.0).then(|| s.friction / s.normal);
            let mut lead = vec![
                s.beta.into(),
                s.normal.into(),
                s.friction.into(),
                ratio.into(),
                s.viable.into(),
            ];
            if sd.is_some() {
                let ok = row_sd.and_then(|r| r.as_ref().ok());
                lead.extend([
                    ok.map(|r| r.normal).into(),
                    ok.map(|r| r.friction).into(),
                    ok.and_then(|r| r.ratio).into(),
                ]);
            }
            a.grasp(0, lead, s.reversed, s.invalid.as_ref(), &s.warnings);
            if let Some(Err(note)) = row_sd {
                if let Some(row) = a.tables[0].rows.last_mut() {
                    let at = row.len() - 1;
                    row[at] = note.clone().into();
                }
            }
            continue;
        };
        failed += 1;
        let mut lead = vec![
            s.beta.into(),
            Cell::Empty,
            Cell::Empty,
            Cell::Empty,
            s.viable.into(),
        ];
        if sd.is_some() {
            lead.extend([Cell::Empty, Cell::Empty, Cell::Empty]);
        }
        a.failed(0, lead, why.clone().into());
    }
    let range = v.range();
    let viable = v.scan.iter().filter(|s| s.viable).count();
    let summary = Summary {
        sphere_beta_range_rad: range,
        sphere_viable_angles: Some(ViableSummary {
            r_mm: v.radius,
            fv_n: v.lift,
            intervals_rad: v.intervals.clone(),
            samples: v.scan.len(),
            viable_samples: viable,
            failed_samples: failed,
            intervals_sd_rad: sd.map(|d| {
                d.intervals
                    .iter()
                    .map(|[a, b]| [a.clone().ok(), b.clone().ok()])
                    .collect()
            }),
        }),
    };
    a.overview.push(vec![
        "viable b (rad)".into(),
        range.map_or("none".into(), |[a, b]| {
            format!("[{}, {}]", fmt(a, 4), fmt(b, 4))
        }),
    ]);
    a.overview.push(vec![
        "viable b (deg)".into(),
        range.map_or("none".into(), |[a, b]| {
            format!("[{}, {}]", fmt(a.to_degrees(), 1), fmt(b.to_degrees(), 1))
        }),
    ]);
    a.overview.push(vec![
        "separate intervals".into(),
        v.intervals.len().to_string(),
    ]);
    a.overview.push(vec![
        "angles scanned / viable".into(),
        format!("{} / {viable}", v.scan.len()),
    ]);
    if failed > 0 {
        a.notes.push(format!(
            "{failed} scanned angles did not solve (status 'failed' in study6.csv)"
        ));
    }
    a.strict_dropped = v
        .scan
        .iter()
        .filter(|s| matches!(s.invalid, Some(Invalid::CurvatureReversal { .. })))
        .count();
    let mut out = a.finish(figure(v, mu, sd), &summary);
    if sd.is_some() {
        out.bands = exact_bands(&SD_COLUMNS);
    }
    out
}

/// Friction needed against the grasping angle, with the viable band; the
/// normal force; with `sd` their 1-sigma bands.
fn figure(v: &ViableAngles, mu: f64, sd: Option<&ViableSd>) -> Figure {
    // the band of y(sample) with its sd, over the solved samples
    let band = |key: &str,
                y: &dyn Fn(&AngleSample) -> Option<f64>,
                s: fn(&AngleSd) -> Option<f64>,
                clamp: [f64; 2]| {
        let d = sd?;
        let (at, sds): (Vec<[f64; 2]>, Vec<f64>) = v
            .scan
            .iter()
            .zip(&d.scan)
            .filter_map(|(a, r)| {
                let y = y(a)?;
                let sd = r.as_ref().ok().and_then(s).unwrap_or(f64::NAN);
                Some(([a.beta.to_degrees(), y], sd))
            })
            .unzip();
        Series::spread(key, &at, &sds, clamp).map(|s| s.label(BAND_LABEL))
    };
    let solved: Vec<(usize, &AngleSample)> = v
        .scan
        .iter()
        .enumerate()
        .filter(|(_, s)| s.failure.is_none())
        .collect();
    let bent = |i: usize| v.scan[i].reversed;
    let ratio =
        |s: &AngleSample| (s.normal > 0.0).then(|| [s.beta.to_degrees(), s.friction / s.normal]);
    let (lo, hi) = (-1.0, (3.0 * mu).max(2.0));
    let in_range = |p: &[f64; 2]| p[1] >= lo && p[1] <= hi;
    let all: Vec<[f64; 2]> = solved.iter().filter_map(|(_, s)| ratio(s)).collect();
    let pick = |keep: &dyn Fn(usize, &AngleSample) -> bool| -> Vec<[f64; 2]> {
        solved
            .iter()
            .filter(|(i, s)| keep(*i, s))
            .filter_map(|(_, s)| ratio(s))
            .filter(in_range)
            .collect()
    };
    let clipped = all.iter().filter(|p| !in_range(p)).count();
    let x_range = Some([grasping_angle_range(mu)[0].to_degrees() - 2.0, 92.0]);
    let bands: Vec<Band> = v
        .intervals
        .iter()
        .map(|iv| Band {
            from: iv[0].to_degrees(),
            to: iv[1].to_degrees(),
            color: "viable".into(),
        })
        .collect();

    let mut p = Panel::new(
        "Friction needed",
        PlotAxis::new("grasping angle b", "deg"),
        PlotAxis::new("required friction ratio f/F", ""),
    );
    let (ymin, ymax) = all
        .iter()
        .filter(|p| in_range(p))
        .fold((0.0f64, mu), |(a, b), p| (a.min(p[1]), b.max(p[1])));
    let pad = 0.06 * (ymax - ymin);
    p.y.range = Some([ymin - pad, ymax + pad]);
    p.x.range = x_range;
    p.bands = bands.clone();
    p.band_label = Some("viable range of b".into());
    p.series.extend(band(
        "reference",
        &|s| (s.failure.is_none() && s.normal > 0.0).then(|| s.friction / s.normal),
        |s| s.ratio,
        [lo, hi],
    ));
    p.series.push(Series::new(
        "reference",
        SeriesKind::Line,
        all.iter().copied().filter(in_range).collect(),
    ));
    p.series.push(
        Series::new("viable", SeriesKind::Points, pick(&|_, s| s.viable)).label("viable grasp"),
    );
    p.series.push(
        Series::new("not viable", SeriesKind::Hollow, pick(&|_, s| !s.viable)).label("not viable"),
    );
    p.series
        .extend(Series::bent_backwards(pick(&|i, _| bent(i))));
    p.hlines.push(RefLine {
        at: mu,
        label: format!("μ = {mu}"),
    });
    p.hlines.push(RefLine {
        at: 0.0,
        label: String::new(),
    });
    match v.range() {
        Some([a, b]) => p.notes.push(format!(
            "viable b in [{:.1}°, {:.1}°] (shaded)",
            a.to_degrees(),
            b.to_degrees()
        )),
        None => p.notes.push("no viable grasping angle".into()),
    }
    if clipped > 0 {
        p.notes
            .push(format!("{clipped} samples off the plotted range"));
    }
    let failed = v.scan.len() - solved.len();
    if failed > 0 {
        p.notes.push(format!("{failed} angles did not solve"));
    }

    let mut f = Panel::new(
        "Normal force",
        PlotAxis::new("grasping angle b", "deg"),
        PlotAxis::new("normal force F", "N"),
    );
    f.x.range = x_range;
    f.bands = bands;
    f.series.extend(band(
        "normal force",
        &|s| s.failure.is_none().then_some(s.normal),
        |s| Some(s.normal),
        [f64::MIN, f64::MAX],
    ));
    f.curve(
        Series::new(
            "normal force",
            SeriesKind::LinePoints,
            pts(solved.iter().map(|(_, s)| (s.beta.to_degrees(), s.normal))),
        )
        .label("F"),
        pts(solved
            .iter()
            .filter(|(i, _)| bent(*i))
            .map(|(_, s)| (s.beta.to_degrees(), s.normal))),
    );
    f.hlines.push(RefLine {
        at: 0.0,
        label: String::new(),
    });
    Figure::row(
        format!(
            "Study 6: viable grasping angles (sphere r = {} mm, f_v = {} N per finger)",
            v.radius, v.lift
        ),
        [1200, 580],
        vec![p, f],
    )
}

//! Study 5 (Sec. 5.2.1): the sphere grasping region of the Sec. 5 gripper.

use serde::Serialize;

use super::bands::{exact_bands, BandParams, BAND_LABEL};
use super::info::StudyInfo;
use super::options::{section5_gripper, StudyOptions, SweepStop, SECTION5_EPS0};
use super::output::*;
use super::sweep::size_sweep;
use crate::actuator::Actuator;
use crate::error::Warning;
use crate::gripper::{
    grasping_angle_range, EnvelopeCounts, Gripper, Invalid, Object, SphereEnvelope, SphereLift,
};
use crate::sensitivity::{Covariance, GripperParam, Param};
use crate::solve_error::SolveError;

/// A valid sphere grasp of the study-5 sweep (`f = mu F`).
#[derive(Debug, Clone, PartialEq)]
pub struct SpherePoint {
    /// Grasping angle (rad).
    pub beta: f64,
    /// Sphere radius (mm).
    pub radius: f64,
    /// Max lifting force `F (sin b + mu cos b)` (N).
    pub lift: f64,
    /// Normal force (N).
    pub normal: f64,
    /// Grasping size (mm).
    pub size: f64,
    /// An element is bent backwards (dropped in strict mode).
    pub reversed: bool,
    /// The grasp's validity findings.
    pub warnings: Vec<Warning>,
}

/// Study 5 result: the sphere grasping region.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereRegion {
    /// Every valid grasp of the sweeps.
    pub points: Vec<SpherePoint>,
    /// Number of invalid grasps dropped.
    pub dropped: usize,
    /// Of those, the grasps dropped only for bending an element backwards
    /// (strict mode; 0 otherwise).
    pub strict_dropped: usize,
    /// Max lifting force versus radius on a radius grid over the swept
    /// radii, each the best valid grasping angle ([`Gripper::max_sphere_lift`]),
    /// followed from radius to radius ([`SphereEnvelope`]).
    pub envelope: Vec<SphereLift>,
    /// The envelope's highest point, refined by Brent's method in the
    /// radius to 1e-6 mm (`None`: no valid grasp).
    pub peak: Option<SphereLift>,
    /// Sweeps that stopped early: (grasping angle, where and why).
    pub stopped: Vec<(f64, SweepStop)>,
    /// How the envelope's radii (the peak's search included) were
    /// answered: continued on a boundary or inside, or searched afresh.
    pub envelope_counts: EnvelopeCounts,
    /// With a covariance ([`study5_sphere_region_with`]): one entry per
    /// point of `envelope`, its 1-sigma or why it has none (the best
    /// lift's sensitivities failed); empty without a covariance.
    pub envelope_sd: Vec<Result<SphereLiftSd, String>>,
    /// With a covariance: the peak's 1-sigma at its radius held fixed, or
    /// why it has none; `None` without a covariance or without a peak.
    /// Its lift's is the peak's own (the peak is stationary in the
    /// radius); its normal force's is at that radius only (the peak's
    /// radius moves with the parameters, and F with it).
    pub peak_sd: Option<Result<SphereLiftSd, String>>,
}

/// 1-sigma of a point of the study-5 envelope from a covariance, by
/// first-order propagation through the best lift's exact sensitivities
/// at its radius ([`Gripper::max_sphere_lift_sensitivities`]: the envelope
/// theorem over the grasping angle, or the angle moving along the
/// validity boundary that holds it).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereLiftSd {
    /// Of the best lifting force f_v (N).
    pub lift: f64,
    /// Of the normal force F at the best angle (N).
    pub normal: f64,
}

/// Study 5 (Sec. 5.2.1): the Sec. 5 gripper; grasping angles over
/// `[-arctan mu, pi/2)`, at each a sweep of the grasping size (so of `F`)
/// with `f = mu F`, `r = tip gap / (2 cos b)`; invalid grasps dropped. The
/// envelope is solved directly on a grid of `2 sweep_points` radii over the
/// swept ones: at each radius, the best valid grasping angle, continued
/// from the radii before it ([`SphereEnvelope`]: a fresh search only
/// where the continuation fails).
pub fn study5_sphere_region(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<SphereRegion, SolveError> {
    study5_sphere_region_with(actuator, opts, None)
}

/// [`study5_sphere_region`], and with a covariance of the actuator's
/// parameters the 1-sigma of each envelope point and of the peak
/// ([`SphereRegion::envelope_sd`], [`SphereRegion::peak_sd`]) by
/// first-order propagation through the best lift's exact sensitivities
/// at its radius held fixed (the envelope's radius grid moves with the
/// parameters: a band is the spread of the best lift at a given radius).
/// The gripper's prestrain (0.25) is the study's own: its variance is not
/// propagated (`crate::studies::not_propagated`).
pub fn study5_sphere_region_with(
    actuator: &Actuator,
    opts: &StudyOptions,
    covariance: Option<&Covariance>,
) -> Result<SphereRegion, SolveError> {
    // each count checked, then their product, before the sweeps
    let g = section5_gripper(actuator, opts)?;
    opts.validate_sphere()?;
    let [lo, hi] = grasping_angle_range(g.mu());
    let n = opts.sweep_points;
    // the angles' sweeps are independent: on every core, gathered in order
    let betas: Vec<f64> = (0..opts.angle_samples)
        .map(|j| lo + (hi - lo) * j as f64 / opts.angle_samples as f64)
        .collect();
    let sweeps = crate::cancel::par_map(&betas, |&beta| angle_sweep(&g, beta, n));
    let mut points = Vec::new();
    let (mut dropped, mut strict_dropped) = (0, 0);
    let mut stopped = Vec::new();
    for (&beta, sweep) in betas.iter().zip(sweeps) {
        points.extend(sweep.points);
        dropped += sweep.dropped;
        strict_dropped += sweep.strict_dropped;
        stopped.extend(sweep.stop.map(|s| (beta, s)));
    }
    let (envelope, peak, envelope_counts) =
        sphere_envelope(&g, &points, 2 * n, opts.angle_samples)?;
    let (mut envelope_sd, mut peak_sd) = (Vec::new(), None);
    if let Some(b) = covariance.map(BandParams::new) {
        let act = actuator.with_eps0(SECTION5_EPS0)?;
        let sd =
            |e: &SphereLift| lift_sd(&g, &act, e, &b).map_err(|e| format!("no error bars: {e}"));
        envelope_sd = envelope.iter().map(sd).collect();
        peak_sd = peak.as_ref().map(sd);
    }
    Ok(SphereRegion {
        points,
        dropped,
        strict_dropped,
        envelope,
        peak,
        stopped,
        envelope_counts,
        envelope_sd,
        peak_sd,
    })
}

/// One grasping angle's sweep of study 5.
struct AngleSweep {
    points: Vec<SpherePoint>,
    dropped: usize,
    strict_dropped: usize,
    stop: Option<SweepStop>,
}

/// The sweep of the grasping size at angle `beta` over `n` sizes up to
/// `d_max`: its valid grasps, the count of invalid ones, and where it
/// stopped early.
fn angle_sweep(g: &Gripper, beta: f64, n: usize) -> AngleSweep {
    let mut sweep = AngleSweep {
        points: Vec::new(),
        dropped: 0,
        strict_dropped: 0,
        stop: None,
    };
    let d_max = g.d_max();
    let (from, to) = (d_max / n as f64, d_max);
    sweep.stop = size_sweep(g, 0.0, beta, Object::Sphere, from, to, n - 1, |gr| {
        if gr.is_valid() {
            let c = g.sphere_contact(&gr.solution, beta);
            sweep.points.push(SpherePoint {
                beta,
                radius: c.radius,
                lift: gr.lift,
                normal: gr.normal,
                size: gr.size,
                reversed: gr.is_reversed(),
                warnings: gr.warnings.clone(),
            });
        } else {
            sweep.dropped += 1;
            if matches!(gr.invalid(), Some(Invalid::CurvatureReversal { .. })) {
                sweep.strict_dropped += 1;
            }
        }
    });
    sweep
}

/// The 1-sigma of a best lift and its normal force (module `bands`).
fn lift_sd(
    g: &Gripper,
    act: &Actuator,
    best: &SphereLift,
    b: &BandParams,
) -> Result<SphereLiftSd, SolveError> {
    // the actuator's parameters among those propagated; the others (none
    // a gripper's finger has) count 0
    let propagated = b.params();
    let params: Vec<GripperParam> = propagated
        .iter()
        .filter_map(|p| match p {
            Param::Actuator(a) => Some(GripperParam::Actuator(*a)),
            _ => None,
        })
        .collect();
    let rows = g
        .max_sphere_lift_sensitivities(act, 0.0, best, &params)?
        .rows;
    let along = |f: fn(&crate::sensitivity::EnvelopeSensitivity) -> f64| {
        let d: Vec<f64> = propagated
            .iter()
            .map(|p| match p {
                Param::Actuator(a) => rows
                    .iter()
                    .find(|r| r.param == GripperParam::Actuator(*a))
                    .map_or(0.0, f),
                _ => 0.0,
            })
            .collect();
        b.sigma(&d)
    };
    Ok(SphereLiftSd {
        lift: along(|r| r.lift),
        normal: along(|r| r.normal),
    })
}

/// The max-lift envelope on `m` radii spanning the valid sweep points,
/// and its peak refined by Brent's method around the best radius.
fn sphere_envelope(
    g: &Gripper,
    points: &[SpherePoint],
    m: usize,
    samples: usize,
) -> Result<(Vec<SphereLift>, Option<SphereLift>, EnvelopeCounts), SolveError> {
    let rmin = points
        .iter()
        .map(|p| p.radius)
        .fold(f64::INFINITY, f64::min);
    let rmax = points.iter().map(|p| p.radius).fold(0.0, f64::max);
    if !(rmin.is_finite() && rmax > rmin) {
        return Ok((Vec::new(), None, EnvelopeCounts::default()));
    }
    // each radius continued from those answered before it
    let mut follower = SphereEnvelope::new(g, 0.0, samples);
    let radii: Vec<f64> = (0..m)
        .map(|i| rmin + (rmax - rmin) * i as f64 / (m - 1) as f64)
        .collect();
    let mut envelope = Vec::with_capacity(m);
    let mut best: Option<(usize, SphereLift)> = None;
    for e in follower.along(&radii)?.into_iter().flatten() {
        if best.as_ref().is_none_or(|(_, b)| e.lift > b.lift) {
            best = Some((envelope.len(), e.clone()));
        }
        envelope.push(e);
    }
    let Some((i, mut peak)) = best else {
        return Ok((envelope, None, follower.counts()));
    };
    // Brent's method on the neighbours' bracket (a radius without a valid
    // grasp counts as -inf): the peak's optimality condition in r
    let (a, b) = (
        envelope[i.saturating_sub(1)].radius,
        envelope[(i + 1).min(envelope.len() - 1)].radius,
    );
    let (centre, fb) = (peak.radius, peak.lift);
    let mut eval = |r: f64| -> Result<Option<f64>, SolveError> {
        let e = follower.at(r)?;
        let lift = e.as_ref().map(|e| e.lift);
        if let Some(e) = e {
            if e.lift > peak.lift {
                peak = e;
            }
        }
        Ok(lift)
    };
    crate::brent::brent_max(&mut eval, a, centre, b, fb, PEAK_RADIUS_TOL_MM, 40)?;
    Ok((envelope, Some(peak), follower.counts()))
}

/// Tolerance (mm) on the radius of the study-5 envelope's peak.
const PEAK_RADIUS_TOL_MM: f64 = 1e-6;

// ------------------------------------------------------------ outputs

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 5,
    key: "sphere_region",
    title: "Sphere grasping region",
    description: "The same gripper; grasping angle b swept over [−arctan μ, π/2), at each the grasping size swept with f = μF, r = d / (2 cos b), invalid grasps (not open, second contact, friction) dropped; the envelope is the best b at each radius (Sec. 5.2.1).",
    run,
    has_bands: true,
    empty: || output(None, 0, false),
};

fn run(
    act: &Actuator,
    opts: &StudyOptions,
    cov: Option<&Covariance>,
) -> Result<StudyOutput, SolveError> {
    let region = study5_sphere_region_with(act, opts, cov)?;
    Ok(output(Some(&region), opts.angle_samples, cov.is_some()))
}

const COLUMNS: [Column; 5] = [
    Column::new("beta_rad", "rad"),
    Column::new("r_mm", "mm"),
    Column::new("fv_n", "N"),
    Column::new("F_n", "N"),
    Column::new("d_mm", "mm"),
];

const ENVELOPE_COLUMNS: [Column; 4] = [
    Column::new("r_mm", "mm"),
    Column::new("beta_rad", "rad"),
    Column::new("fv_n", "N"),
    Column::new("F_n", "N"),
];

/// The envelope's 1-sigma columns, with a covariance (`bands`).
const ENVELOPE_SD_COLUMNS: [Column; 2] = [Column::new("fv_n_sd", "N"), Column::new("F_n_sd", "N")];

#[derive(Serialize)]
struct Peak {
    r_mm: f64,
    beta_rad: f64,
    fv_n: f64,
    #[serde(rename = "F_n")]
    f_n: f64,
    /// With a covariance: the 1-sigma of the peak's lift (null where
    /// none). Not of its F: the peak's radius moves with the parameters.
    #[serde(skip_serializing_if = "Option::is_none")]
    fv_n_sd: Option<Option<f64>>,
}

#[derive(Serialize)]
struct RegionSummary {
    valid_points: usize,
    dropped_points: usize,
    /// Sweeps that ended before d_max at the gripper's own limit (status
    /// `ended` in study5.csv).
    ended_sweeps: usize,
    /// Sweeps stopped by a failed solve (status `stopped`).
    stopped_sweeps: usize,
    peak: Option<Peak>,
}

#[derive(Serialize)]
struct Summary {
    sphere_envelope_peak_radius_mm: Option<f64>,
    sphere_region: Option<RegionSummary>,
}

/// The outputs of study 5 (`None`: the empty outputs); `with_sd`: the
/// envelope's 1-sigma too (columns `fv_n_sd`, `F_n_sd` of
/// `study5_envelope`, a band, the peak's in the summary).
pub(crate) fn output(
    region: Option<&SphereRegion>,
    angle_samples: usize,
    with_sd: bool,
) -> StudyOutput {
    let envelope_columns: Vec<Column> = if with_sd {
        ENVELOPE_COLUMNS
            .iter()
            .chain(&ENVELOPE_SD_COLUMNS)
            .copied()
            .collect()
    } else {
        ENVELOPE_COLUMNS.to_vec()
    };
    let mut a = Assembly::new(
        &[
            ("study5", &columns(&COLUMNS, &GRASP_TAIL)),
            ("study5_envelope", &columns(&envelope_columns, &GRASP_TAIL)),
        ],
        &["quantity", "value"],
    );
    let Some(region) = region else {
        let summary = Summary {
            sphere_envelope_peak_radius_mm: None,
            sphere_region: None,
        };
        return a.empty(&summary);
    };
    // the region and its envelope hold valid grasps only
    for p in &region.points {
        let lead = [p.beta, p.radius, p.lift, p.normal, p.size].map(Cell::from);
        a.grasp(0, lead.to_vec(), p.reversed, None, &p.warnings);
    }
    for (beta, s) in &region.stopped {
        let case = format!("b = {beta:.6} rad");
        a.stop(
            0,
            vec![("beta_rad", (*beta).into())],
            "d_mm",
            &case,
            StopAt::Mm,
            s,
            false,
        );
    }
    let ended = region
        .stopped
        .iter()
        .filter(|(_, s)| s.is_natural())
        .count();
    let failed = region.stopped.len() - ended;
    if ended > 0 {
        a.notes.push(format!(
            "{ended} of the {angle_samples} grasping-angle sweeps ended before d_max at the gripper's own limit (rows with status 'ended' in study5.csv)",
        ));
    }
    if failed > 0 {
        a.notes.push(format!(
            "{failed} of the {angle_samples} grasping-angle sweeps stopped on a failed solve (rows with status 'stopped' in study5.csv)",
        ));
    }
    for (i, e) in region.envelope.iter().enumerate() {
        let mut lead = [e.radius, e.beta, e.lift, e.normal]
            .map(Cell::from)
            .to_vec();
        let sd = region.envelope_sd.get(i);
        if with_sd {
            let ok = sd.and_then(|s| s.as_ref().ok());
            lead.extend([ok.map(|s| s.lift).into(), ok.map(|s| s.normal).into()]);
        }
        a.grasp(1, lead, e.reversed, None, &e.warnings);
        if let Some(Err(why)) = sd.filter(|_| with_sd) {
            if let Some(row) = a.tables[1].rows.last_mut() {
                let at = row.len() - 1;
                row[at] = why.clone().into();
            }
        }
    }
    let peak = region.peak.as_ref();
    let peak_lift_sd = region
        .peak_sd
        .as_ref()
        .and_then(|s| s.as_ref().ok())
        .map(|s| s.lift);
    let summary = Summary {
        sphere_envelope_peak_radius_mm: peak.map(|p| p.radius),
        sphere_region: Some(RegionSummary {
            valid_points: region.points.len(),
            dropped_points: region.dropped,
            ended_sweeps: ended,
            stopped_sweeps: failed,
            peak: peak.map(|p| Peak {
                r_mm: p.radius,
                beta_rad: p.beta,
                fv_n: p.lift,
                f_n: p.normal,
                fv_n_sd: with_sd.then_some(peak_lift_sd),
            }),
        }),
    };
    a.overview.push(vec![
        "valid grasps / dropped".into(),
        format!("{} / {}", region.points.len(), region.dropped),
    ]);
    a.overview.push(vec![
        "envelope peak radius (mm)".into(),
        fmt_opt(peak.map(|p| p.radius), 2),
    ]);
    a.overview.push(vec![
        "envelope peak f_v (N)".into(),
        fmt_opt(peak.map(|p| p.lift), 3),
    ]);
    a.overview.push(vec![
        "grasping angle at the peak (deg)".into(),
        fmt_opt(peak.map(|p| p.beta.to_degrees()), 1),
    ]);
    a.overview.push(vec![
        "radii covered (mm)".into(),
        match (
            min_of(region.points.iter().map(|p| p.radius)),
            max_of(region.points.iter().map(|p| p.radius)),
        ) {
            (Some(a), Some(b)) => format!("{} to {}", fmt(a, 1), fmt(b, 1)),
            _ => "–".into(),
        },
    ]);
    a.strict_dropped = region.strict_dropped;
    let mut out = a.finish(figure(region, with_sd), &summary);
    if with_sd {
        out.bands = exact_bands(&ENVELOPE_SD_COLUMNS);
    }
    out
}

/// Valid sphere grasps and the max-lift envelope; `with_sd`: the
/// envelope's 1-sigma band.
fn figure(region: &SphereRegion, with_sd: bool) -> Figure {
    let mut p = Panel::new(
        "Valid grasps and the max lifting force envelope",
        PlotAxis::new("sphere radius r", "mm"),
        PlotAxis::new("lifting force f_v per finger", "N"),
    );
    p.y.include_zero = true;
    let grasps = pts(region.points.iter().map(|q| (q.radius, q.lift)));
    let bent = pts(region
        .points
        .iter()
        .filter(|q| q.reversed)
        .map(|q| (q.radius, q.lift)));
    p.curve(
        Series::new("grasps", SeriesKind::Scatter, grasps)
            .label(format!("valid grasps ({})", region.points.len())),
        bent,
    );
    if with_sd {
        let (at, sd): (Vec<[f64; 2]>, Vec<f64>) = region
            .envelope
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let sd = region.envelope_sd.get(i).and_then(|s| s.as_ref().ok());
                ([e.radius, e.lift], sd.map_or(f64::NAN, |s| s.lift))
            })
            .unzip();
        p.series.extend(
            Series::spread("envelope", &at, &sd, [f64::MIN, f64::MAX]).map(|s| s.label(BAND_LABEL)),
        );
    }
    let envelope = pts(region.envelope.iter().map(|e| (e.radius, e.lift)));
    let bent = pts(region
        .envelope
        .iter()
        .filter(|e| e.reversed)
        .map(|e| (e.radius, e.lift)));
    p.curve(
        Series::new("envelope", SeriesKind::Line, envelope).label("envelope (best b)"),
        bent,
    );
    if let Some(pk) = &region.peak {
        p.series.push(
            Series::new("peak", SeriesKind::Cross, vec![[pk.radius, pk.lift]]).label(format!(
                "peak: r = {:.1} mm, f_v = {:.3} N, b = {:.1}°",
                pk.radius,
                pk.lift,
                pk.beta.to_degrees()
            )),
        );
    }
    p.notes
        .push(format!("{} invalid grasps dropped", region.dropped));
    // natural ends, counted by kind ("7 angle sweeps end at the validity limit")
    let mut natural = 0;
    for (kind, what) in [
        ("fold", "a fold"),
        ("path", "the end of the path from rest (the size turns back or the held finger loses its stability)"),
        ("validity", "the validity limit"),
        ("force_bound", "the force bound"),
    ] {
        let n = region
            .stopped
            .iter()
            .filter(|(_, s)| s.end.as_ref().is_some_and(|e| e.kind() == kind))
            .count();
        if n > 0 {
            natural += n;
            p.notes.push(format!("{n} angle sweeps end at {what}"));
        }
    }
    if region.stopped.len() > natural {
        p.notes.push(format!(
            "{} of the angle sweeps stopped early (failed solves)",
            region.stopped.len() - natural
        ));
    }
    Figure::row(
        "Study 5: sphere grasping region (ε0 = 0.25, a = π/3, g = 20 mm, f = μF)",
        [1000, 640],
        vec![p],
    )
}

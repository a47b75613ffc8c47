//! Study 6 (Sec. 5.2.2): the grasping angles that hold a sphere.

use serde::Serialize;

use super::info::StudyInfo;
use super::options::{section5_gripper, StudyOptions};
use super::output::*;
use crate::actuator::Actuator;
use crate::gripper::{grasping_angle_range, AngleSample, Invalid, ViableAngles};
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

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 6,
    key: "viable_angles",
    title: "Viable grasping angles",
    description: "A sphere r = 50 mm needing f_v = 0.5 N per finger: the grasping angles b at which some F with 0 ≤ f ≤ μF holds it validly (Sec. 5.2.2).",
    run,
    has_bands: false,
    empty: || output(None, StudyOptions::default().mu),
};

fn run(
    act: &Actuator,
    opts: &StudyOptions,
    _: Option<&crate::sensitivity::Covariance>,
) -> Result<StudyOutput, SolveError> {
    let v = study6_viable_angles(act, opts)?;
    Ok(output(Some(&v), opts.mu))
}

const COLUMNS: [Column; 5] = [
    Column::new("beta_rad", "rad"),
    Column::new("F_n", "N"),
    Column::new("f_n", "N"),
    Column::new("f_over_F", ""),
    Column::new("viable", ""),
];

#[derive(Serialize)]
struct ViableSummary {
    r_mm: f64,
    fv_n: f64,
    intervals_rad: Vec<[f64; 2]>,
    samples: usize,
    viable_samples: usize,
    failed_samples: usize,
}

#[derive(Serialize)]
struct Summary {
    sphere_beta_range_rad: Option<[f64; 2]>,
    sphere_viable_angles: Option<ViableSummary>,
}

/// The outputs of study 6 (`None`: the empty outputs).
pub(crate) fn output(v: Option<&ViableAngles>, mu: f64) -> StudyOutput {
    let mut a = Assembly::new(
        &[("study6", &columns(&COLUMNS, &GRASP_TAIL))],
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
    for s in &v.scan {
        let Some(why) = &s.failure else {
            let ratio = (s.normal != 0.0).then(|| s.friction / s.normal);
            let lead = vec![
                s.beta.into(),
                s.normal.into(),
                s.friction.into(),
                ratio.into(),
                s.viable.into(),
            ];
            a.grasp(0, lead, s.reversed, s.invalid.as_ref(), &s.warnings);
            continue;
        };
        failed += 1;
        let lead = vec![
            s.beta.into(),
            Cell::Empty,
            Cell::Empty,
            Cell::Empty,
            s.viable.into(),
        ];
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
    a.finish(figure(v, mu), &summary)
}

/// Friction needed against the grasping angle, with the viable band; the
/// normal force.
fn figure(v: &ViableAngles, mu: f64) -> Figure {
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

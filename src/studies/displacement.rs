//! Study 8 (Sec. 6.3): the tip force that moves the tip a fixed distance.

use serde::Serialize;

use super::bands::{exact_bands, BandParams, BAND_LABEL};
use super::info::StudyInfo;
use super::options::{StudyOptions, STUDY8_PRESSURES_KPA};
use super::output::*;
use crate::actuator::Actuator;
use crate::error::{finite, Warning};
use crate::field::Field;
use crate::finger::{
    Finger, Load, Solution, SolveOptions, Solver, TargetFold, TargetProblem, Traced,
};
use crate::sensitivity::{Covariance, Param};
use crate::solve_error::SolveError;

/// An axis of the finger frame.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Axis {
    /// Along the root tangent.
    X,
    /// Normal to it, towards the constraining layer.
    Z,
}

impl Axis {
    fn unit(self) -> [f64; 2] {
        match self {
            Axis::X => [1.0, 0.0],
            Axis::Z => [0.0, 1.0],
        }
    }
}

/// A tip force that moves the tip a given distance along an axis.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplacementForce {
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// The axis of force and displacement.
    pub axis: Axis,
    /// Displacement of the tip along the axis (mm).
    pub displacement: f64,
    /// The force along the axis (N).
    pub force: f64,
    /// The pressurised, unloaded tip (finger frame, mm).
    pub start_tip: [f64; 2],
    /// The loaded equilibrium.
    pub solution: Solution,
}

/// From the pressurised unloaded shape, the tip force along `axis` (finger
/// frame) that moves the tip `displacement` mm along that axis (the gas
/// law's factor kappa at its default, as in the paper's study 8).
pub fn tip_force_for_displacement(
    finger: &Finger,
    pressure_kpa: f64,
    axis: Axis,
    displacement: f64,
) -> Result<DisplacementForce, SolveError> {
    let kappa = Load::unloaded().kappa;
    tip_force_for_displacement_with_kappa(finger, pressure_kpa, kappa, axis, displacement)
}

/// [`tip_force_for_displacement`] with the pressure factor `kappa` of the
/// finger's gas law (a measured specimen's, or a calibrated one).
pub fn tip_force_for_displacement_with_kappa(
    finger: &Finger,
    pressure_kpa: f64,
    kappa: f64,
    axis: Axis,
    displacement: f64,
) -> Result<DisplacementForce, SolveError> {
    finite(Field::key("displacement.pressure_kpa"), pressure_kpa)?;
    finite(Field::key("displacement.distance"), displacement)?;
    let base = Load {
        kappa,
        ..Load::unloaded()
    }
    .with_pressure_kpa(pressure_kpa);
    let opts = SolveOptions::default();
    let mut solver = Solver::new(finger);
    let start = solver.solve(&base, None, &opts)?;
    let u = axis.unit();
    let at = |target: f64| TargetProblem {
        base,
        direction: u,
        weights: u,
        target,
    };
    let s0 = u[0] * start.tip[0] + u[1] * start.tip[1];
    let value = displacement;
    let not_on_path = |how: &str, f: TargetFold| SolveError::NotOnPath {
        target: Field::key("displacement.distance"),
        value,
        detail: format!(
            "pushing the tip from its unloaded position, {how} at {:.4} mm (force {:.4} N)",
            f.target - s0,
            f.lambda
        ),
    };
    let (solution, force) = match solver
        .trace_target(
            &at(s0 + displacement),
            &start.coefficients,
            0.0,
            1e-9,
            &opts,
        )
        .map_err(|e| crate::gripper::for_target(e, Field::key("displacement.distance"), value))?
    {
        Traced::Reached {
            solution, lambda, ..
        } => (solution, lambda),
        Traced::Stalled { reached, .. } => {
            return Err(SolveError::TargetNotReached {
                target: Field::key("displacement.distance"),
                value,
                reached,
                detail: "the path from the unloaded tip spent its step budget".into(),
            })
        }
        Traced::Fold(f) => return Err(not_on_path("the path turns back", f)),
        Traced::Unstable(f) => return Err(not_on_path("the finger loses its stability", f)),
    };
    Ok(DisplacementForce {
        pressure_kpa,
        axis,
        displacement,
        force,
        start_tip: start.tip,
        solution,
    })
}

/// One row of study 8.
#[derive(Debug, Clone, PartialEq)]
pub struct DisplacementForceRow {
    /// Prestrain of the sample.
    pub eps0: f64,
    /// Axis of force and displacement.
    pub axis: Axis,
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Force for a 10 mm tip displacement (N); `None` when the solve failed.
    pub force: Option<f64>,
    /// The loaded finger's validity findings.
    pub warnings: Vec<Warning>,
    /// With a covariance ([`study8_force_at_displacement_with`]): the
    /// force's 1-sigma (N); `None` without one, or when the force or its
    /// sensitivities failed (`sd_note` says why).
    pub force_sd: Option<f64>,
    /// Why a row of a study with a covariance has no `force_sd`.
    pub sd_note: Option<String>,
}

/// Study 8 (Sec. 6.3): at 0, 27.6, 55.2, 82.7 kPa, the tip force that moves
/// the tip 10 mm: along +X for the eps0 = 0.4 sample, along +Z for the
/// eps0 = 0.15 sample.
pub fn study8_force_at_displacement(
    actuator: &Actuator,
    opts: &StudyOptions,
) -> Result<Vec<DisplacementForceRow>, SolveError> {
    study8_force_at_displacement_with(actuator, opts, None)
}

/// [`study8_force_at_displacement`], and with a covariance of the
/// actuator's parameters each force's 1-sigma
/// ([`DisplacementForceRow::force_sd`]) by first-order propagation through
/// exact sensitivities: the target solve's `d(force)/dp` at a fixed
/// target, plus `d(force)/d(target)` times the move of the target with
/// the unloaded tip it starts from (`d(s0)/dp`, the unloaded
/// equilibrium's sensitivities). The prestrain of each sample and
/// `load.kappa` are the study's own: their variances are not propagated
/// (`crate::studies::not_propagated`).
pub fn study8_force_at_displacement_with(
    actuator: &Actuator,
    opts: &StudyOptions,
    covariance: Option<&Covariance>,
) -> Result<Vec<DisplacementForceRow>, SolveError> {
    opts.validate()?;
    let bands = covariance.map(BandParams::new);
    let mut rows = Vec::new();
    for (eps0, axis) in [(0.4, Axis::X), (0.15, Axis::Z)] {
        let finger = opts.finger(actuator, eps0)?;
        let act = actuator.with_eps0(eps0)?;
        for p in STUDY8_PRESSURES_KPA {
            let r = tip_force_for_displacement(&finger, p, axis, DISPLACEMENT_MM).ok();
            let (force_sd, sd_note) = match (&bands, &r) {
                (Some(b), Some(r)) => match force_sd(&finger, &act, r, b) {
                    Ok(sd) => (Some(sd), None),
                    Err(e) => (None, Some(format!("no error bar: {e}"))),
                },
                _ => (None, None),
            };
            rows.push(DisplacementForceRow {
                eps0,
                axis,
                pressure_kpa: p,
                force: r.as_ref().map(|r| r.force),
                warnings: r.map(|r| r.solution.warnings).unwrap_or_default(),
                force_sd,
                sd_note,
            });
        }
    }
    Ok(rows)
}

/// The 1-sigma of the force of `r` (module `bands`).
fn force_sd(
    finger: &Finger,
    act: &Actuator,
    r: &DisplacementForce,
    b: &BandParams,
) -> Result<f64, String> {
    let params = b.params();
    let base = Load::unloaded().with_pressure_kpa(r.pressure_kpa);
    // the unloaded start, solved as tip_force_for_displacement solves it
    let start = Solver::new(finger)
        .solve(&base, None, &SolveOptions::default())
        .map_err(|e| e.to_string())?;
    let moved = finger
        .sensitivities(act, &start, &base, &params)
        .map_err(|e| e.to_string())?;
    let u = r.axis.unit();
    let problem = TargetProblem {
        base,
        direction: u,
        weights: u,
        target: u[0] * start.tip[0] + u[1] * start.tip[1] + r.displacement,
    };
    let mut with_target = params.clone();
    with_target.push(Param::Target);
    let t = finger
        .target_sensitivities(act, &r.solution, &problem, r.force, &with_target)
        .map_err(|e| e.to_string())?;
    let per_target = t.rows.last().and_then(|row| row.lambda);
    let d: Option<Vec<f64>> = params
        .iter()
        .enumerate()
        .map(|(k, _)| {
            let ds0 = u[0] * moved.rows[k].tip[0] + u[1] * moved.rows[k].tip[1];
            Some(t.rows[k].lambda? + per_target? * ds0)
        })
        .collect();
    match d {
        Some(d) if d.iter().all(|v| v.is_finite()) => Ok(b.sigma(&d)),
        _ => Err("the target solve's sensitivities have no load factor".into()),
    }
}

// ------------------------------------------------------------ outputs

pub(crate) const INFO: StudyInfo = StudyInfo {
    number: 8,
    key: "force_at_displacement",
    title: "Force at a fixed displacement",
    description: "From the pressurised unloaded shape at 0, 27.6, 55.2 and 82.7 kPa, the tip force that moves the tip 10 mm: along +X for the eps0 = 0.4 sample, along +Z for the eps0 = 0.15 sample (Sec. 6.3).",
    run: |act, opts, cov| {
        Ok(output(
            &study8_force_at_displacement_with(act, opts, cov)?,
            cov.is_some(),
        ))
    },
    has_bands: true,
    empty: || output(&[], false),
};

/// The tip displacement of study 8 (mm).
const DISPLACEMENT_MM: f64 = 10.0;

impl Axis {
    /// `X` or `Z`.
    pub fn name(self) -> &'static str {
        match self {
            Axis::X => "X",
            Axis::Z => "Z",
        }
    }
}

const COLUMNS: [Column; 5] = [
    Column::new("eps0", ""),
    Column::new("axis", ""),
    Column::new("pressure_kpa", "kPa"),
    Column::new("displacement_mm", "mm"),
    Column::new("force_n", "N"),
];

/// The 1-sigma column, with a covariance (`bands`).
const SD_COLUMN: Column = Column::new("force_n_sd", "N");

/// One entry of `force_at_10mm`.
#[derive(Serialize)]
struct Row {
    axis: &'static str,
    eps0: f64,
    pressure_kpa: f64,
    force_n: Option<f64>,
    /// With a covariance: the force's 1-sigma (null where none).
    #[serde(skip_serializing_if = "Option::is_none")]
    force_n_sd: Option<Option<f64>>,
}

#[derive(Serialize)]
struct Summary {
    force_at_10mm: Vec<Row>,
}

/// The outputs of study 8 from its rows; `with_sd`: the forces' 1-sigma
/// too (column `force_n_sd`, bands, summary entries).
pub(crate) fn output(rows: &[DisplacementForceRow], with_sd: bool) -> StudyOutput {
    let mut lead_columns = COLUMNS.to_vec();
    if with_sd {
        lead_columns.push(SD_COLUMN);
    }
    let mut a = Assembly::new(
        &[("study8", &columns(&lead_columns, &STATE_TAIL))],
        &["eps0", "axis", "P (kPa)", "force for 10 mm (N)"],
    );
    for r in rows {
        let axis = r.axis.name();
        let mut lead = vec![
            r.eps0.into(),
            axis.into(),
            r.pressure_kpa.into(),
            DISPLACEMENT_MM.into(),
            r.force.into(),
        ];
        if with_sd {
            lead.push(r.force_sd.into());
        }
        a.overview.push(vec![
            r.eps0.to_string(),
            format!("+{axis}"),
            r.pressure_kpa.to_string(),
            fmt_opt(r.force, 4),
        ]);
        if r.force.is_some() {
            let note = r.sd_note.clone().map_or(Cell::Empty, Cell::Text);
            a.state(0, lead, &r.warnings, note);
            continue;
        }
        a.failed(0, lead, "no solution".into());
        let case = format!("eps0 = {}, axis {axis}", r.eps0);
        a.notes
            .push(format!("{case}: no solution at {} kPa", r.pressure_kpa));
        a.stop_record(Stop {
            case,
            at: StopAt::Kpa(r.pressure_kpa),
            reason: "no solution".into(),
            end: None,
        });
    }
    let summary = Summary {
        force_at_10mm: rows
            .iter()
            .map(|r| Row {
                axis: r.axis.name(),
                eps0: r.eps0,
                pressure_kpa: r.pressure_kpa,
                force_n: r.force,
                force_n_sd: with_sd.then_some(r.force_sd),
            })
            .collect(),
    };
    let mut out = a.finish(figure(rows, with_sd), &summary);
    if with_sd {
        out.bands = exact_bands(&[SD_COLUMN]);
    }
    out
}

/// Tip force for a 10 mm displacement against pressure, one curve per sample.
/// `with_sd`: each curve's 1-sigma band.
fn figure(rows: &[DisplacementForceRow], with_sd: bool) -> Figure {
    let mut p = Panel::new(
        "",
        PlotAxis::new("pressure P", "kPa"),
        PlotAxis::new("tip force", "N"),
    );
    p.y.include_zero = true;
    let mut cases: Vec<(f64, Axis)> = Vec::new();
    for r in rows {
        if !cases.contains(&(r.eps0, r.axis)) {
            cases.push((r.eps0, r.axis));
        }
    }
    for (eps0, axis) in cases {
        let sel: Vec<_> = rows
            .iter()
            .filter(|r| r.eps0 == eps0 && r.axis == axis)
            .collect();
        let points = pts(sel
            .iter()
            .filter_map(|r| r.force.map(|f| (r.pressure_kpa, f))));
        if with_sd {
            let (at, sd): (Vec<[f64; 2]>, Vec<f64>) = sel
                .iter()
                .filter_map(|r| {
                    let f = r.force?;
                    Some(([r.pressure_kpa, f], r.force_sd.unwrap_or(f64::NAN)))
                })
                .unzip();
            p.series.extend(
                Series::spread(eps0_key(eps0), &at, &sd, [f64::MIN, f64::MAX])
                    .map(|s| s.label(BAND_LABEL)),
            );
        }
        p.series.push(
            Series::new(eps0_key(eps0), SeriesKind::LinePoints, points).label(format!(
                "ε0 = {eps0}, force and displacement along +{}",
                axis.name()
            )),
        );
        for r in sel.iter().filter(|r| r.force.is_none()) {
            p.notes.push(format!(
                "ε0 = {eps0}, +{}: no solution at {} kPa",
                axis.name(),
                r.pressure_kpa
            ));
        }
    }
    Figure::row(
        "Study 8: tip force that moves the tip 10 mm, from the pressurised shape",
        [1000, 600],
        vec![p],
    )
}

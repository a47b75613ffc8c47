//! The weighted residuals of every data row at given parameter values,
//! and their exact Jacobian: `r = (measured - predicted) / sd`,
//! `dr/dtheta = -(d predicted/dtheta) / sd`.
//!
//! The predictions are those of [`crate::compare`]; their derivatives:
//!
//! - a marker: the element unknowns' sensitivities `dK/dp` (implicit
//!   function theorem, [`Finger::sensitivities`]) carried through the chain
//!   to the marker's point exactly (`src/sensitivity/midplane.rs`), and
//!   through the camera's
//!   rotation for a camera frame;
//! - a radius: the shape samples' derivatives the same way, then the circle
//!   fit's by implicit differentiation (`src/circle_fit.rs`);
//! - a force: the target solve's `d lambda/dp` at a fixed target
//!   ([`Finger::target_sensitivities`]), plus `d lambda/d target` times the
//!   move of the target, which is the pressurised unloaded tip's
//!   `u . d tip/dp` (`u` the axis).

use std::collections::HashMap;

use super::params::Unknown;
use crate::actuator::Actuator;
use crate::circle_fit::radius_tangents;
use crate::coefficients::Coefficients;
use crate::field::Field;
use crate::finger::{Finger, Load, Solution, SolveOptions, Solver, TargetProblem, Traced};
use crate::measure::{Specimen, TestData};
use crate::num::Num;
use crate::plan::PlannedFinger;
use crate::sensitivity::Param;
use crate::sensitivity::{points_and_tangents, shape_sites, site_at, Site};
use crate::solve_error::SolveError;
use crate::studies::Axis;

/// One measured quantity at the parameters.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct FitResidual {
    /// The specimen.
    pub specimen: String,
    /// The test's file.
    pub file: String,
    /// The row's line in it.
    pub line: usize,
    /// The row's pressure (kPa).
    pub pressure_kpa: f64,
    /// `x_mm`, `z_mm`, `radius_mm` or `force_n`.
    pub quantity: &'static str,
    /// The measured value.
    pub measured: f64,
    /// Its standard deviation.
    pub sd: f64,
    /// The model's value.
    pub predicted: f64,
    /// `(measured - predicted) / sd`.
    pub residual_sd: f64,
}

/// Residuals, Jacobian (row-major, one row per residual, one column per
/// unknown) and what it cost.
#[derive(Debug, Clone, Default)]
pub(crate) struct Evaluation {
    pub rows: Vec<FitResidual>,
    pub jacobian: Vec<Vec<f64>>,
    /// Equilibrium solves (unloaded, per specimen and pressure).
    pub solves: usize,
    /// Target solves (forces).
    pub target_solves: usize,
    /// Predictions by a finger outside the model (docs/model.md section 8).
    pub outside_model: usize,
}

fn bits(p: f64) -> u64 {
    (p + 0.0).to_bits()
}

fn unit(axis: Axis) -> [f64; 2] {
    match axis {
        Axis::X => [1.0, 0.0],
        Axis::Z => [0.0, 1.0],
    }
}

/// A specimen's actuator and load factor at the values `theta`.
fn specimen_at(
    s: &Specimen,
    unknowns: &[Unknown],
    theta: &[f64],
) -> Result<(Actuator, f64), SolveError> {
    let mut act = s.scene.actuator.clone();
    let mut kappa = s.scene.load.kappa;
    for (u, &v) in unknowns.iter().zip(theta) {
        if !u.applies_to(&s.name) || !u.is_model() {
            continue;
        }
        match u.param {
            Param::Actuator(a) => act = a.with_value(&act, v)?,
            Param::Kappa => kappa = v,
            _ => {}
        }
    }
    Ok((act, kappa))
}

/// The unloaded equilibrium at one pressure and its sensitivities.
struct AtPressure {
    load: Load,
    solution: Solution,
    dk: Vec<Coefficients>,
    tip_rows: Vec<[f64; 2]>,
}

/// Evaluates one specimen, appending its rows.
fn evaluate_specimen(
    s: &Specimen,
    unknowns: &[Unknown],
    theta: &[f64],
    out: &mut Evaluation,
) -> Result<(), SolveError> {
    let (act, kappa) = specimen_at(s, unknowns, theta)?;
    let planned = PlannedFinger::builder(&act)
        .model(s.scene.model)
        .plan(s.scene.partition.plan())
        .build()?;
    let finger: Finger = planned.fixed().cloned().ok_or_else(|| {
        SolveError::from(super::options::inconsistent(
            "partition",
            format!(
                "specimen {:?}: a calibration needs a fixed partition (elements = N or lengths), not an automatic one or a tip tolerance",
                s.name
            ),
        ))
    })?;
    // the columns of this specimen
    let cols: Vec<(usize, Param)> = unknowns
        .iter()
        .enumerate()
        .filter(|(_, u)| u.applies_to(&s.name) && u.is_model())
        .map(|(j, u)| (j, u.param))
        .collect();
    let params: Vec<Param> = cols.iter().map(|c| c.1).collect();
    let opts = SolveOptions {
        shape: false,
        ..s.scene.options
    };
    let per = s.scene.options.samples_per_element;
    let lengths = finger.element_lengths().to_vec();
    let mut cache: HashMap<u64, AtPressure> = HashMap::new();
    // `file` and `line`: the first row at this pressure, which a failed
    // solve names
    let at = |cache: &mut HashMap<u64, AtPressure>,
              p: f64,
              out: &mut Evaluation,
              file: &str,
              line: usize|
     -> Result<(), SolveError> {
        if cache.contains_key(&bits(p)) {
            return Ok(());
        }
        let load = Load {
            kappa,
            ..Load::unloaded().with_pressure_kpa(p)
        };
        let solution = finger
            .solve(&load, &opts)
            .map_err(|e| unsolved_row(e, file, line, p))?;
        out.solves += 1;
        if solution
            .warnings
            .iter()
            .any(crate::error::Warning::is_validity)
        {
            out.outside_model += 1;
        }
        let sens = finger.sensitivities(&act, &solution, &load, &params)?;
        cache.insert(
            bits(p),
            AtPressure {
                load,
                dk: sens.rows.iter().map(|r| r.coefficients.clone()).collect(),
                tip_rows: sens.rows.iter().map(|r| r.tip).collect(),
                solution,
            },
        );
        Ok(())
    };
    let n = unknowns.len();
    let push = |out: &mut Evaluation, row: FitResidual, d: &[f64]| {
        let mut j = vec![0.0; n];
        for ((col, _), v) in cols.iter().zip(d) {
            j[*col] = -v / row.sd;
        }
        out.rows.push(row);
        out.jacobian.push(j);
    };
    for (ti, test) in s.tests.iter().enumerate() {
        // this test's camera unknowns: (column, component)
        let cam: Vec<(usize, usize)> = unknowns
            .iter()
            .enumerate()
            .filter_map(|(j, u)| match u.camera {
                Some((t, k)) if t == ti && u.applies_to(&s.name) => Some((j, k)),
                _ => None,
            })
            .collect();
        let row = |line, p, quantity, measured, sd, predicted: f64| FitResidual {
            specimen: s.name.clone(),
            file: test.file.clone(),
            line,
            pressure_kpa: p,
            quantity,
            measured,
            sd,
            predicted,
            residual_sd: (measured - predicted) / sd,
        };
        match &test.data {
            TestData::Markers { camera, rows } => {
                let mut camera = *camera;
                if let Some(c) = &mut camera {
                    for &(j, k) in &cam {
                        match k {
                            0 => c.angle_deg = theta[j],
                            1 => c.x_mm = theta[j],
                            _ => c.z_mm = theta[j],
                        }
                    }
                }
                for r in rows {
                    at(&mut cache, r.pressure_kpa, out, &test.file, r.line)?;
                    let a = &cache[&bits(r.pressure_kpa)];
                    let site = site_at(&lengths, r.s_mm);
                    let (q, dq) = points_and_tangents(
                        &finger,
                        &a.solution.coefficients,
                        &a.dk,
                        &[Some(site)],
                    )?;
                    let (mut q, mut dq): ([f64; 2], Vec<[f64; 2]>) =
                        (q[0], dq.iter().map(|d| d[0]).collect());
                    // the camera's own columns: camera = R(-a) (finger - o)
                    let mut dcam: Vec<(usize, [f64; 2])> = Vec::new();
                    if let Some(c) = camera {
                        q = c.to_camera(q);
                        let (sn, cs) = (-c.angle_deg.to_radians()).sin_cos();
                        for d in &mut dq {
                            *d = [cs * d[0] - sn * d[1], sn * d[0] + cs * d[1]];
                        }
                        // d/da of R(-a) v is (q_z, -q_x) per radian; the
                        // offsets move every point by -R(-a) e
                        let per_degree = std::f64::consts::PI / 180.0;
                        for &(j, k) in &cam {
                            let d = match k {
                                0 => [per_degree * q[1], -per_degree * q[0]],
                                1 => [-cs, -sn],
                                _ => [sn, -cs],
                            };
                            dcam.push((j, d));
                        }
                    }
                    for (i, quantity) in ["x_mm", "z_mm"].into_iter().enumerate() {
                        let d: Vec<f64> = dq.iter().map(|v| v[i]).collect();
                        push(
                            out,
                            row(
                                r.line,
                                r.pressure_kpa,
                                quantity,
                                r.point_mm[i],
                                r.sd_mm,
                                q[i],
                            ),
                            &d,
                        );
                        if let Some(last) = out.jacobian.last_mut() {
                            for &(j, dv) in &dcam {
                                last[j] = -dv[i] / r.sd_mm;
                            }
                        }
                    }
                }
            }
            TestData::Radius(rows) => {
                for r in rows {
                    at(&mut cache, r.pressure_kpa, out, &test.file, r.line)?;
                    let a = &cache[&bits(r.pressure_kpa)];
                    let sites: Vec<Option<Site>> = shape_sites(&lengths, per);
                    let (pts, dpts) =
                        points_and_tangents(&finger, &a.solution.coefficients, &a.dk, &sites)?;
                    let (circle, d) = radius_tangents(&pts, &dpts).ok_or_else(|| {
                        SolveError::from(super::options::inconsistent(
                            "radius",
                            format!(
                                "{}:{}: the model's mid-plane at {} kPa is straight: no circle fits it, so the radius has no derivative",
                                test.file, r.line, r.pressure_kpa
                            ),
                        ))
                    })?;
                    push(
                        out,
                        row(
                            r.line,
                            r.pressure_kpa,
                            "radius_mm",
                            r.radius_mm,
                            r.sd_mm,
                            circle.radius,
                        ),
                        &d,
                    );
                }
            }
            TestData::Force(rows) => {
                for r in rows {
                    at(&mut cache, r.pressure_kpa, out, &test.file, r.line)?;
                    let a = &cache[&bits(r.pressure_kpa)];
                    let u = unit(r.axis);
                    let s0 = u[0] * a.solution.tip[0] + u[1] * a.solution.tip[1];
                    let problem = TargetProblem {
                        base: a.load,
                        direction: u,
                        weights: u,
                        target: s0 + r.displacement_mm,
                    };
                    let mut solver = Solver::new(&finger);
                    let traced = solver.trace_target(
                        &problem,
                        &a.solution.coefficients,
                        0.0,
                        1e-10,
                        &opts,
                    )?;
                    out.target_solves += 1;
                    let (solution, lambda) = match traced {
                        Traced::Reached {
                            solution, lambda, ..
                        } => (solution, lambda),
                        _ => {
                            return Err(SolveError::TargetNotReached {
                                target: Field::key("displacement_mm"),
                                value: r.displacement_mm,
                                reached: 0.0,
                                detail: format!(
                                    "{}:{}: the model's tip does not reach the displacement from its unloaded position",
                                    test.file, r.line
                                ),
                            })
                        }
                    };
                    if solution
                        .warnings
                        .iter()
                        .any(crate::error::Warning::is_validity)
                    {
                        out.outside_model += 1;
                    }
                    let mut with_target = params.clone();
                    with_target.push(Param::Target);
                    let ts = finger.target_sensitivities(
                        &act,
                        &solution,
                        &problem,
                        lambda,
                        &with_target,
                    )?;
                    let dl_dt = ts.rows[params.len()].lambda.unwrap_or(0.0);
                    let d: Vec<f64> = ts.rows[..params.len()]
                        .iter()
                        .zip(&a.tip_rows)
                        .map(|(row, tip)| {
                            row.lambda.unwrap_or(0.0) + dl_dt * (u[0] * tip[0] + u[1] * tip[1])
                        })
                        .collect();
                    push(
                        out,
                        row(
                            r.line,
                            r.pressure_kpa,
                            "force_n",
                            r.force_n,
                            r.sd_of_mean(),
                            lambda,
                        ),
                        &d,
                    );
                }
            }
        }
    }
    Ok(())
}

/// Every specimen's rows at `theta`. The specimens are independent: they
/// are solved in parallel and joined in their order (the first failure in
/// that order is the answer), as a loop over them would give.
pub(crate) fn evaluate(
    manifest: &crate::measure::Manifest,
    unknowns: &[Unknown],
    theta: &[f64],
) -> Result<Evaluation, SolveError> {
    evaluate_observed(manifest, unknowns, theta, &|| {})
}

/// A row at whose pressure the model does not solve, named by its file
/// and line (a rejected input or a cancelled run stays as it is). In the
/// fit's trial steps this is a rejected step; at the start, nothing can
/// be fitted until the row is left out.
fn unsolved_row(e: SolveError, file: &str, line: usize, p: f64) -> SolveError {
    match e {
        SolveError::Input(_) | SolveError::Cancelled => e,
        e => super::options::inconsistent(
            "pressure_kpa",
            format!(
                "{file}:{line}: the model does not solve at {} kPa with these parameters ({e}); leave the row out to calibrate (`fpc compare` lists every row the model cannot predict)",
                Num(p)
            ),
        )
        .into(),
    }
}

/// [`evaluate`], calling `solved` as each specimen is done (whether or
/// not it failed), on the thread that solved it.
pub(crate) fn evaluate_observed(
    manifest: &crate::measure::Manifest,
    unknowns: &[Unknown],
    theta: &[f64],
    solved: &(dyn Fn() + Sync),
) -> Result<Evaluation, SolveError> {
    let parts = crate::cancel::par_map(&manifest.specimens, |s| {
        let mut e = Evaluation::default();
        let done = evaluate_specimen(s, unknowns, theta, &mut e).map(|()| e);
        solved();
        done
    });
    let mut out = Evaluation::default();
    for part in parts {
        let e = part?;
        out.rows.extend(e.rows);
        out.jacobian.extend(e.jacobian);
        out.solves += e.solves;
        out.target_solves += e.target_solves;
        out.outside_model += e.outside_model;
    }
    Ok(out)
}

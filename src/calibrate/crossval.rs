//! Leave-one-pressure-out prediction errors: for every pressure of the
//! data, the fit again without the rows at that pressure (started from
//! the full fit), and those rows predicted by it. A model that only
//! absorbs the data predicts its left-out pressures badly; a right model
//! with honest standard deviations predicts them at about one standard
//! deviation.

use serde::Serialize;

use super::driver::run;
use super::params::{enough_values, Unknown};
use super::progress::Tracker;
use super::residuals::evaluate;
use crate::measure::{total, Manifest, TestData};
use crate::num::Num;
use crate::solve_error::SolveError;

/// The rows at one pressure, predicted by the fit without them.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct HeldOut {
    /// The pressure left out (kPa).
    pub pressure_kpa: f64,
    /// Residuals at that pressure.
    pub points: usize,
    /// Their chi-square under the fit without them.
    pub chi_square: f64,
    /// Root mean square of their residuals in standard deviations.
    pub rms_sd: f64,
    /// The unknowns fitted without them.
    pub values: Vec<f64>,
    /// Why there is no prediction (a failed fit or solve).
    pub failure: Option<String>,
}

/// Every pressure left out in turn.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CrossValidation {
    /// One entry per distinct pressure, ascending.
    pub held_out: Vec<HeldOut>,
    /// The chi-square of every held-out residual.
    pub chi_square: f64,
    /// How many.
    pub points: usize,
    /// Root mean square in standard deviations over all of them.
    pub rms_sd: f64,
}

fn key(p: f64) -> u64 {
    (p + 0.0).to_bits()
}

/// `manifest` without (`keep = false`) or with only (`true`) the rows at `p`.
fn filtered(manifest: &Manifest, p: f64, keep: bool) -> Manifest {
    let mut m = manifest.clone();
    let at = |q: f64| (key(q) == key(p)) == keep;
    for s in &mut m.specimens {
        for t in &mut s.tests {
            match &mut t.data {
                TestData::Markers { rows, .. } => rows.retain(|r| at(r.pressure_kpa)),
                TestData::Radius(rows) => rows.retain(|r| at(r.pressure_kpa)),
                TestData::Force(rows) => rows.retain(|r| at(r.pressure_kpa)),
            }
        }
    }
    m
}

/// The distinct pressures of `manifest`, ascending.
pub(crate) fn pressures(manifest: &Manifest) -> Vec<f64> {
    let mut ps: Vec<f64> = Vec::new();
    for t in manifest.specimens.iter().flat_map(|s| &s.tests) {
        let rows: Vec<f64> = match &t.data {
            TestData::Markers { rows, .. } => rows.iter().map(|r| r.pressure_kpa).collect(),
            TestData::Radius(rows) => rows.iter().map(|r| r.pressure_kpa).collect(),
            TestData::Force(rows) => rows.iter().map(|r| r.pressure_kpa).collect(),
        };
        for p in rows {
            if !ps.iter().any(|&q| key(q) == key(p)) {
                ps.push(p);
            }
        }
    }
    ps.sort_by(f64::total_cmp);
    ps
}

/// Leave-one-pressure-out over `manifest`, each refit started at `theta`.
/// Returns the record and the solves it took (equilibria, targets). The
/// refits are independent and run in parallel; the record is the one a
/// loop over the pressures in order gives. Each refit finished is
/// reported to `progress`, where there is one.
pub(crate) fn cross_validate(
    manifest: &Manifest,
    unknowns: &[Unknown],
    theta: &[f64],
    max_iterations: usize,
    progress: Option<&Tracker<'_>>,
) -> (CrossValidation, usize, usize) {
    let refits = crate::cancel::par_map(&pressures(manifest), |&p| {
        let refit = held_out_at(manifest, unknowns, theta, max_iterations, p);
        if let Some(t) = progress {
            t.update(|p| p.refits_done += 1);
        }
        refit
    });
    let solves = refits.iter().map(|r| r.1).sum();
    let targets = refits.iter().map(|r| r.2).sum();
    let held_out: Vec<HeldOut> = refits.into_iter().map(|r| r.0).collect();
    let chi_square = total(held_out.iter().map(|h| h.chi_square));
    let points: usize = held_out.iter().map(|h| h.points).sum();
    (
        CrossValidation {
            held_out,
            chi_square,
            points,
            rms_sd: (chi_square / points.max(1) as f64).sqrt(),
        },
        solves,
        targets,
    )
}

/// [`cross_validate`]'s fit without the rows at pressure `p` and its
/// prediction of them, with the solves it took (equilibria, targets).
fn held_out_at(
    manifest: &Manifest,
    unknowns: &[Unknown],
    theta: &[f64],
    max_iterations: usize,
    p: f64,
) -> (HeldOut, usize, usize) {
    let (mut solves, mut targets) = (0, 0);
    let without = filtered(manifest, p, false);
    let only = filtered(manifest, p, true);
    // leaving out the only pressures that carry enough data leaves
    // nothing to fit: a failure, not the full fit presented as a refit
    let result = enough_values(
        &without,
        unknowns.len(),
        &format!("the data without {} kPa", Num(p)),
    )
    .map_err(SolveError::from)
    .and_then(|()| run(&without, unknowns, theta.to_vec(), max_iterations))
    .and_then(|r| {
        solves += r.solves;
        targets += r.target_solves;
        let values = r.min.theta;
        let e = evaluate(&only, unknowns, &values)?;
        solves += e.solves;
        targets += e.target_solves;
        Ok((values, e.rows))
    });
    let held = match result {
        Ok((values, rows)) => {
            let chi = total(rows.iter().map(|r| r.residual_sd * r.residual_sd));
            HeldOut {
                pressure_kpa: p,
                points: rows.len(),
                chi_square: chi,
                rms_sd: (chi / rows.len().max(1) as f64).sqrt(),
                values,
                failure: None,
            }
        }
        Err(e) => HeldOut {
            pressure_kpa: p,
            points: 0,
            chi_square: 0.0,
            rms_sd: 0.0,
            values: Vec::new(),
            failure: Some(e.to_string()),
        },
    };
    (held, solves, targets)
}

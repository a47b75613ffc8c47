//! The calibration: the unknowns resolved, Levenberg-Marquardt over the
//! exact Jacobian, then the errors and the identifiability at the fit.

use super::crossval::{cross_validate, pressures};
use super::driver::run_observed;
use super::identify::analyse;
use super::options::{CalibrateOptions, MAX_HELD_OUT_PRESSURES};
use super::params::{enough_values, unknowns};
use super::progress::{CalibrateProgress, CalibrateStage, Tracker};
use super::record::{Calibration, FittedParameter, Reproduction};
use super::reproduce::reproduce;
use crate::measure::Manifest;
use crate::solve_error::SolveError;

/// Fits `options.fit` to every test of `manifest` by weighted least
/// squares (docs/calibration.md). Bad options or a parameter the manifest
/// cannot fit are [`SolveError::Input`] naming the field (`fit`,
/// `max_iterations`, `partition`); a data row at whose pressure the
/// model does not solve at the start is an input error on `pressure_kpa`
/// naming the row's file and line (leave the row out to calibrate). Nothing panics on user input, and no NaN
/// comes out: a residual or Jacobian entry that is not finite stops the
/// fit with an error.
pub fn calibrate(
    manifest: &Manifest,
    options: &CalibrateOptions,
) -> Result<Calibration, SolveError> {
    calibrate_with_progress(manifest, options, &|_| {})
}

/// [`calibrate`], handing `observer` a [`CalibrateProgress`] at every
/// change of stage, iteration, evaluation, specimen solved and
/// cross-validation refit finished (none before the options and the
/// manifest's parameters are checked). The observer is called from the
/// calibration's threads, one call at a time, and its counts never fall
/// from one call to the next; it should return quickly (store the event,
/// say), as the calibration waits for it.
pub fn calibrate_with_progress(
    manifest: &Manifest,
    options: &CalibrateOptions,
    observer: &(dyn Fn(&CalibrateProgress) + Sync),
) -> Result<Calibration, SolveError> {
    options.validate()?;
    let unknowns = unknowns(manifest, options)?;
    let n = unknowns.len();
    enough_values(manifest, n, "the manifest")?;
    if options.cross_validate {
        let held = pressures(manifest).len();
        if held > MAX_HELD_OUT_PRESSURES {
            return Err(crate::error::InputError::OutOfRange {
                field: crate::field::Field::key("cross_validate"),
                value: held as f64,
                rule: format!(
                    "the data have {held} distinct pressures; a cross-validation leaves out at most {MAX_HELD_OUT_PRESSURES} (one fit each)"
                ),
            }
            .into());
        }
    }
    let theta0: Vec<f64> = unknowns.iter().map(|u| u.start).collect();
    let tracker = Tracker::new(
        observer,
        CalibrateProgress::new(options.max_iterations, manifest.specimens.len()),
    );
    tracker.update(|_| {});
    let run = run_observed(
        manifest,
        &unknowns,
        theta0,
        options.max_iterations,
        Some(&tracker),
    )?;
    let (min, solves, target_solves, start_chi_square) = (
        run.min,
        run.solves,
        run.target_solves,
        Some(run.start_chi_square),
    );
    let cross_validation = options.cross_validate.then(|| {
        tracker.update(|p| {
            p.stage = CalibrateStage::CrossValidating;
            p.refits = pressures(manifest).len();
        });
        cross_validate(
            manifest,
            &unknowns,
            &min.theta,
            options.max_iterations,
            Some(&tracker),
        )
        .0
    });
    let names: Vec<String> = unknowns.iter().map(|u| u.label()).collect();
    let (identifiability, cov) = analyse(&min.point.j, &names);
    let chi_square = min.point.r.norm_squared();
    let m = min.point.r.len();
    let dof = m - n;
    let per_dof = chi_square / dof as f64;
    let parameters = unknowns
        .iter()
        .enumerate()
        .map(|(k, u)| {
            let se = cov.as_ref().map(|c| c[(k, k)].max(0.0).sqrt());
            let v = min.theta[k];
            FittedParameter {
                name: u.label(),
                key: u.key.clone(),
                specimen: u.specimen.clone(),
                start: u.start,
                value: v,
                standard_error: se,
                scaled_standard_error: se.map(|s| s * per_dof.sqrt()),
                lower: u.lower,
                upper: u.upper,
                at_bound: v <= u.lower || v >= u.upper,
            }
        })
        .collect();
    let correlation = cov.as_ref().map(|c| {
        (0..n)
            .map(|a| {
                (0..n)
                    .map(|b| c[(a, b)] / (c[(a, a)] * c[(b, b)]).sqrt())
                    .collect()
            })
            .collect()
    });
    let mut fit = Calibration {
        manifest: manifest.file.clone(),
        parameters,
        covariance: cov.map(|c| {
            (0..n)
                .map(|a| (0..n).map(|b| c[(a, b)]).collect())
                .collect()
        }),
        correlation,
        identifiability,
        chi_square,
        points: m,
        dof,
        chi_square_per_dof: per_dof,
        start_chi_square: start_chi_square.unwrap_or(chi_square),
        residuals: min.extra.rows,
        iterations: min.iterations,
        evaluations: min.evaluations,
        solves,
        target_solves,
        termination: min.termination,
        outside_model: min.extra.outside_model,
        cross_validation,
        reproduction: Reproduction::not_run(),
    };
    tracker.update(|p| p.stage = CalibrateStage::Checking);
    fit.reproduction = reproduce(manifest, &unknowns, &fit);
    Ok(fit)
}

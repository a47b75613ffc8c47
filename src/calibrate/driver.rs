//! The Levenberg-Marquardt run over a manifest's residuals: what a fit
//! and each leave-one-pressure-out refit share.

use nalgebra::{DMatrix, DVector};

use super::lm::{minimise, Minimum, Point};
use super::options::inconsistent;
use super::params::Unknown;
use super::progress::Tracker;
use super::residuals::{evaluate_observed, Evaluation};
use crate::measure::Manifest;
use crate::solve_error::SolveError;

/// The relative step at which the iterations stop.
pub const STEP_TOLERANCE: f64 = 1e-10;

/// A finished minimisation with its counts.
pub(crate) struct Run {
    pub min: Minimum<Evaluation>,
    pub solves: usize,
    pub target_solves: usize,
    pub start_chi_square: f64,
}

/// Levenberg-Marquardt over `manifest` from `theta0`.
pub(crate) fn run(
    manifest: &Manifest,
    unknowns: &[Unknown],
    theta0: Vec<f64>,
    max_iterations: usize,
) -> Result<Run, SolveError> {
    run_observed(manifest, unknowns, theta0, max_iterations, None)
}

/// [`run`], reporting its iterations, evaluations and specimens solved
/// to `progress` where there is one.
pub(crate) fn run_observed(
    manifest: &Manifest,
    unknowns: &[Unknown],
    theta0: Vec<f64>,
    max_iterations: usize,
    progress: Option<&Tracker<'_>>,
) -> Result<Run, SolveError> {
    let solved = || {
        if let Some(t) = progress {
            t.update(|p| p.specimens_solved += 1);
        }
    };
    let n = unknowns.len();
    let lower: Vec<f64> = unknowns.iter().map(|u| u.lower).collect();
    let upper: Vec<f64> = unknowns.iter().map(|u| u.upper).collect();
    let mut solves = 0;
    let mut target_solves = 0;
    let mut start_chi_square = None;
    let min = minimise(
        theta0,
        &lower,
        &upper,
        max_iterations,
        STEP_TOLERANCE,
        |theta| {
            let e = evaluate_observed(manifest, unknowns, theta, &solved);
            if let Some(t) = progress {
                t.update(|p| p.evaluations += 1);
            }
            let e = e?;
            solves += e.solves;
            target_solves += e.target_solves;
            let bad = e
                .rows
                .iter()
                .map(|r| r.residual_sd)
                .chain(e.jacobian.iter().flatten().copied())
                .any(|v| !v.is_finite());
            if bad {
                return Err(SolveError::from(inconsistent(
                    "fit",
                    "the model's residuals or their derivatives are not finite at these parameters"
                        .into(),
                )));
            }
            let p = point(&e, n);
            start_chi_square.get_or_insert(p.r.norm_squared());
            Ok((p, e))
        },
        |iterations, chi_square| {
            if let Some(t) = progress {
                t.update(|p| {
                    p.iterations = iterations;
                    p.chi_square = Some(chi_square);
                });
            }
        },
    )?;
    Ok(Run {
        start_chi_square: start_chi_square.unwrap_or_else(|| min.point.r.norm_squared()),
        min,
        solves,
        target_solves,
    })
}

fn point(e: &Evaluation, n: usize) -> Point {
    let m = e.rows.len();
    Point {
        r: DVector::from_iterator(m, e.rows.iter().map(|r| r.residual_sd)),
        j: DMatrix::from_fn(m, n, |i, k| e.jacobian[i][k]),
    }
}

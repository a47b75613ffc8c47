//! Choosing N for a tip accuracy: the CCM's error in N is large at the
//! paper's N = 8 (about 1 mm at the tip of a strongly curled finger), so a
//! user may ask for a tip tolerance instead of an element count.
//!
//! The partition is refined by doubling N. The error of the finer solution
//! is estimated by the change of the tip between N and 2N, which is the
//! Richardson estimate for a first-order method and an over-estimate for
//! faster convergence; it stays honest where convergence is irregular (the
//! ribs are resolved only once elements are shorter than the rib pitch).

use crate::actuator::Actuator;
use crate::blocks::Partition;
use crate::error::{positive, require, InputError, SolveError};
use crate::finger::{Finger, Load, Solution, SolveOptions};

/// Largest N the refinement tries.
pub const MAX_REFINED_ELEMENTS: usize = 512;

/// A solution at the N chosen for a tip tolerance.
#[derive(Debug, Clone, PartialEq)]
pub struct Refined {
    /// The solution at `elements`.
    pub solution: Solution,
    /// The number of equal elements used.
    pub elements: usize,
    /// Estimated tip error (mm): the tip's change from `elements / 2`.
    pub estimated_tip_error_mm: f64,
}

/// Solves `load` with equal elements, doubling N from `start` until the
/// estimated tip error is at most `tip_tol_mm`. `start` must lie in
/// [1, `MAX_REFINED_ELEMENTS` / 2] (at least one doubling). Fails with an
/// input error when `MAX_REFINED_ELEMENTS` cannot reach the tolerance.
pub fn solve_to_tip_tolerance(
    actuator: &Actuator,
    ribs: bool,
    load: &Load,
    tip_tol_mm: f64,
    start: usize,
    opts: &SolveOptions,
) -> Result<Refined, SolveError> {
    positive("tip_tol_mm", tip_tol_mm)?;
    let most = MAX_REFINED_ELEMENTS / 2;
    require(
        (1..=most).contains(&start),
        "partition.n",
        start as f64,
        format!("must lie in [1, {most}] to refine to a tip tolerance (N doubles up to {MAX_REFINED_ELEMENTS})"),
    )?;
    let lx = actuator.geometry().lx;
    let solve = |n: usize| -> Result<Solution, SolveError> {
        Finger::new(actuator, &Partition::equal(lx, n)?, ribs).solve(load, opts)
    };
    let mut n = start;
    let mut coarse = solve(n)?;
    let mut last_estimate = f64::INFINITY;
    while 2 * n <= MAX_REFINED_ELEMENTS {
        let fine = solve(2 * n)?;
        let est = (fine.tip[0] - coarse.tip[0]).hypot(fine.tip[1] - coarse.tip[1]);
        n *= 2;
        last_estimate = est;
        if est <= tip_tol_mm {
            return Ok(Refined {
                solution: fine,
                elements: n,
                estimated_tip_error_mm: est,
            });
        }
        coarse = fine;
    }
    Err(InputError::OutOfRange {
        field: "tip_tol_mm".into(),
        value: tip_tol_mm,
        rule: format!(
            "not reached with up to {MAX_REFINED_ELEMENTS} elements (estimated tip error there {last_estimate:.3e} mm)"
        ),
    }
    .into())
}

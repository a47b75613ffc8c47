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
use crate::error::{positive, require, InputError, SolveError, Warning};
use crate::finger::{Coefficients, Finger, Load, Solution, SolveOptions};
use crate::model::ModelId;

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
    model: ModelId,
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
        Finger::with_model(model, actuator, &Partition::equal(lx, n)?, ribs).solve(load, opts)
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

/// The automatic partition's result.
#[derive(Debug, Clone)]
pub struct AutoSolved {
    /// The solution on the chosen partition.
    pub solution: Solution,
    /// The partition chosen.
    pub partition: Partition,
    /// The finger built on it.
    pub finger: Finger,
    /// How many times elements were split after a solve.
    pub refinements: usize,
}

/// Largest number of elements the automatic partition uses.
pub const MAX_AUTO_ELEMENTS: usize = 1000;

/// Solves `load` on an automatic partition: element boundaries on the
/// material changes ([`Partition::material`], pieces at most `Lx / 8`),
/// then, while an element turns beyond the CCM's small-slope limit at the
/// solved state, that element is split in two and the finger solved again
/// from the previous state. Stops with the remaining findings on the
/// solution when [`MAX_AUTO_ELEMENTS`] would be exceeded.
pub fn solve_auto(
    model: ModelId,
    actuator: &Actuator,
    ribs: bool,
    load: &Load,
    opts: &SolveOptions,
) -> Result<AutoSolved, SolveError> {
    let lx = actuator.geometry().lx;
    let mut partition = Partition::material(actuator, ribs, lx / 8.0)?;
    let mut finger = Finger::with_model(model, actuator, &partition, ribs);
    let mut solution = finger.solve(load, opts)?;
    let mut refinements = 0;
    loop {
        let mut split = vec![false; partition.len()];
        for w in &solution.warnings {
            if let Warning::ElementSlope { element, .. } = w {
                split[*element] = true;
            }
        }
        let extra = split.iter().filter(|&&s| s).count();
        if extra == 0 || partition.len() + extra > MAX_AUTO_ELEMENTS {
            return Ok(AutoSolved {
                solution,
                partition,
                finger,
                refinements,
            });
        }
        // each half starts from its parent's raw coefficients
        let per = solution.coefficients.per_element();
        let mut guess = Vec::with_capacity((partition.len() + extra) * per);
        for (i, k) in solution.coefficients.iter().enumerate() {
            guess.extend_from_slice(k);
            if split[i] {
                guess.extend_from_slice(k);
            }
        }
        partition = partition.split(&split);
        finger = Finger::with_model(model, actuator, &partition, ribs);
        let guess = Coefficients::new(per, guess)?;
        solution = match finger.solve_from(load, &guess, opts) {
            Ok(s) => s,
            Err(_) => finger.solve(load, opts)?,
        };
        refinements += 1;
    }
}

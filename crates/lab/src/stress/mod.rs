//! Numerical stress test: seeded random scenes over a domain wider than
//! the model's validity, each solved with the library's defaults
//! (stability from the structured factorisation on, no shape sampling),
//! checked independently of the solver, and classified inside or outside
//! the validity envelope ([`inside_envelope`]).
//!
//! A case draws, from a fastrand stream fixed by the seed and the case
//! index:
//!
//! - the element model, uniform over [`fpc::ModelId::ALL`];
//! - the prestrain `eps0` uniform in [0.01, 0.6];
//! - the pressure: 0 (one case in five) or uniform in [0, 600] kPa, from
//!   the curled finger past flattening into reversed curvature;
//! - the tip load: none (three cases in ten), otherwise a magnitude
//!   `f F_ref` with `f` log-uniform in [1e-3, 30] and the force scale
//!   `F_ref = D / lx^2` of the drawn stack ([`force_scale`]); its direction
//!   is along +-X one time in seven, along +-Z one time in seven, and
//!   uniform otherwise (positive `Fx` pulls the finger straight, negative
//!   compresses it towards buckling, `Fz` folds it);
//! - the partition: automatic ([`fpc::Plan::Auto`]: boundaries on material
//!   changes, elements split until each is within the slope limit) in
//!   [`AUTO_FRACTION`] of the cases; otherwise N from
//!   [`STRESS_ELEMENT_COUNTS`] with weights that fall for the large counts,
//!   capped by [`StressConfig::max_elements`], and equal elements (three
//!   in ten, and always for N = 1) or lengths `r^u_i` with `u_i` uniform
//!   in [0, 1] (one element at each end of the range) and `r`
//!   log-uniform in [1, 100], normalised to `lx` ([`Partition::custom`]);
//! - the layer stack scaled by `s` log-uniform in [0.3, 3]; in about one
//!   case in three each lamina's thickness is further multiplied by its
//!   own factor, log-uniform in [0.5, 2], and the channel's heights
//!   within the fluidic layer are redrawn (fractions 0.15 to 0.95 of the
//!   layer's part above and below the mid-plane);
//! - ribs on or off.
//!
//! A draw that [`Actuator::new`] or [`Partition::custom`] rejects (the
//! mid-plane outside the fluidic layer, an element shorter than
//! [`MIN_ELEMENT_FRACTION`](fpc::partition::MIN_ELEMENT_FRACTION) `lx`) is an
//! expected outcome, not a failure: it is counted and the whole case is
//! drawn again, up to [`MAX_DRAWS`] times; a case whose every draw was
//! rejected is reported as rejected input.
//!
//! Checks on a returned solution, all independent of the solver's own
//! report: the raw gradient is recomputed with [`Finger::gradient`],
//! scaled per unknown by [`Finger::unknown_scales`], and its infinity norm
//! over [`Finger::stiffness_scale`] must be at most [`RESIDUAL_LIMIT`]; the
//! tip, end angle, energy and every coefficient must be finite, and the
//! tip and energy must agree with [`Finger::tip`] and the energy
//! [`Finger::gradient`] returns at the returned coefficients; the element
//! lengths must be the finger's and `stable` must say what
//! `negative_eigenvalues` says. A violation is a *silently wrong answer*.
//! Stability, for solutions on at most [`DENSE_CHECK_MAX_ELEMENTS`]
//! elements: the dense Hessian ([`Finger::hessian`], scaled by the unknown
//! scales and over the stiffness, a congruence that keeps the inertia) has
//! its eigenvalues counted by `fpc_newton`'s dense eigensolver below
//! `-tau` and below `+tau` ([`STABILITY_TOLERANCE`]); the structured
//! factorisation's count ([`Solution::negative_eigenvalues`]) must lie
//! between the two, otherwise the case is a *wrong stability* answer (an
//! unstable equilibrium reported as stable is the case that matters).
//! A panic anywhere (drawing, validation, solve, check) is caught and
//! reported: the library must never panic on user input. All three are
//! bugs.
//!
//! Conditioning, for solutions on at most [`CONDITIONING_MAX_ELEMENTS`]
//! elements (a dense `O(N^3)` eigenvalue problem): `lambda_min` of the
//! scaled Hessian and `G = max_i sum_j |H_ij|` its Gershgorin bound; the
//! case records `lambda_min / stiffness` and `conditioning = lambda_min /
//! G`, a lower bound on `1 / cond(H)` for a stable equilibrium.
//!
//! Validity: every solution carries the library's findings
//! ([`fpc::Warning::is_validity`]: element slope, mid-plane strain,
//! prestressed strain, self contact); a converged case with findings is
//! *warned*. Inside the envelope a case must converge without findings;
//! outside it may converge with its findings or fail with a typed reason.

mod check;
mod draw;
pub mod envelope;
mod inputs;
mod report;

pub use check::dense_negative_eigenvalues;
pub use inputs::{force_scale, inside_envelope, PartitionKey, StressInputs};
pub use report::{
    finding_name, reason_name, Quantiles, StressCase, StressOutcome, StressReport, Tally,
};

use check::check;
use draw::{draw_case, NoFinger};

use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use fpc::{Actuator, Finger, Partition, Solution, SolveError, SolveOptions};

/// Largest accepted recomputed residual, `||g_scaled||_inf` over the
/// stiffness scale (the solver's own tolerance is 1e-11).
pub const RESIDUAL_LIMIT: f64 = 1e-9;

/// Draws per case before it counts as rejected input.
pub const MAX_DRAWS: usize = 4;

/// Share of the cases solved on the automatic partition.
pub const AUTO_FRACTION: f64 = 0.4;

/// The fixed element counts drawn (the other cases use the automatic
/// partition), and their relative weights.
pub const STRESS_ELEMENT_COUNTS: [usize; 10] = [1, 2, 3, 4, 8, 16, 32, 64, 128, 256];
const ELEMENT_WEIGHTS: [f64; 10] = [10.0, 10.0, 10.0, 12.0, 14.0, 14.0, 12.0, 8.0, 6.0, 4.0];

/// Largest element count whose stability is checked against a dense
/// eigenvalue count (`O(N^3)`).
pub const DENSE_CHECK_MAX_ELEMENTS: usize = 64;

/// Largest element count whose conditioning is reported.
pub const CONDITIONING_MAX_ELEMENTS: usize = 32;

/// Eigenvalues of the scaled Hessian over the stiffness within this of
/// zero may be counted either way: the structured count must lie between
/// the dense counts below `-tau` and below `+tau`.
pub const STABILITY_TOLERANCE: f64 = 1e-9;

/// Validity checks per element when the stress test re-checks a solution
/// more finely than the solver does ([`StressCase::missed_findings`]).
pub const FINE_VALIDITY_SAMPLES: usize = 32;

/// Settings of a stress run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StressConfig {
    /// Seed of the case generator.
    pub seed: u64,
    /// Cases to run (fewer when the budget runs out).
    pub cases: usize,
    /// Wall-clock budget: no case starts after it is spent.
    pub budget: Duration,
    /// Largest fixed element count drawn (counts above it are never drawn;
    /// at least 1). The automatic partition is drawn whatever it is.
    pub max_elements: usize,
}

impl StressConfig {
    /// `cases` cases from `seed` within `budget`, every element count.
    pub fn new(seed: u64, cases: usize, budget: Duration) -> StressConfig {
        StressConfig {
            seed,
            cases,
            budget,
            max_elements: 256,
        }
    }
}

/// Runs `cases` stress cases from `seed` (every element count) until done,
/// `budget` is spent, or `progress(done, total)`, called after each case,
/// returns false (Ctrl-C in `fpc-lab stress`).
pub fn stress(
    seed: u64,
    cases: usize,
    budget: Duration,
    progress: impl FnMut(usize, usize) -> bool,
) -> StressReport {
    stress_with(&StressConfig::new(seed, cases, budget), progress)
}

/// [`stress`] with every setting.
pub fn stress_with(
    config: &StressConfig,
    mut progress: impl FnMut(usize, usize) -> bool,
) -> StressReport {
    let start = Instant::now();
    let mut out = Vec::with_capacity(config.cases);
    for index in 0..config.cases {
        if start.elapsed() >= config.budget {
            break;
        }
        out.push(run_case(config, index));
        if !progress(index + 1, config.cases) {
            break;
        }
    }
    StressReport {
        config: *config,
        elapsed: start.elapsed(),
        cases: out,
    }
}

/// Runs case `index` of a run from `seed` alone (to reproduce a case).
pub fn stress_case(seed: u64, index: usize, max_elements: usize) -> StressCase {
    let config = StressConfig {
        max_elements,
        ..StressConfig::new(seed, index + 1, Duration::MAX)
    };
    run_case(&config, index)
}

/// The inputs of case `index` of a run from `seed` (fixed element counts
/// up to `max_elements`) and the number of draws validation rejected
/// before them. When all [`MAX_DRAWS`] draws were rejected, the inputs are
/// the last draw's. Deterministic: the same arguments give the same inputs.
pub fn stress_inputs(seed: u64, index: usize, max_elements: usize) -> (StressInputs, usize) {
    let (inputs, rejected, _) = draw_case(seed, index, max_elements);
    (inputs, rejected.len())
}

/// The options of every solve: the defaults without shape sampling
/// (stability on, so `negative_eigenvalues` is counted).
fn solve_options() -> SolveOptions {
    SolveOptions {
        shape: false,
        stability: true,
        ..SolveOptions::default()
    }
}

/// Solves a case: on the automatic partition, or on the drawn one.
fn solve(inputs: &StressInputs, act: &Actuator) -> Result<(Finger, Solution, usize), SolveError> {
    let load = inputs.load();
    let opts = solve_options();
    if inputs.auto_partition {
        let a = fpc::PlannedFinger::builder(act)
            .model(inputs.model)
            .ribs(inputs.ribs)
            .plan(fpc::Plan::Auto)
            .build()?
            .solve(&load, &opts)?;
        Ok((a.finger, a.solution, a.splits))
    } else {
        let part = Partition::custom(inputs.lengths.clone(), inputs.geometry.lx)?;
        let finger = Finger::with_model(inputs.model, act, &part, inputs.ribs);
        let sol = finger.solve(&load, &opts)?;
        Ok((finger, sol, 0))
    }
}

fn run_case(config: &StressConfig, index: usize) -> StressCase {
    let t0 = Instant::now();
    let (inputs, rejected_fields, act) = draw_case(config.seed, index, config.max_elements);
    let mut c = StressCase {
        index,
        inside_envelope: inside_envelope(&inputs),
        inputs,
        rejected_draws: rejected_fields.len(),
        rejected_fields,
        outcome: StressOutcome::Converged,
        solved_elements: None,
        refinements: None,
        iterations: None,
        continuation_steps: None,
        steps: None,
        residual: None,
        negative_eigenvalues: None,
        dense_negative: None,
        min_eig: None,
        conditioning: None,
        max_rotation: None,
        findings: Vec::new(),
        notes: Vec::new(),
        missed_findings: Vec::new(),
        seconds: 0.0,
    };
    let act = match act {
        Ok(a) => a,
        Err(NoFinger::Rejected(error)) => {
            c.outcome = StressOutcome::Rejected { error };
            c.seconds = t0.elapsed().as_secs_f64();
            return c;
        }
        Err(NoFinger::Panicked(message)) => {
            c.outcome = StressOutcome::Panicked { message };
            c.seconds = t0.elapsed().as_secs_f64();
            return c;
        }
    };
    let load = c.inputs.load();
    let result = catch_unwind(AssertUnwindSafe(|| match solve(&c.inputs, &act) {
        Ok((finger, sol, refinements)) => {
            let m = check(&finger, &load, &sol);
            Ok((sol, refinements, m))
        }
        Err(e) => Err(e),
    }));
    match result {
        Err(p) => {
            c.outcome = StressOutcome::Panicked {
                message: fpc::cancel::panic_text(&*p),
            };
        }
        Ok(Err(SolveError::NotConverged {
            reason,
            iterations,
            relative_residual,
            element,
            ..
        })) => {
            c.iterations = Some(iterations);
            c.outcome = StressOutcome::Failed {
                reason,
                element,
                relative_residual,
            };
        }
        Ok(Err(
            e @ (SolveError::TargetNotReached { .. }
            | SolveError::NotOnPath { .. }
            | SolveError::Cancelled),
        )) => {
            // the stress run never cancels
            c.outcome = StressOutcome::SilentlyWrong {
                what: format!("a plain solve reported a target or a cancellation: {e}"),
            };
        }
        Ok(Err(SolveError::Input(e))) => {
            c.outcome = StressOutcome::Rejected {
                error: format!("at solve: {e}"),
            };
        }
        Ok(Ok((sol, refinements, m))) => {
            c.solved_elements = Some(sol.coefficients.elements());
            c.refinements = Some(refinements);
            c.iterations = Some(sol.report.iterations);
            c.continuation_steps = Some(sol.report.continuation_steps);
            c.steps = Some(sol.report.steps);
            c.residual = Some(m.residual);
            c.negative_eigenvalues = sol.negative_eigenvalues;
            c.dense_negative = m.dense_negative;
            c.min_eig = m.min_eig;
            c.conditioning = m.conditioning;
            c.max_rotation = Some(m.max_rotation).filter(|r| r.is_finite());
            c.findings = m.findings;
            c.notes = m.notes;
            c.missed_findings = m.missed;
            if let Some(what) = m.wrong {
                c.outcome = StressOutcome::SilentlyWrong { what };
            } else if let (Some(reported), Some((below, within))) =
                (sol.negative_eigenvalues, m.dense_negative)
            {
                if reported < below || reported > within {
                    c.outcome = StressOutcome::WrongStability {
                        reported,
                        below,
                        within,
                    };
                }
            }
        }
    }
    c.seconds = t0.elapsed().as_secs_f64();
    c
}

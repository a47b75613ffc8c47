//! The plans the integration tests solve often, each one call through the
//! front door (`PlannedFinger`): included by `#[path]` where used.

#![allow(dead_code)] // each test crate uses some of them

use fpc::plan::Refinement;
use fpc::{Actuator, Load, ModelId, Plan, PlannedFinger, SolveError, SolveOptions, Solved};

/// A solve on the automatic partition.
pub fn solve_auto(
    model: ModelId,
    act: &Actuator,
    ribs: bool,
    load: &Load,
    opts: &SolveOptions,
) -> Result<Solved, SolveError> {
    PlannedFinger::builder(act)
        .model(model)
        .ribs(ribs)
        .plan(Plan::Auto)
        .build()?
        .solve(load, opts)
}

/// `load` solved to `tip_tol_mm`.
pub fn solve_to_tip_tolerance(
    model: ModelId,
    act: &Actuator,
    ribs: bool,
    load: &Load,
    tip_tol_mm: f64,
    start: Option<usize>,
    opts: &SolveOptions,
) -> Result<Solved, SolveError> {
    PlannedFinger::builder(act)
        .model(model)
        .ribs(ribs)
        .plan(Plan::TipTolerance { tip_tol_mm, start })
        .build()?
        .solve(load, opts)
}

/// `plan`'s levels solved.
pub fn refine(
    act: &Actuator,
    ribs: bool,
    load: &Load,
    plan: &Refinement,
    opts: &SolveOptions,
) -> Result<Solved, SolveError> {
    PlannedFinger::builder(act)
        .ribs(ribs)
        .refinement(plan)
        .build()?
        .solve(load, opts)
}

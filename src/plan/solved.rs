//! The answer of a planned solve: the solution, the finger it is on and
//! the refinement's record.

use std::any::Any;
use std::sync::Arc;

use crate::error::Warning;
use crate::finger::{Finger, Solution};

use super::refinement::RefinementRecord;

/// A solve of a [`PlannedFinger`](crate::PlannedFinger), whatever its plan.
#[derive(Debug, Clone)]
pub struct Solved {
    /// The solution (on the finest partition of a refinement).
    pub solution: Solution,
    /// The finger the solution is on (its partition: the fixed one, the
    /// finest level's, or the automatic partition as chosen).
    pub finger: Finger,
    /// The refinement's levels and best tip, for a tip tolerance and
    /// nested levels; `None` for a single partition.
    pub refinement: Option<RefinementRecord>,
    /// How many rounds of splits the automatic partition took: splits of
    /// the elements beyond the slope limit after a solve, and halvings of
    /// a start that did not solve (0 for the other plans).
    pub splits: usize,
    /// The [`PlannedFinger`](crate::PlannedFinger) solved, when a scene
    /// keeps it: a nearby scene on the same finger (a sweep over loads)
    /// solves on it again instead of building its fingers anew
    /// ([`crate::scene::Scene::solve_warm`]). Held as `Any` because the
    /// planner sits above this module and returns it.
    pub(crate) planned: Option<Arc<dyn Any + Send + Sync>>,
}

impl Solved {
    pub(super) fn single(solution: Solution, finger: &Finger) -> Solved {
        Solved {
            solution,
            finger: finger.clone(),
            refinement: None,
            splits: 0,
            planned: None,
        }
    }

    /// Elements of the partition the solution is on.
    pub fn elements(&self) -> usize {
        self.finger.len()
    }

    /// The best tip (mm, finger frame): extrapolated when the refinement
    /// extrapolates, else the solution's.
    pub fn tip(&self) -> [f64; 2] {
        self.refinement
            .as_ref()
            .map_or(self.solution.tip, |r| r.tip)
    }

    /// The best end angle (rad), like [`Solved::tip`].
    pub fn end_angle(&self) -> f64 {
        self.refinement
            .as_ref()
            .map_or(self.solution.end_angle, |r| r.end_angle)
    }

    /// Estimated distance of [`Solved::tip`] from the N -> infinity limit
    /// (mm): a refinement's estimate, `None` without one.
    pub fn estimated_tip_error_mm(&self) -> Option<f64> {
        self.refinement
            .as_ref()
            .and_then(|r| r.estimated_tip_error_mm)
    }

    /// Newton iterations: over every level of a refinement (whose finest
    /// level's final solve, from its own converged state, often takes
    /// none), else the solution's.
    pub fn iterations(&self) -> usize {
        self.refinement
            .as_ref()
            .map_or(self.solution.report.iterations, |r| r.iterations())
    }

    /// True when [`Solved::tip`] is extrapolated.
    pub fn is_extrapolated(&self) -> bool {
        self.refinement
            .as_ref()
            .is_some_and(RefinementRecord::is_extrapolated)
    }

    /// The solution's warnings (findings and the actuator's notes).
    pub fn warnings(&self) -> &[Warning] {
        &self.solution.warnings
    }

    /// True when no warning puts the answer outside the model
    /// ([`Warning::is_validity`], [`Solution::is_within_model`]).
    pub fn is_valid(&self) -> bool {
        self.solution.is_within_model()
    }
}

//! The automatic partition ([`crate::Plan::Auto`]): element boundaries on
//! the material changes (halved while that start does not solve), then
//! every element that turns beyond the CCM's
//! small-slope limit at the solved state split in two and the finger
//! solved again from the previous state, until no element is beyond the
//! limit, a split meets a fold or does not solve, or a bound is reached
//! (docs/model.md section 8, docs/stress.md "Folds end the automatic
//! partition" and "A split that does not solve").

use super::solved::Solved;
use crate::actuator::Actuator;
use crate::coefficients::Coefficients;
use crate::error::{InputError, Warning};
use crate::finger::{Finger, Load, Solution, SolveOptions, Solver};
use crate::model::ModelId;
use crate::partition::Partition;
use crate::solve_error::SolveError;

/// Largest number of elements the automatic partition uses.
pub const MAX_AUTO_ELEMENTS: usize = 1000;

/// Most rounds of splits the automatic partition takes. Before the fold
/// rule ([`FOLD_TURN_RATIO`]), a finger that split one element or two per
/// round climbed towards [`MAX_AUTO_ELEMENTS`] for up to 77 s and ended
/// beyond the slope limit either way (docs/stress.md, "Shifts on badly
/// scaled chains"); since, the stress set's automatic partitions take at
/// most 9 rounds, and this bound is the backstop.
pub const MAX_AUTO_SPLITS: usize = 64;

/// A split after which one half still turns at least this fraction of its
/// parent's turn beyond the slope limit has met a fold: the turn gathers
/// in one element however short it is, and the automatic partition stops
/// there. Halving a smooth bend leaves each half about half the turn; in
/// the stress set a half kept 0.9 or more of its parent's turn only on
/// fingers already beyond the strain limits, which no partition clears
/// (docs/stress.md, "Folds end the automatic partition").
pub const FOLD_TURN_RATIO: f64 = 0.9;

/// How many times the automatic partition halves every element of its
/// start when the start does not solve from rest. On the stress set, 35
/// automatic partitions failed on their start; halved once, 12 of them
/// solve, halved twice 2 more, and halving further rescued none
/// (docs/stress.md, "A start that does not solve").
pub const START_HALVINGS: usize = 2;

/// Each element's turn beyond the slope limit at a solution (degrees, 0
/// for an element within it).
fn slope_turns(solution: &Solution, elements: usize) -> Vec<f64> {
    let mut turns = vec![0.0; elements];
    for w in &solution.warnings {
        if let Warning::ElementSlope {
            element, degrees, ..
        } = w
        {
            turns[*element] = *degrees;
        }
    }
    turns
}

/// Where the halves of the elements turning beyond the limit land once
/// they are split: each first half's index in the split partition, with
/// its parent's turn (degrees).
fn split_halves(turns: &[f64]) -> Vec<(usize, f64)> {
    let mut halves = Vec::new();
    let mut at = 0;
    for &t in turns {
        if t > 0.0 {
            halves.push((at, t));
            at += 1;
        }
        at += 1;
    }
    halves
}

/// The fold a split of the last round met, if any: `halves` holds the
/// index of each split element's first half and the parent's turn. Of
/// several, the half that kept the largest share of its parent's turn.
fn fold(halves: &[(usize, f64)], turns: &[f64]) -> Option<Warning> {
    let mut found: Option<(f64, Warning)> = None;
    for &(i, parent) in halves {
        let (element, degrees) = if turns[i + 1] > turns[i] {
            (i + 1, turns[i + 1])
        } else {
            (i, turns[i])
        };
        let share = degrees / parent;
        if share >= FOLD_TURN_RATIO && found.as_ref().is_none_or(|(s, _)| share > *s) {
            let w = Warning::PartitionFold {
                element,
                degrees,
                parent,
                limit: FOLD_TURN_RATIO,
            };
            found = Some((share, w));
        }
    }
    found.map(|(_, w)| w)
}

/// The automatic partition's start, built: the implementation of
/// [`crate::Plan::Auto`].
#[derive(Debug, Clone)]
pub(crate) struct Auto {
    model: ModelId,
    actuator: Actuator,
    ribs: bool,
    partition: Partition,
    finger: Finger,
}

impl Auto {
    /// Element boundaries on the material changes
    /// ([`Partition::material`], pieces at most `Lx / 8`).
    pub(crate) fn new(model: ModelId, actuator: &Actuator, ribs: bool) -> Result<Auto, InputError> {
        let lx = actuator.geometry().lx;
        let partition = Partition::material(actuator, ribs, lx / 8.0)?;
        let finger = Finger::with_model(model, actuator, &partition, ribs);
        Ok(Auto {
            model,
            actuator: actuator.clone(),
            ribs,
            partition,
            finger,
        })
    }

    /// The finger of the starting partition.
    pub(crate) fn finger(&self) -> &Finger {
        &self.finger
    }

    /// Solves `load` on the starting partition (with every element halved,
    /// up to [`START_HALVINGS`] times, while it does not solve from rest),
    /// then, while an element
    /// turns beyond the CCM's small-slope limit at the solved state, that
    /// element is split in two and the finger solved again from the
    /// previous state. Stops with the remaining findings on the solution
    /// at a fold (a half that kept [`FOLD_TURN_RATIO`] of its parent's
    /// turn; the solution then carries the note
    /// [`Warning::PartitionFold`]), when [`MAX_AUTO_ELEMENTS`] would be exceeded, or after
    /// [`MAX_AUTO_SPLITS`] rounds of splits.
    ///
    /// Where a split partition fails, the whole refinement is taken again
    /// with a chain's shifted steps as the shift gives them (not doubled):
    /// doubled steps can end a level on another equilibrium, whose splits
    /// then ask for a partition that neither way solves, where the
    /// path before them converged (docs/stress.md, "Shifted steps doubled
    /// along a chain"). Where a split partition does not converge that way
    /// either, the answer is the last partition that solved, with its
    /// findings and the note [`Warning::PartitionSplitFailed`]
    /// (docs/stress.md, "A split that does not solve"); a start that does
    /// not solve however halved, or a cancelled solve, is an error.
    pub(crate) fn solve(&self, load: &Load, opts: &SolveOptions) -> Result<Solved, SolveError> {
        match self.refine(load, opts, true) {
            // (a Ctrl-C is not taken again)
            Err(Stop::Split(e, first)) if !matches!(e, SolveError::Cancelled) => {
                match self.refine(load, opts, false) {
                    Ok(solved) => Ok(solved),
                    Err(Stop::Split(SolveError::NotConverged { .. }, second)) => Ok(*second),
                    Err(Stop::Start(SolveError::NotConverged { .. })) => Ok(*first),
                    Err(Stop::Start(e) | Stop::Split(e, _)) => Err(e),
                }
            }
            Ok(solved) => Ok(solved),
            Err(Stop::Start(e) | Stop::Split(e, _)) => Err(e),
        }
    }

    /// [`Auto::solve`] with a chain's shifted steps doubled or not; an
    /// error says whether it was a solve of a split partition.
    fn refine(
        &self,
        load: &Load,
        opts: &SolveOptions,
        double_shifted: bool,
    ) -> Result<Solved, Stop> {
        let solve = |finger: &Finger, guess: Option<&Coefficients>| {
            let mut solver = Solver::new(finger);
            if !double_shifted {
                solver.keep_shifted_steps();
            }
            solver.solve(load, guess, opts)
        };
        let (model, actuator, ribs) = (self.model, &self.actuator, self.ribs);
        let mut partition = self.partition.clone();
        let mut finger = self.finger.clone();
        let mut refinements = 0;
        // a start that does not solve from rest is halved, at most
        // START_HALVINGS times
        let mut solution = loop {
            match solve(&finger, None) {
                Ok(s) => break s,
                Err(e) => {
                    let retry = matches!(e, SolveError::NotConverged { .. })
                        && refinements < START_HALVINGS
                        && 2 * partition.len() <= MAX_AUTO_ELEMENTS;
                    if !retry {
                        return Err(Stop::Start(e));
                    }
                    partition = partition.split(&vec![true; partition.len()]);
                    finger = Finger::with_model(model, actuator, &partition, ribs);
                    refinements += 1;
                }
            }
        };
        // the last round's splits: each first half's index, its parent's turn
        let mut halves: Vec<(usize, f64)> = Vec::new();
        loop {
            let turns = slope_turns(&solution, partition.len());
            let split: Vec<bool> = turns.iter().map(|&t| t > 0.0).collect();
            let extra = split.iter().filter(|&&s| s).count();
            let fold = fold(&halves, &turns);
            let stop = extra == 0
                || fold.is_some()
                || partition.len() + extra > MAX_AUTO_ELEMENTS
                || refinements == MAX_AUTO_SPLITS;
            if stop {
                solution.warnings.extend(fold);
                return Ok(solved(solution, finger, refinements));
            }
            let guess = solution.coefficients.split(&split);
            halves = split_halves(&turns);
            let next = partition.split(&split);
            let next_finger = Finger::with_model(model, actuator, &next, ribs);
            let next_solution = match solve(&next_finger, Some(&guess)) {
                Ok(s) => s,
                Err(_) => match solve(&next_finger, None) {
                    Ok(s) => s,
                    Err(e) => {
                        // the last partition that solved, with a note
                        solution.warnings.push(Warning::PartitionSplitFailed {
                            elements: next.len(),
                            kept: partition.len(),
                            reason: e.to_string(),
                        });
                        let last = solved(solution, finger, refinements);
                        return Err(Stop::Split(e, Box::new(last)));
                    }
                },
            };
            (partition, finger, solution) = (next, next_finger, next_solution);
            refinements += 1;
        }
    }
}

/// Why [`Auto::refine`] stopped without an answer.
enum Stop {
    /// The starting partition did not solve.
    Start(SolveError),
    /// A split partition did not solve: the error, and the last partition
    /// that solved, with the note [`Warning::PartitionSplitFailed`].
    Split(SolveError, Box<Solved>),
}

/// The automatic partition's answer on `finger` after `splits` rounds.
fn solved(solution: Solution, finger: Finger, splits: usize) -> Solved {
    Solved {
        solution,
        finger,
        refinement: None,
        splits,
        planned: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Halves are found where [`Partition::split`] puts them, and a fold is
    /// a half that keeps [`FOLD_TURN_RATIO`] of its parent's turn.
    #[test]
    fn halves_follow_the_split_and_a_kept_turn_is_a_fold() {
        let turns = [0.0, 50.0, 0.0, 0.0, 80.0];
        let halves = split_halves(&turns);
        assert_eq!(halves, [(1, 50.0), (5, 80.0)]);
        let split: Vec<bool> = turns.iter().map(|&t| t > 0.0).collect();
        let partition = Partition::custom(vec![1.0, 2.0, 3.0, 4.0, 5.0], 15.0)
            .unwrap()
            .split(&split);
        for &(i, _) in &halves {
            assert_eq!(partition.lengths()[i], partition.lengths()[i + 1]);
        }
        assert_eq!(partition.lengths()[5], 2.5);
        // halving a smooth bend: each half about half the turn
        let mut after = [0.0; 7];
        after[5] = 46.0;
        assert_eq!(fold(&halves, &after), None);
        // the second half keeps 90 % of the 80 degrees
        after[6] = 72.0;
        let note = |element, degrees, parent| Warning::PartitionFold {
            element,
            degrees,
            parent,
            limit: FOLD_TURN_RATIO,
        };
        assert_eq!(fold(&halves, &after), Some(note(6, 72.0, 80.0)));
        // of two folds, the one that kept more of its parent's turn
        after[1] = 49.0;
        assert_eq!(fold(&halves, &after), Some(note(1, 49.0, 50.0)));
        after[6] = 0.0;
        after[1] = 45.1;
        assert_eq!(fold(&halves, &after), Some(note(1, 45.1, 50.0)));
    }

    /// A Ctrl-C during a split partition's solve ends the automatic
    /// partition: it is not refined again from the start (the retry is for
    /// a split partition that failed to solve).
    #[test]
    fn a_cancelled_split_is_not_refined_again() {
        // 300 mm long, no ribs, eps0 = 0.4: the 37.5 mm pieces turn beyond
        // the slope limit, so the unloaded finger is split
        use crate::actuator::{ActuatorParams, Channel, Geometry, RibLayout};
        let mut params = ActuatorParams {
            geometry: Geometry {
                lx: 300.0,
                ..Geometry::default()
            },
            channel: Channel {
                cx: 295.0,
                ..Channel::default()
            },
            ribs: RibLayout::None,
            ..ActuatorParams::default()
        };
        params.pemc.eps0 = 0.4;
        let actuator = Actuator::new(params).unwrap();
        let auto = Auto::new(ModelId::default(), &actuator, false).unwrap();
        let (load, opts) = (Load::unloaded(), SolveOptions::default());
        let (solved, checks) =
            crate::cancel::cancelled_from(usize::MAX, || auto.solve(&load, &opts));
        let splits = solved.unwrap().splits;
        assert!(splits > 0);
        // one solve (one check) per partition
        assert_eq!(checks, splits + 1);
        // cancelled at the first split partition: its solve from the
        // parent's state and the cold one after it fail, and nothing more
        // is solved
        let (solved, checks) = crate::cancel::cancelled_from(2, || auto.solve(&load, &opts));
        assert_eq!(solved.err(), Some(SolveError::Cancelled));
        assert_eq!(checks, 3);
    }
}

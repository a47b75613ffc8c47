//! Choosing the discretisation for an accuracy: partitions, refinement by
//! doubling, nested iteration and extrapolation of the tip.
//!
//! With equal elements the CCM converges irregularly at first order in the
//! element length, because rib edges and the channel's end fall inside
//! elements. With element boundaries on every material change
//! ([`PartitionKind::Material`]) the tip error of the CCM follows the
//! expansion `c1 h + c2 h^2 + c3 h^3 + ...` in the element length `h`: the
//! second-order term dominates on coarse partitions, and a small
//! first-order term, present whenever a tip load bends the elements, takes
//! over at a few hundred elements (docs/performance.md, "Why the tip
//! converges at first order": the end slope of decision D2 couples each
//! element's end moment to its axial unknowns). A [`Refinement`] solves a
//! sequence of partitions, each level halving every element of the one
//! before and starting Newton from it (nested iteration: the halves of an
//! element start from their parent's coefficients).
//!
//! Extrapolation of material partitions (levels `t_0, t_1, ...` halving `h`):
//! - from two levels, `R2 = t + (t - t_prev) / 3` removes the `h^2` term;
//! - from three or more, `T3`, built from the last three levels, removes
//!   the `h` and `h^2` terms: `(8 t_n - 6 t_n-1 + t_n-2) / 3`.
//!
//! Error estimates (mm, distance of the reported tip from the N -> infinity
//! limit), with `D = |t_n - t_n-1|`:
//! - extrapolated, two levels: `D / 3`. Two levels cannot separate the
//!   first-order term; this bounds `R2`'s error while the first-order term
//!   is at most the second-order one at the finer level (true on the 27 +
//!   54 elements the tolerance-driven choice starts from by a factor of 8 or
//!   more on every finger tested; not beyond a few hundred elements under a
//!   tip load: use three or more levels there);
//! - extrapolated, three levels: the larger of the first-order term the
//!   third level removed, `|T3 - R2|`, and `D / 3` (a three-level
//!   extrapolation is not trusted to beat the two-level one before a fourth
//!   level confirms it: on coarse partitions the `h^3` term can dominate);
//! - extrapolated, four or more levels: the change of `T3` from the
//!   previous three levels, `|T3_n - T3_n-1|` (about 7 times `T3`'s error
//!   once the `h^3` term leads);
//! - material, not extrapolated: `D / 2` from two levels (the same
//!   assumption as `D / 3` above), else `|t_n - T3|` plus `T3`'s estimate;
//! - equal elements: `3 max(D, |t_n-1 - t_n-2| / 2)`, from three levels
//!   (`None` with fewer). Their convergence is too irregular for two levels:
//!   the error of the finer level reached 4.4 times `D` in the measurements
//!   of docs/performance.md, and 0.67 times this estimate at most.
//!
//! A tip tolerance ([`crate::Plan::TipTolerance`]) uses the material
//! partition with extrapolation for every tolerance
//! ([`Refinement::for_tolerance`]) and refines until the estimate meets
//! the tolerance. [`crate::PlannedFinger`] is the front door to every
//! plan; this module holds the refinements behind it.

use std::sync::{Arc, Mutex, PoisonError};

use super::refinement::{
    Extrapolation, Level, PartitionKind, Refinement, RefinementRecord, MAX_REFINED_ELEMENTS,
};
use super::solved::Solved;
use crate::actuator::Actuator;
use crate::coefficients::Coefficients;
use crate::error::{positive, require, InputError};
use crate::field::Field;
use crate::finger::{Finger, Load, Solution, SolveOptions};
use crate::model::ModelId;
use crate::solve_error::SolveError;

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// A level's extrapolated quantities: tip X, tip Z, end angle.
type Values = [f64; 3];

fn values(l: &Level) -> Values {
    [l.tip[0], l.tip[1], l.end_angle]
}

fn tip_dist(a: &Values, b: &Values) -> f64 {
    dist([a[0], a[1]], [b[0], b[1]])
}

/// One Richardson step: removes the term of order `p` in the element
/// length from a coarse value and the value at half its element length.
fn eliminate(coarse: &Values, fine: &Values, p: i32) -> Values {
    let f = 2f64.powi(p) - 1.0;
    std::array::from_fn(|i| fine[i] + (fine[i] - coarse[i]) / f)
}

/// `R2`: the `h^2` term removed from the last two of `v`.
fn r2(v: &[Values]) -> Values {
    let n = v.len();
    eliminate(&v[n - 2], &v[n - 1], 2)
}

/// `T3`: the `h` and `h^2` terms removed from the last three of `v`,
/// `(8 t_n - 6 t_n-1 + t_n-2) / 3`.
fn t3(v: &[Values]) -> Values {
    let n = v.len();
    let a = eliminate(&v[n - 3], &v[n - 2], 1);
    let b = eliminate(&v[n - 2], &v[n - 1], 1);
    eliminate(&a, &b, 2)
}

/// `T3` of the last three of `v` (at least three) and its estimated error
/// (module docs).
fn t3_estimate(v: &[Values]) -> (Values, f64) {
    let n = v.len();
    let t = t3(v);
    let est = if n == 3 {
        tip_dist(&t, &r2(v)).max(tip_dist(&v[n - 1], &v[n - 2]) / 3.0)
    } else {
        tip_dist(&t, &t3(&v[..n - 1]))
    };
    (t, est)
}

/// The best tip, end angle and error estimate from the levels solved so far
/// (module docs).
fn estimate(plan: &Refinement, levels: &[Level]) -> ([f64; 2], f64, Option<f64>) {
    let v: Vec<Values> = levels.iter().map(values).collect();
    let n = v.len();
    let last = v[n - 1];
    let (best, est) = if n < 2 {
        (last, None)
    } else {
        let change = tip_dist(&v[n - 1], &v[n - 2]);
        match (plan.partition, Extrapolation::of(plan, n), n) {
            (PartitionKind::Equal, _, 2) => (last, None),
            (PartitionKind::Equal, _, _) => {
                let before = tip_dist(&v[n - 2], &v[n - 3]);
                (last, Some(3.0 * change.max(before / 2.0)))
            }
            (PartitionKind::Material, Some(Extrapolation::LastTwo), _) => {
                (r2(&v), Some(change / 3.0))
            }
            (PartitionKind::Material, Some(Extrapolation::LastThree), _) => {
                let (t, est) = t3_estimate(&v);
                (t, Some(est))
            }
            (PartitionKind::Material, None, 2) => (last, Some(change / 2.0)),
            (PartitionKind::Material, None, _) => {
                let (t, est) = t3_estimate(&v);
                (last, Some(tip_dist(&last, &t) + est))
            }
        }
    };
    ([best[0], best[1]], best[2], est)
}

/// Relative residual an intermediate level of [`INTERMEDIATE_ELEMENTS`]
/// elements is solved to (at least; finer levels proportionally tighter).
/// The same relative residual leaves a larger tip error on a finer
/// partition (each element's share of the gradient shrinks with its
/// length), hence the scaling: on the standard tip-loaded case the
/// loosened levels move the extrapolated tip by 2.5e-6 mm on two levels,
/// 2.0e-6 mm on three and 7e-7 mm on four (tests/refine.rs holds the four
/// to 1e-5 mm, a thousandth of the 0.01 mm the two-level configuration
/// meets), well inside the error estimates, and save Newton steps on the
/// coarsest level.
pub const INTERMEDIATE_RTOL: f64 = 1e-9;

/// The element count at which an intermediate level uses
/// [`INTERMEDIATE_RTOL`].
pub const INTERMEDIATE_ELEMENTS: usize = 27;

/// The options a refinement solves an intermediate level of `elements`
/// elements with: only the tip is needed, to [`INTERMEDIATE_RTOL`] scaled
/// by `INTERMEDIATE_ELEMENTS / elements` (at most 1), or the caller's
/// looser tolerance (`fpc-lab timing` times the first level alone with
/// them).
pub fn intermediate_options(opts: &SolveOptions, elements: usize) -> SolveOptions {
    let scale = (INTERMEDIATE_ELEMENTS as f64 / elements.max(1) as f64).min(1.0);
    SolveOptions {
        rtol: opts.rtol.max(INTERMEDIATE_RTOL * scale),
        ..tip_options(opts)
    }
}

/// The options of a level that may turn out to be the last: the caller's
/// tolerance, only the tip.
fn tip_options(opts: &SolveOptions) -> SolveOptions {
    SolveOptions {
        shape: false,
        stability: false,
        ..*opts
    }
}

/// A refinement's fingers, built once (one per level) and reused for any
/// number of loads: the implementation of the nested-levels and
/// tip-tolerance plans of [`crate::PlannedFinger`].
#[derive(Debug, Clone)]
pub(crate) struct Refiner {
    plan: Refinement,
    fingers: Vec<Finger>,
    actuator: Actuator,
    ribs: bool,
}

impl Refiner {
    /// Builds the fingers of every level of `plan`.
    pub(crate) fn new(
        actuator: &Actuator,
        ribs: bool,
        plan: &Refinement,
    ) -> Result<Refiner, InputError> {
        plan.validate(actuator, ribs)?;
        let mut r = Refiner {
            plan: *plan,
            fingers: Vec::with_capacity(plan.levels),
            actuator: actuator.clone(),
            ribs,
        };
        for level in 0..plan.levels {
            r.finger(level)?;
        }
        Ok(r)
    }

    /// The fingers built so far, coarsest first.
    pub(crate) fn fingers(&self) -> &[Finger] {
        &self.fingers
    }

    /// The finger of `level`, built when first asked for.
    fn finger(&mut self, level: usize) -> Result<&Finger, InputError> {
        while self.fingers.len() <= level {
            let part = self
                .plan
                .partition(&self.actuator, self.ribs, self.fingers.len())?;
            self.fingers.push(Finger::with_model(
                self.plan.model,
                &self.actuator,
                &part,
                self.ribs,
            ));
        }
        Ok(&self.fingers[level])
    }

    /// Solves `load` on every level of the plan, coarse to fine, each level
    /// starting from the one before (nested iteration); the finest level
    /// uses `opts`, the others only compute the tip. `guess` (raw
    /// coefficients on the coarsest partition) starts the coarsest solve.
    pub(crate) fn solve(
        &self,
        load: &Load,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
    ) -> Result<Solved, SolveError> {
        let mut run = Run::default();
        for (level, finger) in self.fingers.iter().enumerate().take(self.plan.levels) {
            let last = level + 1 == self.plan.levels;
            let level_opts = if last {
                *opts
            } else {
                intermediate_options(opts, finger.len())
            };
            solve_level(finger, &mut run, load, guess, &level_opts, !last)?;
        }
        Ok(self.finish(run))
    }

    /// Solves `load` to an estimated tip error of at most `tip_tol_mm`,
    /// adding levels (built when first needed) until the estimate meets
    /// it. The plan of a tolerance ([`TipTolerance::refiner`]).
    fn solve_to(
        &mut self,
        load: &Load,
        tip_tol_mm: f64,
        opts: &SolveOptions,
    ) -> Result<Solved, SolveError> {
        let mut run = Run::default();
        let mut level = 0;
        // the levels before the first estimate are intermediate (equal
        // elements need three, material partitions two); any later one may be
        // the last: the caller's tolerance, tip only
        let first_estimate = match self.plan.partition {
            PartitionKind::Equal => 2,
            PartitionKind::Material => 1,
        };
        loop {
            let intermediate = level < first_estimate;
            let finger = self.finger(level)?;
            let level_opts = if intermediate {
                intermediate_options(opts, finger.len())
            } else {
                tip_options(opts)
            };
            solve_level(finger, &mut run, load, None, &level_opts, intermediate)?;
            let plan = Refinement {
                levels: run.levels.len(),
                ..self.plan
            };
            let (_, _, est) = estimate(&plan, &run.levels);
            if est.is_some_and(|e| e <= tip_tol_mm) {
                break;
            }
            level += 1;
            if self.finger(level).is_err() {
                return Err(InputError::OutOfRange {
                    field: Field::TipTolMm,
                    value: tip_tol_mm,
                    rule: match est {
                        Some(e) => format!(
                            "not reached with up to {MAX_REFINED_ELEMENTS} elements (estimated tip error there {e:.3e} mm)"
                        ),
                        None => format!(
                            "not reached with up to {MAX_REFINED_ELEMENTS} elements (equal elements need three levels for an error estimate)"
                        ),
                    },
                }
                .into());
            }
        }
        self.finalise(&mut run, load, opts)?;
        Ok(self.finish(run))
    }

    /// Re-solves the finest level with the caller's options when they ask
    /// for more than the tip (the level was solved as [`tip_options`]), or
    /// when it was solved as an intermediate one.
    fn finalise(&self, run: &mut Run, load: &Load, opts: &SolveOptions) -> Result<(), SolveError> {
        let Some(state) = &run.state else {
            return Ok(());
        };
        if run.last.is_some() && (opts.shape, opts.stability) == (false, false) {
            return Ok(());
        }
        let finger = &self.fingers[run.levels.len() - 1];
        let sol = finger.solve_from(load, state, opts)?;
        run.last = Some(sol);
        Ok(())
    }

    fn finish(&self, mut run: Run) -> Solved {
        let plan = Refinement {
            levels: run.levels.len(),
            ..self.plan
        };
        let (tip, end_angle, est) = estimate(&plan, &run.levels);
        let solution = run
            .last
            .take()
            .expect("a refinement solves at least one level");
        Solved {
            solution,
            finger: self.fingers[run.levels.len() - 1].clone(),
            refinement: Some(RefinementRecord {
                tip,
                end_angle,
                estimated_tip_error_mm: est,
                levels: run.levels,
                plan,
            }),
            splits: 0,
            planned: None,
        }
    }
}

/// Solves one level on `finger` with `level_opts`, from the previous
/// level's solution when there is one (else from `guess`).
fn solve_level(
    finger: &Finger,
    run: &mut Run,
    load: &Load,
    guess: Option<&Coefficients>,
    level_opts: &SolveOptions,
    intermediate: bool,
) -> Result<(), SolveError> {
    // nested iteration from the previous level (a failed warm start
    // falls back to a cold one), else from `guess`
    let nested = match &run.state {
        Some(prev) if prev.elements() * 2 == finger.len() => {
            Some(prev.split(&vec![true; prev.elements()]))
        }
        _ => None,
    };
    let start = nested.as_ref().or(guess);
    let trusted = nested.is_some();
    let level = |tip, end_angle, iterations, steps| Level {
        elements: finger.len(),
        tip,
        end_angle,
        iterations,
        steps,
    };
    let (state, level) = if intermediate {
        // only the state and the tip: no Solution for a level nobody sees
        let t = match finger.solve_tip(load, start, level_opts, trusted) {
            Err(_) if trusted => finger.solve_tip(load, None, level_opts, false),
            r => r,
        }?;
        run.last = None;
        (
            t.coefficients,
            level(t.tip, t.end_angle, t.iterations, t.steps),
        )
    } else {
        let solve = |g: Option<&Coefficients>| match g {
            Some(g) if trusted => finger.solve_trusted(load, g, level_opts),
            Some(g) => finger.solve_from(load, g, level_opts),
            None => finger.solve(load, level_opts),
        };
        let sol = match solve(start) {
            Err(_) if trusted => solve(None),
            r => r,
        }?;
        let done = level(
            sol.tip,
            sol.end_angle,
            sol.report.iterations,
            sol.report.steps,
        );
        let state = sol.coefficients.clone();
        run.last = Some(sol);
        (state, done)
    };
    run.levels.push(level);
    run.state = Some(state);
    Ok(())
}

/// The levels solved so far.
#[derive(Default)]
struct Run {
    levels: Vec<Level>,
    /// The last level's state (raw coefficients).
    state: Option<Coefficients>,
    /// The last level's solution, when it was solved as one.
    last: Option<Solution>,
}

/// A tip tolerance, checked, with the fingers of its first level: the
/// implementation of [`crate::Plan::TipTolerance`].
#[derive(Debug, Clone)]
pub(crate) struct TipTolerance {
    tip_tol_mm: f64,
    refiner: Refiner,
    /// Every level's finger built by the solves so far (each a function of
    /// the plan alone), kept for the next solve: solving many loads builds
    /// each level once. Shared by clones, which have the same plan.
    built: Arc<Mutex<Vec<Finger>>>,
}

impl TipTolerance {
    /// Checks `tip_tol_mm` and `start` and builds the first level.
    ///
    /// Without `start`, on the material partition with extrapolation
    /// ([`Refinement::for_tolerance`]); with `start`, on equal elements
    /// doubled from `start` (which must lie in [1, `MAX_REFINED_ELEMENTS` /
    /// 2]; equal elements need three levels for an estimate).
    pub(crate) fn new(
        model: ModelId,
        actuator: &Actuator,
        ribs: bool,
        tip_tol_mm: f64,
        start: Option<usize>,
    ) -> Result<TipTolerance, InputError> {
        positive(Field::TipTolMm, tip_tol_mm)?;
        let plan = match start {
            None => Refinement {
                levels: 1,
                ..Refinement::for_tolerance(model, tip_tol_mm)
            },
            Some(start) => {
                let most = MAX_REFINED_ELEMENTS / 2;
                require(
                    (1..=most).contains(&start),
                    Field::PartitionN,
                    start as f64,
                    || {
                        format!("must lie in [1, {most}] to refine to a tip tolerance (N doubles up to {MAX_REFINED_ELEMENTS})")
                    },
                )?;
                Refinement {
                    model,
                    partition: PartitionKind::Equal,
                    start,
                    levels: 1,
                    extrapolate: false,
                }
            }
        };
        // a single level cannot be extrapolated yet: validate without, then
        // extrapolate once there are two
        let mut refiner = Refiner::new(
            actuator,
            ribs,
            &Refinement {
                extrapolate: false,
                ..plan
            },
        )?;
        refiner.plan.extrapolate = plan.extrapolate;
        Ok(TipTolerance {
            tip_tol_mm,
            built: Arc::new(Mutex::new(refiner.fingers.clone())),
            refiner,
        })
    }

    /// The fingers built before any solve (the first level's).
    pub(crate) fn fingers(&self) -> &[Finger] {
        self.refiner.fingers()
    }

    /// Solves `load`, adding levels until the estimate (module docs) meets
    /// the tolerance; fails with an input error naming `tip_tol_mm` when
    /// `MAX_REFINED_ELEMENTS` elements do not reach it.
    pub(crate) fn solve(&self, load: &Load, opts: &SolveOptions) -> Result<Solved, SolveError> {
        // the finer levels are built as they are first needed, and kept
        let kept =
            |b: &Mutex<Vec<Finger>>| b.lock().unwrap_or_else(PoisonError::into_inner).clone();
        let mut refiner = Refiner {
            plan: self.refiner.plan,
            fingers: kept(&self.built),
            actuator: self.refiner.actuator.clone(),
            ribs: self.refiner.ribs,
        };
        let solved = refiner.solve_to(load, self.tip_tol_mm, opts);
        let mut built = self.built.lock().unwrap_or_else(PoisonError::into_inner);
        if refiner.fingers.len() > built.len() {
            *built = refiner.fingers;
        }
        solved
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::finger::StepCounts;

    /// A tip tolerance keeps the levels its solves build: a second load
    /// builds none, and solves as a fresh plan does.
    #[test]
    fn a_tip_tolerance_builds_each_level_once() {
        let actuator = Actuator::default();
        let new = || TipTolerance::new(ModelId::default(), &actuator, true, 0.05, None).unwrap();
        let opts = SolveOptions::default();
        let load = |fx| {
            Load::unloaded()
                .with_pressure_kpa(50.0)
                .with_tip_force(fx, 0.2)
        };
        let kept = new();
        assert_eq!(kept.built.lock().unwrap().len(), 1);
        let first = kept.solve(&load(0.5), &opts).unwrap();
        let levels = kept.built.lock().unwrap().len();
        assert!(levels >= 2, "{levels} levels kept");
        // (the finer level whose existence decides the last one counts)
        assert!(first.refinement.as_ref().unwrap().levels.len() <= levels);
        // a load needing a finer level adds it, and only it
        let other = kept.solve(&load(-0.3), &opts).unwrap();
        let more = kept.built.lock().unwrap().len();
        assert!(more >= levels);
        let again = kept.solve(&load(0.5), &opts).unwrap();
        assert_eq!(kept.built.lock().unwrap().len(), more);
        assert_eq!(again.solution, first.solution);
        assert_eq!(again.refinement, first.refinement);
        let fresh = new().solve(&load(-0.3), &opts).unwrap();
        assert_eq!(other.solution, fresh.solution);
        assert_eq!(other.refinement, fresh.refinement);
    }

    fn level(elements: usize, tip: [f64; 2], end_angle: f64) -> Level {
        Level {
            elements,
            tip,
            end_angle,
            iterations: 1,
            steps: StepCounts {
                coupled: 1,
                ..StepCounts::default()
            },
        }
    }

    /// Levels of `t(h) = T + c1 h + c2 h^2 (+ c3 h^3)`, h halving from 1.
    fn levels(c: [f64; 4], n: usize) -> Vec<Level> {
        (0..n)
            .map(|k| {
                let h = 0.5f64.powi(k as i32);
                let t = c[0] + c[1] * h + c[2] * h * h + c[3] * h.powi(3);
                level(27 << k, [t, -t], 0.1 * t)
            })
            .collect()
    }

    fn plan(partition: PartitionKind, extrapolate: bool) -> Refinement {
        Refinement {
            model: ModelId::default(),
            partition,
            start: 8,
            levels: 1,
            extrapolate,
        }
    }

    #[test]
    fn t3_removes_h_and_h2_and_r2_only_h2() {
        let m = plan(PartitionKind::Material, true);
        let v = levels([2.0, 0.3, -5.0, 0.0], 3);
        let (tip, angle, est) = estimate(&m, &v);
        assert!((tip[0] - 2.0).abs() < 1e-14 && (tip[1] + 2.0).abs() < 1e-14);
        assert!((angle - 0.2).abs() < 1e-14);
        // the estimate is the larger of R2's first-order error, (2/3) c1 h
        // at h = 1/4, and the last change over 3 (both components: sqrt 2)
        let r2_err = 2.0 / 3.0 * 0.3 * 0.25 * 2f64.sqrt();
        let change = (0.3 * 0.25 - 5.0 * 3.0 / 16.0f64).abs() * 2f64.sqrt() / 3.0;
        assert!((est.unwrap() - r2_err.max(change)).abs() < 1e-12, "{est:?}");
        let (tip, _, _) = estimate(&m, &v[..2]);
        assert!(((tip[0] - 2.0) - 2.0 / 3.0 * 0.3 * 0.5).abs() < 1e-14);
    }

    #[test]
    fn four_levels_estimate_from_the_change_of_t3() {
        // an h^3 term: T3's error is c3 h^3 / 8 at the coarsest of its three
        // levels, and the change from the previous T3 is 7 times that
        let m = plan(PartitionKind::Material, true);
        let v = levels([1.0, 0.2, 3.0, -4.0], 4);
        let (tip, _, est) = estimate(&m, &v);
        let err = (tip[0] - 1.0).hypot(tip[1] + 1.0);
        let est = est.unwrap();
        assert!((est / err - 7.0).abs() < 1e-9, "{est} vs {err}");
        // unextrapolated: the finest level's distance from T3 plus T3's
        // estimate bounds its error
        let (fine, _, e) = estimate(&plan(PartitionKind::Material, false), &v);
        assert_eq!(fine, v[3].tip);
        let err = (fine[0] - 1.0).hypot(fine[1] + 1.0);
        assert!(e.unwrap() >= err);
    }

    /// A record says which extrapolation its tip came from: with two
    /// levels `R2` of them, with more `T3` of the last three (the formulas
    /// written out here, not `estimate`'s); it sums its levels' steps, and
    /// serializes every level's tip, so a reader can redo the arithmetic.
    #[test]
    fn the_record_names_its_extrapolation_and_sums_its_levels() {
        let v = levels([2.0, 0.3, -5.0, 0.7], 4);
        let record = |n: usize, extrapolate: bool| {
            let plan = Refinement {
                levels: n,
                ..plan(PartitionKind::Material, extrapolate)
            };
            let (tip, end_angle, estimated_tip_error_mm) = estimate(&plan, &v[..n]);
            RefinementRecord {
                tip,
                end_angle,
                estimated_tip_error_mm,
                levels: v[..n].to_vec(),
                plan,
            }
        };
        let x = |k: usize| v[k].tip[0];
        let two = record(2, true);
        assert_eq!(two.extrapolation(), Some(Extrapolation::LastTwo));
        assert!((two.tip[0] - (4.0 * x(1) - x(0)) / 3.0).abs() < 1e-14);
        for n in [3, 4] {
            let r = record(n, true);
            assert_eq!(r.extrapolation(), Some(Extrapolation::LastThree));
            let t3 = (8.0 * x(n - 1) - 6.0 * x(n - 2) + x(n - 3)) / 3.0;
            assert!((r.tip[0] - t3).abs() < 1e-14, "{n} levels");
        }
        assert_eq!(record(3, false).extrapolation(), None);
        assert_eq!(record(1, true).extrapolation(), None);
        let four = record(4, true);
        assert_eq!(four.iterations(), 4);
        let steps = four.steps();
        assert_eq!((steps.coupled, steps.element, steps.chord), (4, 0, 0));
        let json = serde_json::to_value(&four).unwrap();
        assert_eq!(json["extrapolation"], "last_three");
        assert_eq!(json["levels"], serde_json::json!([27, 54, 108, 216]));
        assert_eq!(json["level_tips_mm"][2][0], x(2));
        assert_eq!(json["level_steps"][3]["coupled"], 1);
        assert_eq!(json["tip_mm"][0], four.tip[0]);
        let plain = serde_json::to_value(record(3, false)).unwrap();
        assert!(plain["extrapolation"].is_null() && plain["extrapolated"] == false);
    }

    #[test]
    fn equal_elements_need_three_levels() {
        let e = plan(PartitionKind::Equal, false);
        let v = levels([1.0, 0.5, 0.0, 0.0], 3);
        assert_eq!(estimate(&e, &v[..1]).2, None);
        assert_eq!(estimate(&e, &v[..2]).2, None);
        // regular first order: the finest level's error equals the last
        // change, the estimate is three times it
        let (tip, _, est) = estimate(&e, &v);
        let err = (tip[0] - 1.0).hypot(tip[1] + 1.0);
        assert!((est.unwrap() / err - 3.0).abs() < 1e-12);
    }
}

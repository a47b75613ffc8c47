//! Choosing the discretisation for an accuracy: partitions, refinement by
//! doubling, nested iteration and Richardson extrapolation.
//!
//! With equal elements the CCM converges at first order in the element
//! length, because rib edges fall inside elements; with element boundaries
//! on every material change ([`PartitionKind::Material`]) it converges at
//! second order (docs/performance.md shows both). A [`Refinement`] solves a
//! sequence of partitions, each level halving every element of the one
//! before and starting Newton from it (nested iteration: the halves of an
//! element start from their parent's coefficients). Two levels give an
//! error estimate; on material partitions they also give a Richardson
//! extrapolation of the tip, which removes the leading error term.
//!
//! Error estimates (mm, distance of the tip from the N -> infinity limit):
//! - first order (equal elements): the last change `|t_N - t_N/2|`;
//! - second order (material): `|t_N - t_N/2| / 3`;
//! - extrapolated from three or more levels: the change of the
//!   extrapolation between the last two pairs, and from two levels the
//!   second-order estimate of the finer level (both over-estimate the
//!   extrapolation's error when the convergence is regular).
//!
//! [`solve_to_tip_tolerance`] picks the fastest configuration for an asked
//! tolerance ([`Refinement::for_tolerance`], chosen from the measured
//! accuracy-time front) and refines until the estimate meets it.

use serde::Serialize;

use crate::actuator::Actuator;
use crate::blocks::Partition;
use crate::error::{positive, require, InputError, SolveError, Warning};
use crate::finger::{Coefficients, Finger, Load, Solution, SolveOptions};
use crate::model::ModelId;

/// Largest number of elements a refinement uses.
pub const MAX_REFINED_ELEMENTS: usize = 1000;

/// Tolerances at least this large (mm) are met fastest by equal elements
/// without extrapolation; tighter ones by material partitions with
/// Richardson extrapolation (docs/performance.md, "The front").
pub const EQUAL_PARTITION_TOLERANCE_MM: f64 = 0.5;

/// How a refinement places element boundaries.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PartitionKind {
    /// `start` equal elements, doubled per level (first order).
    Equal,
    /// Boundaries on the material changes ([`Partition::material`], pieces
    /// at most `lx / start` long), every element halved per level (second
    /// order).
    Material,
}

impl PartitionKind {
    /// Every kind.
    pub const ALL: [PartitionKind; 2] = [PartitionKind::Equal, PartitionKind::Material];

    /// The kind's name (`equal`, `material`).
    pub fn name(self) -> &'static str {
        match self {
            PartitionKind::Equal => "equal",
            PartitionKind::Material => "material",
        }
    }

    /// The kind named `name`, or an input error naming `field`.
    pub fn parse(field: &str, name: &str) -> Result<PartitionKind, InputError> {
        PartitionKind::ALL
            .into_iter()
            .find(|k| k.name() == name)
            .ok_or_else(|| InputError::Unrecognised {
                field: field.into(),
                value: name.into(),
                rule: "must be equal or material".into(),
            })
    }

    /// The observed order of convergence in the element length that the
    /// error estimates assume.
    pub fn order(self) -> u32 {
        match self {
            PartitionKind::Equal => 1,
            PartitionKind::Material => 2,
        }
    }
}

/// A discretisation plan: model, partition kind, coarsest partition,
/// number of levels and whether to extrapolate.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Refinement {
    /// The element model.
    pub model: ModelId,
    /// Where element boundaries go.
    pub partition: PartitionKind,
    /// Equal: the coarsest N. Material: pieces at most `lx / start` long.
    pub start: usize,
    /// Number of solves: the coarsest level and `levels - 1` halvings.
    pub levels: usize,
    /// Richardson-extrapolate the tip from the last two levels (needs
    /// `levels >= 2` and a second-order partition).
    pub extrapolate: bool,
}

impl Refinement {
    /// One solve on `n` equal elements.
    pub fn equal(model: ModelId, n: usize) -> Refinement {
        Refinement {
            model,
            partition: PartitionKind::Equal,
            start: n,
            levels: 1,
            extrapolate: false,
        }
    }

    /// The configuration that meets `tip_tol_mm` fastest on the standard
    /// cases (docs/performance.md): equal elements from N = 4 for loose
    /// tolerances, otherwise the material partition (pieces at most lx / 8)
    /// on two levels with Richardson extrapolation. [`solve_to_tip_tolerance`]
    /// adds levels while the estimate is above the tolerance.
    pub fn for_tolerance(model: ModelId, tip_tol_mm: f64) -> Refinement {
        if tip_tol_mm >= EQUAL_PARTITION_TOLERANCE_MM {
            Refinement {
                model,
                partition: PartitionKind::Equal,
                start: 4,
                levels: 2,
                extrapolate: false,
            }
        } else {
            Refinement {
                model,
                partition: PartitionKind::Material,
                start: 8,
                levels: 2,
                extrapolate: true,
            }
        }
    }

    /// A short label, e.g. `ccm/material/8x2+richardson`.
    pub fn label(&self) -> String {
        format!(
            "{}/{}/{}x{}{}",
            self.model.name(),
            self.partition.name(),
            self.start,
            self.levels,
            if self.extrapolate { "+richardson" } else { "" }
        )
    }

    /// Checks the plan against the finger it is for.
    fn validate(&self, actuator: &Actuator, ribs: bool) -> Result<(), InputError> {
        require(
            self.start >= 1,
            "refinement.start",
            self.start as f64,
            "must be at least 1".to_string(),
        )?;
        require(
            self.levels >= 1,
            "refinement.levels",
            self.levels as f64,
            "must be at least 1".to_string(),
        )?;
        require(
            !self.extrapolate || (self.levels >= 2 && self.partition == PartitionKind::Material),
            "refinement.extrapolate",
            1.0,
            "needs at least two levels on a material partition (the extrapolation assumes second-order convergence)".to_string(),
        )?;
        let finest = self.partition(actuator, ribs, self.levels - 1)?.len();
        require(
            finest <= MAX_REFINED_ELEMENTS,
            "refinement.levels",
            self.levels as f64,
            format!(
                "gives {finest} elements at the finest level, more than {MAX_REFINED_ELEMENTS}"
            ),
        )
    }

    /// The partition of `level` (0: the coarsest).
    pub fn partition(
        &self,
        actuator: &Actuator,
        ribs: bool,
        level: usize,
    ) -> Result<Partition, InputError> {
        let lx = actuator.geometry().lx;
        let too_fine = || InputError::OutOfRange {
            field: "refinement.levels".into(),
            value: (level + 1) as f64,
            rule: format!("more than {MAX_REFINED_ELEMENTS} elements"),
        };
        match self.partition {
            PartitionKind::Equal => {
                let n = u32::try_from(level)
                    .ok()
                    .and_then(|l| self.start.checked_mul(1usize.checked_shl(l)?))
                    .filter(|&n| n <= MAX_REFINED_ELEMENTS)
                    .ok_or_else(too_fine)?;
                Partition::equal(lx, n)
            }
            PartitionKind::Material => {
                let mut p = Partition::material(actuator, ribs, lx / self.start as f64)?;
                for _ in 0..level {
                    if 2 * p.len() > MAX_REFINED_ELEMENTS {
                        return Err(too_fine());
                    }
                    p = p.halved();
                }
                Ok(p)
            }
        }
    }
}

/// One level of a refinement.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Level {
    /// Elements at this level.
    pub elements: usize,
    /// Tip (mm, finger frame).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// End angle (rad).
    #[serde(rename = "end_angle_rad")]
    pub end_angle: f64,
    /// Newton iterations of this level's solve.
    pub iterations: usize,
}

/// The result of [`refine`] and [`solve_to_tip_tolerance`].
#[derive(Debug, Clone, PartialEq)]
pub struct Refined {
    /// The solution on the finest partition.
    pub solution: Solution,
    /// Elements of the finest partition.
    pub elements: usize,
    /// The best tip estimate: extrapolated when the plan extrapolates,
    /// else the finest level's.
    pub tip: [f64; 2],
    /// The best end-angle estimate (rad), extrapolated like the tip.
    pub end_angle: f64,
    /// Estimated distance of `tip` from the N -> infinity limit (mm;
    /// module docs); `None` with a single level.
    pub estimated_tip_error_mm: Option<f64>,
    /// Every level, coarsest first.
    pub levels: Vec<Level>,
    /// The plan as run (levels as solved).
    pub plan: Refinement,
}

impl Refined {
    /// True when the tip is extrapolated.
    pub fn is_extrapolated(&self) -> bool {
        self.plan.extrapolate && self.levels.len() >= 2
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// Richardson extrapolation of a second-order sequence: `f + (f - c) / 3`.
fn richardson(coarse: f64, fine: f64) -> f64 {
    fine + (fine - coarse) / 3.0
}

fn extrapolated_tip(coarse: &Level, fine: &Level) -> [f64; 2] {
    [
        richardson(coarse.tip[0], fine.tip[0]),
        richardson(coarse.tip[1], fine.tip[1]),
    ]
}

/// The best tip, end angle and error estimate from the levels solved so far.
fn estimate(plan: &Refinement, levels: &[Level]) -> ([f64; 2], f64, Option<f64>) {
    let last = levels[levels.len() - 1];
    let n = levels.len();
    if n < 2 {
        return (last.tip, last.end_angle, None);
    }
    let prev = levels[n - 2];
    let change = dist(last.tip, prev.tip);
    if plan.extrapolate {
        let tip = extrapolated_tip(&prev, &last);
        let angle = richardson(prev.end_angle, last.end_angle);
        let est = if n >= 3 {
            dist(tip, extrapolated_tip(&levels[n - 3], &prev))
        } else {
            change / 3.0
        };
        return (tip, angle, Some(est));
    }
    let factor = f64::from((1u32 << plan.partition.order()) - 1);
    (last.tip, last.end_angle, Some(change / factor))
}

/// A guess for the partition with every element halved: each half starts
/// from its parent's raw coefficients (exact for the first half, whose
/// local frame is the parent's).
fn halved_guess(k: &Coefficients) -> Result<Coefficients, InputError> {
    let per = k.per_element();
    let mut values = Vec::with_capacity(2 * k.as_slice().len());
    for e in k.iter() {
        values.extend_from_slice(e);
        values.extend_from_slice(e);
    }
    Coefficients::new(per, values)
}

/// Relative residual an intermediate level of [`INTERMEDIATE_ELEMENTS`]
/// elements is solved to (at least; finer levels proportionally tighter).
/// The same relative residual leaves a larger tip error on a finer
/// partition (each element's share of the gradient shrinks with its
/// length), hence the scaling: on the standard tip-loaded case the
/// loosened levels move the extrapolated tip by 2.5e-6 mm (tests/refine.rs
/// holds it to 1e-5 mm, a thousandth of the 0.01 mm the extrapolated
/// configuration is chosen for) and save Newton steps on the coarsest
/// level.
pub const INTERMEDIATE_RTOL: f64 = 1e-9;

/// The element count at which an intermediate level uses
/// [`INTERMEDIATE_RTOL`].
pub const INTERMEDIATE_ELEMENTS: usize = 27;

/// The options of an intermediate level of `elements` elements: only the
/// tip is needed, to [`INTERMEDIATE_RTOL`] scaled by
/// `INTERMEDIATE_ELEMENTS / elements` (at most 1), or the caller's looser
/// tolerance.
fn coarse_options(opts: &SolveOptions, elements: usize) -> SolveOptions {
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

/// Solves `load` on every level of `plan`, coarse to fine, each level
/// starting from the one before (nested iteration); the finest level uses
/// `opts`, the others only compute the tip. See [`Refiner`] to reuse the
/// fingers over many loads.
pub fn refine(
    actuator: &Actuator,
    ribs: bool,
    load: &Load,
    plan: &Refinement,
    opts: &SolveOptions,
) -> Result<Refined, SolveError> {
    Refiner::new(actuator, ribs, plan)?.solve(load, None, opts)
}

/// A refinement's fingers, built once (one per level) and reused for any
/// number of loads.
#[derive(Debug, Clone)]
pub struct Refiner {
    plan: Refinement,
    fingers: Vec<Finger>,
    actuator: Actuator,
    ribs: bool,
}

impl Refiner {
    /// Builds the fingers of every level of `plan`.
    pub fn new(actuator: &Actuator, ribs: bool, plan: &Refinement) -> Result<Refiner, InputError> {
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

    /// The plan.
    pub fn plan(&self) -> &Refinement {
        &self.plan
    }

    /// The finger of `level`, built when first asked for.
    pub fn finger(&mut self, level: usize) -> Result<&Finger, InputError> {
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

    /// Solves `load` on every level of the plan; `guess` (raw coefficients
    /// on the coarsest partition) starts the coarsest solve.
    pub fn solve(
        &mut self,
        load: &Load,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
    ) -> Result<Refined, SolveError> {
        let mut run = Run::default();
        for level in 0..self.plan.levels {
            let level_opts = if level + 1 == self.plan.levels {
                *opts
            } else {
                coarse_options(opts, self.finger(level)?.len())
            };
            let intermediate = level + 1 < self.plan.levels;
            self.solve_level(&mut run, load, level, guess, &level_opts, intermediate)?;
        }
        Ok(self.finish(run))
    }

    /// Solves `level` with `level_opts`, from the previous level's solution
    /// when there is one (else from `guess`).
    fn solve_level(
        &mut self,
        run: &mut Run,
        load: &Load,
        level: usize,
        guess: Option<&Coefficients>,
        level_opts: &SolveOptions,
        intermediate: bool,
    ) -> Result<(), SolveError> {
        let finger = self.finger(level)?;
        // nested iteration from the previous level (a failed warm start
        // falls back to a cold one), else from `guess`
        let nested = match &run.state {
            Some(prev) if prev.elements() * 2 == finger.len() => Some(halved_guess(prev)?),
            _ => None,
        };
        let start = nested.as_ref().or(guess);
        let trusted = nested.is_some();
        let level = |tip, end_angle, iterations| Level {
            elements: finger.len(),
            tip,
            end_angle,
            iterations,
        };
        let (state, level) = if intermediate {
            // only the state and the tip: no Solution for a level nobody sees
            let t = match finger.solve_tip(load, start, level_opts, trusted) {
                Err(_) if trusted => finger.solve_tip(load, None, level_opts, false),
                r => r,
            }?;
            run.last = None;
            (t.coefficients, level(t.tip, t.end_angle, t.iterations))
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
            let done = level(sol.tip, sol.end_angle, sol.report.iterations);
            let state = sol.coefficients.clone();
            run.last = Some(sol);
            (state, done)
        };
        run.levels.push(level);
        run.state = Some(state);
        Ok(())
    }

    /// Re-solves the finest level with the caller's options when they ask
    /// for more than the tip (the level was solved as [`tip_options`]), or
    /// when it was solved as an intermediate one.
    fn finalise(
        &mut self,
        run: &mut Run,
        load: &Load,
        opts: &SolveOptions,
    ) -> Result<(), SolveError> {
        let Some(state) = &run.state else {
            return Ok(());
        };
        if run.last.is_some() && (opts.shape, opts.stability) == (false, false) {
            return Ok(());
        }
        let finger = self.finger(run.levels.len() - 1)?;
        let sol = finger.solve_from(load, state, opts)?;
        run.last = Some(sol);
        Ok(())
    }

    fn finish(&self, mut run: Run) -> Refined {
        let plan = Refinement {
            levels: run.levels.len(),
            ..self.plan
        };
        let (tip, end_angle, est) = estimate(&plan, &run.levels);
        let solution = run
            .last
            .take()
            .expect("a refinement solves at least one level");
        Refined {
            elements: solution.element_lengths.len(),
            solution,
            tip,
            end_angle,
            estimated_tip_error_mm: est,
            levels: run.levels,
            plan,
        }
    }
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

/// Solves `load` to an estimated tip error of at most `tip_tol_mm`.
///
/// Without `start`, with the fastest configuration for the tolerance
/// ([`Refinement::for_tolerance`]); with `start`, on equal elements
/// doubled from `start` (which must lie in [1, `MAX_REFINED_ELEMENTS` /
/// 2]). Levels are added until the estimate meets the tolerance; fails
/// with an input error naming `tip_tol_mm` when `MAX_REFINED_ELEMENTS`
/// elements do not reach it.
pub fn solve_to_tip_tolerance(
    model: ModelId,
    actuator: &Actuator,
    ribs: bool,
    load: &Load,
    tip_tol_mm: f64,
    start: Option<usize>,
    opts: &SolveOptions,
) -> Result<Refined, SolveError> {
    positive("tip_tol_mm", tip_tol_mm)?;
    let plan = match start {
        None => Refinement {
            levels: 1,
            ..Refinement::for_tolerance(model, tip_tol_mm)
        },
        Some(start) => {
            let most = MAX_REFINED_ELEMENTS / 2;
            require(
                (1..=most).contains(&start),
                "partition.n",
                start as f64,
                format!("must lie in [1, {most}] to refine to a tip tolerance (N doubles up to {MAX_REFINED_ELEMENTS})"),
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
    let mut run = Run::default();
    let mut level = 0;
    loop {
        // one level never has an estimate, so the first is intermediate;
        // any later one may be the last: the caller's tolerance, tip only
        let level_opts = if level == 0 {
            coarse_options(opts, refiner.finger(0)?.len())
        } else {
            tip_options(opts)
        };
        refiner.solve_level(&mut run, load, level, None, &level_opts, level == 0)?;
        let plan = Refinement {
            levels: run.levels.len(),
            ..refiner.plan
        };
        let (_, _, est) = estimate(&plan, &run.levels);
        if est.is_some_and(|e| e <= tip_tol_mm) {
            break;
        }
        level += 1;
        if refiner.finger(level).is_err() {
            return Err(InputError::OutOfRange {
                field: "tip_tol_mm".into(),
                value: tip_tol_mm,
                rule: format!(
                    "not reached with up to {MAX_REFINED_ELEMENTS} elements (estimated tip error there {:.3e} mm)",
                    est.unwrap_or(f64::INFINITY)
                ),
            }
            .into());
        }
    }
    refiner.finalise(&mut run, load, opts)?;
    Ok(refiner.finish(run))
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

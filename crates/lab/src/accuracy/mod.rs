//! The accuracy-time front: how far the tip of the standard tip-loaded
//! finger is from its N -> infinity limit, against the run time, for every
//! element model, partition kind and extrapolation the library offers
//! (`fpc::plan::Refinement`).
//!
//! Scene: the default actuator with ribs, eps0 = 0.25, no pressure, tip
//! force Fx = 0.939782 N, Fz = 0.521707 N (finger frame), tip-only output
//! at the default Newton tolerance ([`STANDARD_LOAD_N`]).
//!
//! **References.** Per model, from two families of material partitions:
//! pieces at most lx / [`REFERENCE_START`] (27 elements for the default
//! actuator) halved [`REFERENCE_LEVELS`] - 1 times (27 -> 864 elements),
//! and pieces at most lx / [`SECOND_FAMILY_START`] (40 elements) halved
//! [`SECOND_FAMILY_LEVELS`] - 1 times (40 -> 640). Every level is solved
//! to a relative residual of [`REFERENCE_RTOL`] (rounding) by nested
//! iteration, independently of how tightly a [`PlannedFinger`]
//! solves its intermediate levels (see [`fpc::plan::INTERMEDIATE_RTOL`]). The
//! tip error of material partitions follows `c1 h + c2 h^2 + c3 h^3 + ...`
//! (a first-order term under a tip load, docs/performance.md), so each
//! family's limit removes the terms h to h^4 from its [`LIMIT_LEVELS`]
//! finest levels ([`FamilyLimit::limit`]), with as its uncertainty the
//! distance from the limit through the four finest levels and the terms h
//! to h^3 ([`FamilyLimit::uncertainty_mm`]; the h^4 term's share, an
//! over-estimate once it leads). The reference is the midpoint of the two
//! limits, its uncertainty the larger of their uncertainties and their
//! distance; the families must agree within the sum of their
//! uncertainties ([`ModelReference::families_agree`]). The library's own
//! result for the first family's plan with extrapolation is reported next
//! to it ([`ModelReference::refiner_offset_mm`],
//! [`ModelReference::refiner_estimate_mm`]).
//!
//! **Orders.** Per model and partition kind, the observed orders
//! `log2(|t_l - t_{l-1}| / |t_{l+1} - t_l|)` of successive levels, of the
//! tip and of its X and Z alone: the first family's levels, and equal
//! elements from N = 8 doubled to 512, both fully converged.
//!
//! **Configurations** ([`CONFIGURATIONS`], one table applied to every
//! model): each is built once ([`FingerBuilder::build`](fpc::FingerBuilder::build), outside the timed region),
//! its coarsest finger's unloaded equilibrium is solved (outside too), and
//! the timed call is `finger.solve_from(&load, &unloaded.coefficients,
//! &opts)`. Every configuration is timed in [`StudyConfig::rounds`]
//! rounds over all configurations; in each round one batch of calls runs
//! until both [`StudyConfig::min_runs`] calls and its share of
//! [`StudyConfig::budget`] have passed, and the time reported is the
//! fastest round's median (on a shared machine another process's load
//! comes and goes for tens to hundreds of milliseconds and only ever adds
//! time; the fastest round is the estimate of the time on a quiet
//! machine). The N = 8 equal cold solve (the
//! `loaded_cold` case of `fpc-lab timing`) is measured the same way in a batch
//! right before every batch of a configuration (and once at the end), so
//! that its batches are spread over the whole run; its time `t8` is the
//! fastest of those batch medians, the same estimator as the rows', and
//! every row carries `time / t8`. The median of all N = 8 batches, and the
//! median of those measured right before each configuration's fastest
//! round, are reported too: on the project's shared 2-core machine the
//! time of one and the same solve flips between two levels about 1.5x
//! apart (other load on the host), and medians
//! over such a run give ratios off by up to that factor, where the fastest
//! batches agree to about 2 % (the row of the N = 8 configuration itself
//! checks it: [`TimingReference::same_row_ratio`]).
//!
//! **Front.** A row is on the Pareto front when no other row is both at
//! most as slow (up to [`TIME_RESOLUTION`]) and at most as far from the
//! CCM reference (one of the two strictly); for each of [`TOLERANCES_MM`]
//! the fastest row within it is reported, the fastest whose own estimate
//! is within it too, and what the library picks for that tolerance
//! (`fpc::Plan::TipTolerance`, the plan as it ran, timed the same
//! way).

mod config;
mod front;
mod reference;
#[cfg(test)]
mod tests;
mod timing;

use fpc::plan::Refinement;
use fpc::{Actuator, Load, ModelId, PlannedFinger, SolveError, SolveOptions};
use serde::Serialize;

pub use config::{study_models, Plan, StudyConfig, CONFIGURATIONS, QUICK_CONFIGURATIONS};
pub use front::{AccuracyRow, Fastest, FrontPoint, LibraryChoice, TIME_RESOLUTION, TOLERANCES_MM};
pub use reference::{
    Convergence, FamilyLimit, ModelGap, ModelReference, EQUAL_ORDER_LEVELS, EQUAL_ORDER_START,
    LIMIT_LEVELS, REFERENCE_LEVELS, REFERENCE_RTOL, REFERENCE_START, SECOND_FAMILY_LEVELS,
    SECOND_FAMILY_START,
};
pub use timing::TimingReference;

use front::{fastest_row, pareto};
use reference::reference;
use timing::{median, Point};

/// The prestrain of the standard case.
pub const EPS0: f64 = 0.25;

/// The standard tip force (N, finger frame): Fx, Fz.
pub const STANDARD_LOAD_N: [f64; 2] = [0.939782, 0.521707];

/// The whole study.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AccuracyStudy {
    /// `debug` or `release`.
    pub build: &'static str,
    /// The prestrain.
    pub eps0: f64,
    /// The tip force (N).
    pub tip_force_n: [f64; 2],
    /// Relative residual of the timed solves' finest level.
    pub rtol: f64,
    /// What was run.
    pub config: StudyConfig,
    /// Every model's reference, in the order of `config.models`.
    pub references: Vec<ModelReference>,
    /// Every other model's distance from the CCM reference.
    pub gaps: Vec<ModelGap>,
    /// The N = 8 equal cold solve: `t8`.
    pub n8: TimingReference,
    /// Every configuration of every model.
    pub rows: Vec<AccuracyRow>,
    /// The Pareto front, fastest first.
    pub front: Vec<FrontPoint>,
    /// The fastest row for each of [`TOLERANCES_MM`].
    pub fastest: Vec<Fastest>,
}

impl AccuracyStudy {
    /// The reference of `model`.
    pub fn reference(&self, model: ModelId) -> Option<&ModelReference> {
        self.references.iter().find(|r| r.model == model)
    }

    /// The reference of the CCM (the default model).
    pub fn ccm_reference(&self) -> &ModelReference {
        self.reference(ModelId::default())
            .expect("a study always has the CCM's reference")
    }
}

fn dist(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

/// The standard tip load.
pub fn standard_load() -> Load {
    Load::unloaded().with_tip_force(STANDARD_LOAD_N[0], STANDARD_LOAD_N[1])
}

/// Runs the study; `progress(done, total)` is called after each reference
/// and after each point of each round.
pub fn accuracy_study(
    config: &StudyConfig,
    mut progress: impl FnMut(usize, usize),
) -> Result<AccuracyStudy, SolveError> {
    let act = Actuator::paper(EPS0)?;
    let load = standard_load();
    let opts = SolveOptions::default().tip_only();
    let ccm = ModelId::default();
    let mut models = config.models.clone();
    if !models.contains(&ccm) {
        models.insert(0, ccm);
    }
    let rounds = config.rounds.max(1);
    let total = models.len() + rounds * (models.len() * config.plans.len() + TOLERANCES_MM.len());
    let mut done = 0;
    let mut step = |progress: &mut dyn FnMut(usize, usize)| {
        done += 1;
        progress(done, total);
    };

    let mut references = Vec::with_capacity(models.len());
    for &m in &models {
        references.push(reference(&act, &load, m, config.equal_order_levels)?);
        step(&mut progress);
    }
    let ccm_ref = references
        .iter()
        .find(|r| r.model == ccm)
        .expect("the CCM is among the models")
        .clone();
    let gaps = references
        .iter()
        .filter(|r| r.model != ccm)
        .map(|r| ModelGap {
            model: r.model,
            against: ccm,
            gap_mm: dist(r.tip, ccm_ref.tip),
            uncertainty_mm: r.uncertainty_mm + ccm_ref.uncertainty_mm,
        })
        .collect();

    // every configuration, then the library's choice per tolerance (as
    // a tip tolerance ran it), built and solved once
    let mut points = Vec::with_capacity(models.len() * config.plans.len());
    for &m in &models {
        for p in &config.plans {
            points.push(Point::new(&act, &p.for_model(m), &load, &opts)?);
        }
    }
    let rows_len = points.len();
    let mut library = Vec::with_capacity(TOLERANCES_MM.len());
    for &tol in &TOLERANCES_MM {
        let solved = PlannedFinger::builder(&act)
            .model(ccm)
            .plan(fpc::Plan::TipTolerance {
                tip_tol_mm: tol,
                start: None,
            })
            .build()
            .map_err(SolveError::from)
            .and_then(|f| f.solve(&load, &opts))
            .ok()
            .and_then(|s| s.refinement);
        if let Some(r) = &solved {
            points.push(Point::new(&act, &r.plan, &load, &opts)?);
        }
        library.push(solved.map(|r| (r, points.len() - 1)));
    }

    // the rounds: each point timed in one batch per round, right after a
    // batch of the N = 8 cold reference
    let n8_plan = Refinement::equal(ccm, 8);
    let mut n8 = Point::new(&act, &n8_plan, &load, &opts)?;
    let batch = config.budget / rounds as u32;
    for _ in 0..rounds {
        for point in &mut points {
            let (t, _) = n8.prepared.batch(&load, &opts, batch, config.min_runs)?;
            n8.rounds_us.push(t);
            point.n8_us.push(t);
            let (t, runs) = point.prepared.batch(&load, &opts, batch, config.min_runs)?;
            point.rounds_us.push(t);
            point.runs += runs;
            step(&mut progress);
        }
    }
    let (t, _) = n8.prepared.batch(&load, &opts, batch, config.min_runs)?;
    n8.rounds_us.push(t);
    // t8: the fastest N = 8 batch, the same estimator as the points'
    let t8 = n8.rounds_us.iter().copied().fold(f64::INFINITY, f64::min);
    let mut paired: Vec<f64> = points.iter().map(|p| p.n8_us[p.fastest()]).collect();
    let paired_median_us = median(&mut paired);
    let library_points = points.split_off(rows_len);

    let mut rows: Vec<AccuracyRow> = points
        .iter()
        .map(|t| {
            let elements = t.result.elements();
            let r = t.result.refinement.as_ref().expect("a refinement's record");
            let own = references
                .iter()
                .find(|x| x.model == r.plan.model)
                .map_or(f64::NAN, |x| dist(r.tip, x.tip));
            AccuracyRow {
                label: r.plan.label(),
                plan: r.plan,
                elements,
                elements_per_level: r.levels.iter().map(|l| l.elements).collect(),
                iterations: r.levels.iter().map(|l| l.iterations).collect(),
                tip: r.tip,
                error_vs_ccm_mm: dist(r.tip, ccm_ref.tip),
                error_vs_own_mm: own,
                estimated_error_mm: r.estimated_tip_error_mm,
                time_us: t.time_us(),
                rounds_us: t.rounds_us.clone(),
                runs: t.runs,
                time_over_n8: t.time_us() / t8,
                pareto: false,
            }
        })
        .collect();
    let same_row_ratio = rows
        .iter()
        .find(|r| r.plan == n8_plan)
        .map(|r| r.time_over_n8);
    let front = pareto(&mut rows);
    let fastest = TOLERANCES_MM
        .iter()
        .zip(library)
        .map(|(&tol, lib)| {
            let fastest = fastest_row(&rows, |r| r.error_vs_ccm_mm <= tol);
            let fastest_estimated = fastest_row(&rows, |r| {
                r.error_vs_ccm_mm <= tol && r.estimated_error_mm.is_some_and(|e| e <= tol)
            });
            let library = lib.map(|(solved, i)| {
                let point = &library_points[i - rows_len];
                let time_us = point.time_us();
                let error = dist(point.result.tip(), ccm_ref.tip);
                LibraryChoice {
                    plan: solved.plan,
                    label: solved.plan.label(),
                    estimated_error_mm: solved.estimated_tip_error_mm,
                    error_vs_ccm_mm: error,
                    time_us,
                    time_over_n8: time_us / t8,
                    meets: error <= tol,
                }
            });
            let library_over_fastest = match (&fastest, &library) {
                (Some(f), Some(l)) => Some(l.time_us / f.time_us),
                _ => None,
            };
            Fastest {
                tolerance_mm: tol,
                fastest,
                fastest_estimated,
                library,
                library_over_fastest,
            }
        })
        .collect();
    Ok(AccuracyStudy {
        build: if cfg!(debug_assertions) {
            "debug"
        } else {
            "release"
        },
        eps0: EPS0,
        tip_force_n: STANDARD_LOAD_N,
        rtol: opts.rtol,
        config: StudyConfig {
            models,
            ..config.clone()
        },
        references,
        gaps,
        n8: TimingReference {
            label: n8_plan.label(),
            time_us: t8,
            iterations: n8
                .result
                .refinement
                .as_ref()
                .expect("a refinement's record")
                .levels[0]
                .iterations,
            all_batches_median_us: median(&mut n8.rounds_us.clone()),
            paired_median_us,
            batches_us: n8.rounds_us,
            same_row_ratio,
        },
        rows,
        front,
        fastest,
    })
}

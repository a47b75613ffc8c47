//! The accuracy-time front: how far the tip of the standard tip-loaded
//! finger is from its N -> infinity limit, against the run time, for every
//! element model, partition kind and extrapolation the library offers
//! (`fpc::Refinement`).
//!
//! Scene: the default actuator with ribs, eps0 = 0.25, no pressure, tip
//! force Fx = 0.939782 N, Fz = 0.521707 N (finger frame), tip-only output
//! at the default Newton tolerance ([`STANDARD_LOAD_N`]).
//!
//! **References.** Per model: the material partition (pieces at most lx /
//! 8; 27 elements for the default actuator) halved [`REFERENCE_LEVELS`] - 1
//! times (27 -> 864 elements), every level solved to a relative residual
//! of [`REFERENCE_RTOL`] by nested iteration, and the tip Richardson-
//! extrapolated from the last two levels, `R(5,6) = t6 + (t6 - t5) / 3`.
//! Every level is converged fully here, independently of how tightly a
//! [`Refiner`] solves its intermediate levels (see
//! [`fpc::INTERMEDIATE_RTOL`]); the refiner's own result for the same plan
//! is reported next to the reference
//! ([`ModelReference::refiner_offset_mm`]). The uncertainty
//! reported, [`ModelReference::uncertainty_mm`], is the library's
//! three-level estimate of an extrapolated refinement applied to the fully
//! converged levels: the distance between the extrapolations from levels
//! (4,5) and (5,6), `|R(5,6) - R(4,5)|`. (The refinement's own
//! `estimated_tip_error_mm` is that same distance computed from its less
//! converged levels; it is reported as
//! [`ModelReference::refiner_estimate_mm`].) The change before it,
//! `|R(4,5) - R(3,4)|`, is reported too: their ratio shows how regularly
//! the extrapolations converge (1/2: the distance is the sum of the
//! remaining geometric series).
//!
//! **Orders.** Per model and partition kind, the observed orders
//! `log2(|t_l - t_{l-1}| / |t_{l+1} - t_l|)` of successive levels: the
//! reference's material levels, and equal elements from N = 8 doubled to
//! 512, both fully converged.
//!
//! **Configurations** ([`CONFIGURATIONS`], one table applied to every
//! model): each is built once ([`Refiner::new`], outside the timed region),
//! its coarsest finger's unloaded equilibrium is solved (outside too), and
//! the timed call is `refiner.solve(&load, Some(&unloaded.coefficients),
//! &opts)`. Every configuration is timed in [`StudyConfig::rounds`]
//! rounds over all configurations; in each round one batch of calls runs
//! until both [`StudyConfig::min_runs`] calls and its share of
//! [`StudyConfig::budget`] have passed, and the time reported is the
//! fastest round's median (on a shared machine another process's load
//! comes and goes for tens to hundreds of milliseconds and only ever adds
//! time; the fastest round is the estimate of the time on a quiet
//! machine). The N = 8 equal cold solve (the
//! `loaded_cold` case of `fpc timing`) is measured the same way in a batch
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
//! (`fpc::solve_to_tip_tolerance`, the plan as it ran, timed the same
//! way).

use std::time::{Duration, Instant};

use fpc::{
    solve_to_tip_tolerance, Actuator, Coefficients, Level, Load, ModelId, PartitionKind, Refined,
    Refinement, Refiner, SolveError, SolveOptions,
};
use serde::Serialize;

/// The prestrain of the standard case.
pub const EPS0: f64 = 0.25;

/// The standard tip force (N, finger frame): Fx, Fz.
pub const STANDARD_LOAD_N: [f64; 2] = [0.939782, 0.521707];

/// Relative residual every reference level is solved to.
pub const REFERENCE_RTOL: f64 = 1e-13;

/// The references' material partition: pieces at most lx / this.
pub const REFERENCE_START: usize = 8;

/// Levels of the references (27 -> 864 elements).
pub const REFERENCE_LEVELS: usize = 6;

/// Equal elements of the coarsest level of the equal-partition orders.
pub const EQUAL_ORDER_START: usize = 8;

/// Levels of the equal-partition orders in a full study (N = 8 -> 512).
pub const EQUAL_ORDER_LEVELS: usize = 7;

/// Relative difference of times taken as equal on the front and for the
/// fastest configuration per tolerance: the spread of the fastest batches
/// of one configuration over repeated runs (about 1 %), with a margin.
pub const TIME_RESOLUTION: f64 = 0.03;

/// The tolerances (mm) whose fastest configuration is reported.
pub const TOLERANCES_MM: [f64; 3] = [1.0, 0.1, 0.01];

/// A configuration without its model: partition kind, coarsest partition,
/// levels and extrapolation (see [`Refinement`]).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct Plan {
    /// Where element boundaries go.
    pub partition: PartitionKind,
    /// Equal: the coarsest N. Material: pieces at most lx / `start`.
    pub start: usize,
    /// Number of levels solved.
    pub levels: usize,
    /// Richardson extrapolation of the tip from the last two levels.
    pub extrapolate: bool,
}

impl Plan {
    /// One solve on `n` equal elements.
    pub const fn equal(n: usize) -> Plan {
        Plan {
            partition: PartitionKind::Equal,
            start: n,
            levels: 1,
            extrapolate: false,
        }
    }

    /// The material partition from pieces at most lx / 8, on `levels` levels.
    pub const fn material(levels: usize, extrapolate: bool) -> Plan {
        Plan {
            partition: PartitionKind::Material,
            start: REFERENCE_START,
            levels,
            extrapolate,
        }
    }

    /// The plan for `model`.
    pub fn for_model(self, model: ModelId) -> Refinement {
        Refinement {
            model,
            partition: self.partition,
            start: self.start,
            levels: self.levels,
            extrapolate: self.extrapolate,
        }
    }
}

/// Every configuration of a full study, applied to every model: equal N
/// from 1 to 512 (one solve), the material partition on 1 to 5 levels, and
/// on 2 to 5 levels with extrapolation.
pub const CONFIGURATIONS: [Plan; 19] = [
    Plan::equal(1),
    Plan::equal(2),
    Plan::equal(4),
    Plan::equal(8),
    Plan::equal(16),
    Plan::equal(32),
    Plan::equal(64),
    Plan::equal(128),
    Plan::equal(256),
    Plan::equal(512),
    Plan::material(1, false),
    Plan::material(2, false),
    Plan::material(3, false),
    Plan::material(4, false),
    Plan::material(5, false),
    Plan::material(2, true),
    Plan::material(3, true),
    Plan::material(4, true),
    Plan::material(5, true),
];

/// A reduced list for tests and previews ([`StudyConfig::quick`], `fpc
/// accuracy --quick`).
pub const QUICK_CONFIGURATIONS: [Plan; 6] = [
    Plan::equal(2),
    Plan::equal(8),
    Plan::equal(32),
    Plan::material(1, false),
    Plan::material(2, false),
    Plan::material(2, true),
];

/// What a study runs and how long it times each point.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct StudyConfig {
    /// The configurations, applied to every model.
    pub plans: Vec<Plan>,
    /// The models (the default model, the CCM, is always among them).
    pub models: Vec<ModelId>,
    /// Least wall-clock time spent timing each point, over all rounds.
    #[serde(serialize_with = "as_ms", rename = "budget_ms")]
    pub budget: Duration,
    /// Least number of timed runs per point and round.
    pub min_runs: usize,
    /// Rounds over all points: each point is timed once per round, on
    /// `budget / rounds`, and its time is the fastest round's median (a
    /// load that comes and goes on a shared machine then costs rounds, not
    /// the point).
    pub rounds: usize,
    /// Levels of the equal-partition orders (from N = 8).
    pub equal_order_levels: usize,
}

fn as_ms<S: serde::Serializer>(d: &Duration, s: S) -> Result<S::Ok, S::Error> {
    s.serialize_f64(d.as_secs_f64() * 1e3)
}

impl StudyConfig {
    /// Every model, [`CONFIGURATIONS`], 7 rounds, 30 ms per point and at
    /// least 7 runs per point and round.
    pub fn full() -> StudyConfig {
        StudyConfig {
            plans: CONFIGURATIONS.to_vec(),
            models: ModelId::ALL.to_vec(),
            budget: Duration::from_millis(30),
            min_runs: 7,
            rounds: 7,
            equal_order_levels: EQUAL_ORDER_LEVELS,
        }
    }

    /// Every model, [`QUICK_CONFIGURATIONS`], equal orders up to N = 64,
    /// 2 rounds, 1 ms per point and at least 3 runs per point and round.
    pub fn quick() -> StudyConfig {
        StudyConfig {
            plans: QUICK_CONFIGURATIONS.to_vec(),
            models: ModelId::ALL.to_vec(),
            budget: Duration::from_millis(1),
            min_runs: 3,
            rounds: 2,
            equal_order_levels: 4,
        }
    }

    /// With this time budget per point.
    pub fn with_budget(mut self, budget: Duration) -> StudyConfig {
        self.budget = budget;
        self
    }
}

/// A sequence of fully converged levels and its observed orders.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Convergence {
    /// The partition kind.
    pub partition: PartitionKind,
    /// Elements per level.
    pub elements: Vec<usize>,
    /// Tip per level (mm).
    #[serde(rename = "tips_mm")]
    pub tips: Vec<[f64; 2]>,
    /// `|t_l - t_{l-1}|` for l = 1, 2, ... (mm).
    pub changes_mm: Vec<f64>,
    /// `log2` of the ratios of successive changes (one fewer than the
    /// changes; NaN, written `null`, where a change is 0).
    pub orders: Vec<f64>,
}

impl Convergence {
    fn new(partition: PartitionKind, levels: &[Level]) -> Convergence {
        let tips: Vec<[f64; 2]> = levels.iter().map(|l| l.tip).collect();
        let changes_mm: Vec<f64> = tips.windows(2).map(|w| dist(w[1], w[0])).collect();
        let orders = changes_mm.windows(2).map(|w| order(w[0], w[1])).collect();
        Convergence {
            partition,
            elements: levels.iter().map(|l| l.elements).collect(),
            tips,
            changes_mm,
            orders,
        }
    }

    /// The order from the three finest levels (NaN with fewer).
    pub fn finest_order(&self) -> f64 {
        self.orders.last().copied().unwrap_or(f64::NAN)
    }
}

/// `log2(coarse / fine)`, NaN when either change is not positive.
fn order(coarse: f64, fine: f64) -> f64 {
    if coarse > 0.0 && fine > 0.0 {
        (coarse / fine).log2()
    } else {
        f64::NAN
    }
}

/// One model's converged reference.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelReference {
    /// The model.
    pub model: ModelId,
    /// The refinement (every level solved to [`REFERENCE_RTOL`]).
    pub plan: Refinement,
    /// The reference tip: `R(5,6)` (mm).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// `|R(5,6) - R(4,5)|` (mm): the uncertainty reported.
    pub uncertainty_mm: f64,
    /// `|R(4,5) - R(3,4)|` (mm).
    pub previous_change_mm: f64,
    /// The extrapolations `R(l-1,l)` for l = 2..=6 (mm).
    pub extrapolations_mm: Vec<[f64; 2]>,
    /// The material levels and their orders.
    pub material: Convergence,
    /// Equal elements from N = 8 and their orders.
    pub equal: Convergence,
    /// The same plan run by [`Refiner::solve`] (intermediate levels to
    /// `INTERMEDIATE_RTOL`): its tip (mm).
    pub refiner_tip_mm: [f64; 2],
    /// Its `estimated_tip_error_mm`.
    pub refiner_estimate_mm: Option<f64>,
    /// The distance of its tip from the reference tip (mm).
    pub refiner_offset_mm: f64,
}

/// The distance between two models' references.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ModelGap {
    /// The model compared with the CCM.
    pub model: ModelId,
    /// The CCM (the default model).
    pub against: ModelId,
    /// Distance between the two references' tips (mm).
    pub gap_mm: f64,
    /// The sum of the two references' uncertainties (mm).
    pub uncertainty_mm: f64,
}

/// The N = 8 equal cold solve, measured in batches spread over the run.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TimingReference {
    /// Its configuration (`ccm/equal/8x1`).
    pub label: String,
    /// `t8` (us): the fastest batch's median.
    pub time_us: f64,
    /// The median of every batch's median (us).
    pub all_batches_median_us: f64,
    /// The median, over the timed points, of the batch measured right
    /// before each point's fastest round (us).
    pub paired_median_us: f64,
    /// Every batch's median (us), in the order measured.
    pub batches_us: Vec<f64>,
    /// `time / t8` of the row that is this same configuration (`None`
    /// without one): 1 up to the timing noise of the run.
    pub same_row_ratio: Option<f64>,
    /// Newton iterations of the solve.
    pub iterations: usize,
}

/// One configuration, measured.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AccuracyRow {
    /// `model/partition/startxlevels[+richardson]`.
    pub label: String,
    /// The configuration.
    pub plan: Refinement,
    /// Elements of the finest level.
    pub elements: usize,
    /// Elements of every level, coarsest first.
    pub elements_per_level: Vec<usize>,
    /// Newton iterations of every level, coarsest first.
    pub iterations: Vec<usize>,
    /// The tip the configuration reports (extrapolated or the finest
    /// level's; mm).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// Its distance from the CCM reference (mm).
    pub error_vs_ccm_mm: f64,
    /// Its distance from its own model's reference (mm).
    pub error_vs_own_mm: f64,
    /// The refinement's own estimate (mm; `None` with one level).
    pub estimated_error_mm: Option<f64>,
    /// Time of the timed call (us): the fastest round's median.
    pub time_us: f64,
    /// The median of each round (us).
    pub rounds_us: Vec<f64>,
    /// Timed runs, over all rounds.
    pub runs: usize,
    /// `time_us / t8`.
    pub time_over_n8: f64,
    /// On the Pareto front (time against the error vs the CCM reference).
    pub pareto: bool,
}

/// A row of the Pareto front.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct FrontPoint {
    /// Index into [`AccuracyStudy::rows`].
    pub row: usize,
    /// Its label.
    pub label: String,
    /// Its time (us).
    pub time_us: f64,
    /// Its time over t8.
    pub time_over_n8: f64,
    /// Its error vs the CCM reference (mm).
    pub error_vs_ccm_mm: f64,
}

/// What the library picks for a tolerance, measured like the rows.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct LibraryChoice {
    /// `Refinement::for_tolerance` as `solve_to_tip_tolerance` ran it
    /// (levels as solved).
    pub plan: Refinement,
    /// Its label.
    pub label: String,
    /// Its estimate when it stopped (mm).
    pub estimated_error_mm: Option<f64>,
    /// Its error vs the CCM reference (mm).
    pub error_vs_ccm_mm: f64,
    /// Its median time (us), timed like the rows.
    pub time_us: f64,
    /// Its time over t8.
    pub time_over_n8: f64,
    /// The error is within the tolerance.
    pub meets: bool,
}

/// The fastest configuration within a tolerance.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fastest {
    /// The tolerance (mm, error vs the CCM reference).
    pub tolerance_mm: f64,
    /// The fastest row within it (`None`: no row; times within
    /// [`TIME_RESOLUTION`] count as equal, the more accurate row is taken).
    pub fastest: Option<FrontPoint>,
    /// The fastest row within it whose own error estimate is within it too
    /// (a refinement that knows it met the tolerance, as
    /// `solve_to_tip_tolerance` must).
    pub fastest_estimated: Option<FrontPoint>,
    /// The library's choice (`None`: it failed).
    pub library: Option<LibraryChoice>,
    /// The library's time over the fastest row's (`None` without both).
    pub library_over_fastest: Option<f64>,
}

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

fn richardson(coarse: [f64; 2], fine: [f64; 2]) -> [f64; 2] {
    [
        fine[0] + (fine[0] - coarse[0]) / 3.0,
        fine[1] + (fine[1] - coarse[1]) / 3.0,
    ]
}

fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// The standard tip load.
pub fn standard_load() -> Load {
    Load::unloaded().with_tip_force(STANDARD_LOAD_N[0], STANDARD_LOAD_N[1])
}

/// Each half of every element starts from its parent's coefficients.
fn halved(k: &Coefficients) -> Result<Coefficients, SolveError> {
    let mut values = Vec::with_capacity(2 * k.as_slice().len());
    for e in k.iter() {
        values.extend_from_slice(e);
        values.extend_from_slice(e);
    }
    Ok(Coefficients::new(k.per_element(), values)?)
}

/// Every level of `plan` solved to `opts` by nested iteration.
fn converged_levels(
    act: &Actuator,
    load: &Load,
    plan: &Refinement,
    opts: &SolveOptions,
) -> Result<Vec<Level>, SolveError> {
    let mut refiner = Refiner::new(act, true, plan)?;
    let mut levels = Vec::with_capacity(plan.levels);
    let mut prev: Option<Coefficients> = None;
    for level in 0..plan.levels {
        let finger = refiner.finger(level)?;
        let sol = match &prev {
            Some(k) if 2 * k.elements() == finger.len() => finger
                .solve_from(load, &halved(k)?, opts)
                .or_else(|_| finger.solve(load, opts))?,
            _ => finger.solve(load, opts)?,
        };
        levels.push(Level {
            elements: finger.len(),
            tip: sol.tip,
            end_angle: sol.end_angle,
            iterations: sol.report.iterations,
        });
        prev = Some(sol.coefficients);
    }
    Ok(levels)
}

/// The reference of `model` and its orders.
fn reference(
    act: &Actuator,
    load: &Load,
    model: ModelId,
    equal_levels: usize,
) -> Result<ModelReference, SolveError> {
    let opts = SolveOptions {
        rtol: REFERENCE_RTOL,
        ..SolveOptions::default().tip_only()
    };
    let plan = Plan::material(REFERENCE_LEVELS, true).for_model(model);
    let levels = converged_levels(act, load, &plan, &opts)?;
    let material = Convergence::new(PartitionKind::Material, &levels);
    let extrapolations: Vec<[f64; 2]> = material
        .tips
        .windows(2)
        .map(|w| richardson(w[0], w[1]))
        .collect();
    let n = extrapolations.len();
    let tip = extrapolations[n - 1];
    let back = |k: usize| {
        if n > k {
            dist(extrapolations[n - k], extrapolations[n - k - 1])
        } else {
            f64::NAN
        }
    };
    let equal_plan = Refinement {
        start: EQUAL_ORDER_START,
        levels: equal_levels.max(1),
        ..Plan::equal(EQUAL_ORDER_START).for_model(model)
    };
    let equal = Convergence::new(
        PartitionKind::Equal,
        &converged_levels(act, load, &equal_plan, &opts)?,
    );
    let refined = Refiner::new(act, true, &plan)?.solve(load, None, &opts)?;
    Ok(ModelReference {
        model,
        plan,
        tip,
        uncertainty_mm: back(1),
        previous_change_mm: back(2),
        extrapolations_mm: extrapolations,
        material,
        equal,
        refiner_tip_mm: refined.tip,
        refiner_estimate_mm: refined.estimated_tip_error_mm,
        refiner_offset_mm: dist(refined.tip, tip),
    })
}

/// A configuration ready to be timed: fingers built, the coarsest level's
/// unloaded equilibrium solved.
struct Prepared {
    refiner: Refiner,
    unloaded: Coefficients,
}

impl Prepared {
    fn new(act: &Actuator, plan: &Refinement, opts: &SolveOptions) -> Result<Prepared, SolveError> {
        let mut refiner = Refiner::new(act, true, plan)?;
        let unloaded = refiner
            .finger(0)?
            .solve(&Load::unloaded(), opts)?
            .coefficients;
        Ok(Prepared { refiner, unloaded })
    }

    /// The result of one call (untimed; it also warms the caches).
    fn result(&mut self, load: &Load, opts: &SolveOptions) -> Result<Refined, SolveError> {
        self.refiner.solve(load, Some(&self.unloaded), opts)
    }

    /// One batch: the median time (us) of repeated calls until both
    /// `budget` and `min_runs` are spent, and the number of calls.
    fn batch(
        &mut self,
        load: &Load,
        opts: &SolveOptions,
        budget: Duration,
        min_runs: usize,
    ) -> Result<(f64, usize), SolveError> {
        /// Bounds the runs of a very fast point.
        const MAX_RUNS: usize = 100_000;
        let mut samples = Vec::new();
        let start = Instant::now();
        while (start.elapsed() < budget || samples.len() < min_runs.max(1))
            && samples.len() < MAX_RUNS
        {
            let t = Instant::now();
            let r = self.refiner.solve(load, Some(&self.unloaded), opts)?;
            samples.push(t.elapsed().as_secs_f64() * 1e6);
            std::hint::black_box(r);
        }
        let runs = samples.len();
        Ok((median(&mut samples), runs))
    }
}

/// A configuration being timed over the rounds.
struct Point {
    prepared: Prepared,
    result: Refined,
    rounds_us: Vec<f64>,
    /// The N = 8 batch measured right before each round's.
    n8_us: Vec<f64>,
    runs: usize,
}

impl Point {
    fn new(
        act: &Actuator,
        plan: &Refinement,
        load: &Load,
        opts: &SolveOptions,
    ) -> Result<Point, SolveError> {
        let mut prepared = Prepared::new(act, plan, opts)?;
        let result = prepared.result(load, opts)?;
        Ok(Point {
            prepared,
            result,
            rounds_us: Vec::new(),
            n8_us: Vec::new(),
            runs: 0,
        })
    }

    /// The fastest round.
    fn fastest(&self) -> usize {
        (0..self.rounds_us.len())
            .min_by(|&a, &b| self.rounds_us[a].total_cmp(&self.rounds_us[b]))
            .unwrap_or(0)
    }

    /// The fastest round's median (us).
    fn time_us(&self) -> f64 {
        self.rounds_us
            .get(self.fastest())
            .copied()
            .unwrap_or(f64::NAN)
    }
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
    // solve_to_tip_tolerance ran it), built and solved once
    let mut points = Vec::with_capacity(models.len() * config.plans.len());
    for &m in &models {
        for p in &config.plans {
            points.push(Point::new(&act, &p.for_model(m), &load, &opts)?);
        }
    }
    let rows_len = points.len();
    let mut library = Vec::with_capacity(TOLERANCES_MM.len());
    for &tol in &TOLERANCES_MM {
        let solved = solve_to_tip_tolerance(ccm, &act, true, &load, tol, None, &opts).ok();
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
            let r = &t.result;
            let own = references
                .iter()
                .find(|x| x.model == r.plan.model)
                .map_or(f64::NAN, |x| dist(r.tip, x.tip));
            AccuracyRow {
                label: r.plan.label(),
                plan: r.plan,
                elements: r.elements,
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
                let error = dist(point.result.tip, ccm_ref.tip);
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
            iterations: n8.result.levels[0].iterations,
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

fn front_point(i: usize, r: &AccuracyRow) -> FrontPoint {
    FrontPoint {
        row: i,
        label: r.label.clone(),
        time_us: r.time_us,
        time_over_n8: r.time_over_n8,
        error_vs_ccm_mm: r.error_vs_ccm_mm,
    }
}

/// The fastest row meeting `ok`: among those within [`TIME_RESOLUTION`]
/// of the fastest, the most accurate.
fn fastest_row(rows: &[AccuracyRow], ok: impl Fn(&AccuracyRow) -> bool) -> Option<FrontPoint> {
    let t = rows
        .iter()
        .filter(|r| ok(r))
        .map(|r| r.time_us)
        .fold(f64::INFINITY, f64::min);
    rows.iter()
        .enumerate()
        .filter(|(_, r)| ok(r) && r.time_us <= t * (1.0 + TIME_RESOLUTION))
        .min_by(|a, b| a.1.error_vs_ccm_mm.total_cmp(&b.1.error_vs_ccm_mm))
        .map(|(i, r)| front_point(i, r))
}

/// Marks the rows on the Pareto front of time against the error vs the
/// CCM reference and returns them, fastest first. A row is dominated by
/// one at most [`TIME_RESOLUTION`] slower that is at least as accurate
/// (and strictly faster or more accurate): the extrapolation of a
/// refinement costs nothing, so a row without it is never on the front
/// merely by timing noise.
fn pareto(rows: &mut [AccuracyRow]) -> Vec<FrontPoint> {
    let dominated = |i: usize, rows: &[AccuracyRow]| {
        let (t, e) = (rows[i].time_us, rows[i].error_vs_ccm_mm);
        rows.iter().enumerate().any(|(j, r)| {
            j != i
                && r.time_us <= t * (1.0 + TIME_RESOLUTION)
                && r.error_vs_ccm_mm <= e
                && (r.time_us < t || r.error_vs_ccm_mm < e)
        })
    };
    let on: Vec<bool> = (0..rows.len())
        .map(|i| {
            rows[i].time_us.is_finite()
                && rows[i].error_vs_ccm_mm.is_finite()
                && !dominated(i, rows)
        })
        .collect();
    let mut front = Vec::new();
    for (i, r) in rows.iter_mut().enumerate() {
        r.pareto = on[i];
        if on[i] {
            front.push(front_point(i, r));
        }
    }
    front.sort_by(|a, b| {
        a.time_us
            .total_cmp(&b.time_us)
            .then(b.error_vs_ccm_mm.total_cmp(&a.error_vs_ccm_mm))
    });
    front
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(time_us: f64, error: f64) -> AccuracyRow {
        let plan = Refinement::equal(ModelId::default(), 8);
        AccuracyRow {
            label: plan.label(),
            plan,
            elements: 8,
            elements_per_level: vec![8],
            iterations: vec![6],
            tip: [0.0; 2],
            error_vs_ccm_mm: error,
            error_vs_own_mm: error,
            estimated_error_mm: None,
            time_us,
            rounds_us: vec![time_us],
            runs: 1,
            time_over_n8: 1.0,
            pareto: false,
        }
    }

    #[test]
    fn the_front_keeps_the_undominated_rows_fastest_first() {
        let mut rows = vec![
            row(10.0, 1.0),
            row(5.0, 2.0),
            row(20.0, 0.1),
            row(15.0, 1.0), // dominated by the first
            row(10.0, 1.0), // a tie: neither dominates
            row(30.0, f64::NAN),
        ];
        let front = pareto(&mut rows);
        let on: Vec<usize> = front.iter().map(|f| f.row).collect();
        assert_eq!(on, [1, 0, 4, 2]);
        assert_eq!(
            rows.iter().map(|r| r.pareto).collect::<Vec<_>>(),
            [true, true, true, false, true, false]
        );
    }

    #[test]
    fn a_slightly_slower_more_accurate_row_dominates() {
        let mut rows = vec![
            row(10.0, 1.0),
            row(10.2, 0.5),
            row(5.0, 2.0),
            row(10.6, 0.4),
        ];
        let front = pareto(&mut rows);
        let on: Vec<usize> = front.iter().map(|f| f.row).collect();
        assert_eq!(on, [2, 1, 3]);
        let best = fastest_row(&rows, |r| r.error_vs_ccm_mm <= 1.0).unwrap();
        assert_eq!(best.row, 1, "within the resolution the more accurate");
        assert!(fastest_row(&rows, |r| r.error_vs_ccm_mm < 0.1).is_none());
    }

    #[test]
    fn orders_and_extrapolation() {
        assert!((order(4.0, 1.0) - 2.0).abs() < 1e-15);
        assert!(order(0.0, 1.0).is_nan());
        // exact for a second-order sequence t(h) = t* + c h^2
        let t = |h: f64| [1.0 + 3.0 * h * h, -2.0 - h * h];
        let r = richardson(t(0.2), t(0.1));
        assert!(dist(r, [1.0, -2.0]) < 1e-14);
        let mut v = [3.0, 1.0, 2.0];
        assert_eq!(median(&mut v), 2.0);
    }
}

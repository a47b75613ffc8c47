//! The batch timing: each configuration timed in one batch per round, the
//! N = 8 cold solve in a batch right before each, fastest round reported.

use std::time::{Duration, Instant};

use fpc::plan::Refinement;
use fpc::{Actuator, Coefficients, Load, PlannedFinger, SolveError, SolveOptions, Solved};
use serde::Serialize;

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

pub(super) fn median(v: &mut [f64]) -> f64 {
    v.sort_by(f64::total_cmp);
    v.get(v.len() / 2).copied().unwrap_or(f64::NAN)
}

/// A configuration ready to be timed: fingers built, the coarsest level's
/// unloaded equilibrium solved.
pub(super) struct Prepared {
    finger: PlannedFinger,
    unloaded: Coefficients,
}

impl Prepared {
    fn new(act: &Actuator, plan: &Refinement, opts: &SolveOptions) -> Result<Prepared, SolveError> {
        let finger = PlannedFinger::builder(act).refinement(plan).build()?;
        let unloaded = finger.fingers()[0]
            .solve(&Load::unloaded(), opts)?
            .coefficients;
        Ok(Prepared { finger, unloaded })
    }

    /// The result of one call (untimed; it also warms the caches).
    fn result(&mut self, load: &Load, opts: &SolveOptions) -> Result<Solved, SolveError> {
        self.finger.solve_from(load, &self.unloaded, opts)
    }

    /// One batch: the median time (us) of repeated calls until both
    /// `budget` and `min_runs` are spent, and the number of calls.
    pub(super) fn batch(
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
            let r = self.finger.solve_from(load, &self.unloaded, opts)?;
            samples.push(t.elapsed().as_secs_f64() * 1e6);
            std::hint::black_box(r);
        }
        let runs = samples.len();
        Ok((median(&mut samples), runs))
    }
}

/// A configuration being timed over the rounds.
pub(super) struct Point {
    pub(super) prepared: Prepared,
    pub(super) result: Solved,
    pub(super) rounds_us: Vec<f64>,
    /// The N = 8 batch measured right before each round's.
    pub(super) n8_us: Vec<f64>,
    pub(super) runs: usize,
}

impl Point {
    pub(super) fn new(
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
    pub(super) fn fastest(&self) -> usize {
        (0..self.rounds_us.len())
            .min_by(|&a, &b| self.rounds_us[a].total_cmp(&self.rounds_us[b]))
            .unwrap_or(0)
    }

    /// The fastest round's median (us).
    pub(super) fn time_us(&self) -> f64 {
        self.rounds_us
            .get(self.fastest())
            .copied()
            .unwrap_or(f64::NAN)
    }
}

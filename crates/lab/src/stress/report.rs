//! What a run reports: each case's outcome and measurements, the tallies
//! over classes of cases and the run's summary queries.

use std::collections::BTreeMap;
use std::fmt;
use std::time::Duration;

use fpc_newton::Termination;

use fpc::Warning;

use super::inputs::{PartitionKey, StressInputs};
use super::StressConfig;

/// How one case ended.
#[derive(Debug, Clone, PartialEq)]
pub enum StressOutcome {
    /// Solved, and the solution passed every check (it may carry validity
    /// findings: [`StressCase::findings`]).
    Converged,
    /// The solver reported that it did not converge (an honest failure).
    Failed {
        /// Why Newton (or continuation) stopped.
        reason: Termination,
        /// The element whose decoupled solve failed, if any.
        element: Option<usize>,
        /// The solver's last relative residual.
        relative_residual: f64,
    },
    /// Every draw was rejected by validation (expected, not a failure).
    Rejected {
        /// The last rejection.
        error: String,
    },
    /// A returned solution failed a check (a bug).
    SilentlyWrong {
        /// What failed.
        what: String,
    },
    /// The structured count of negative eigenvalues disagrees with the
    /// dense count (a bug).
    WrongStability {
        /// [`Solution::negative_eigenvalues`](fpc::Solution::negative_eigenvalues).
        reported: usize,
        /// Dense eigenvalues below `-tau`.
        below: usize,
        /// Dense eigenvalues below `+tau`.
        within: usize,
    },
    /// A panic was caught (a bug).
    Panicked {
        /// The panic message.
        message: String,
    },
}

impl StressOutcome {
    /// A short label: `converged`, `failed`, `rejected`, `silently_wrong`,
    /// `wrong_stability`, `panic`.
    pub fn label(&self) -> &'static str {
        match self {
            StressOutcome::Converged => "converged",
            StressOutcome::Failed { .. } => "failed",
            StressOutcome::Rejected { .. } => "rejected",
            StressOutcome::SilentlyWrong { .. } => "silently_wrong",
            StressOutcome::WrongStability { .. } => "wrong_stability",
            StressOutcome::Panicked { .. } => "panic",
        }
    }

    /// True for panics, silently wrong answers and wrong stability.
    pub fn is_bug(&self) -> bool {
        matches!(
            self,
            StressOutcome::SilentlyWrong { .. }
                | StressOutcome::WrongStability { .. }
                | StressOutcome::Panicked { .. }
        )
    }
}

impl fmt::Display for StressOutcome {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            StressOutcome::Converged => f.write_str("converged"),
            StressOutcome::Failed {
                reason,
                element,
                relative_residual,
            } => {
                write!(f, "failed ({})", reason_name(*reason))?;
                if let Some(e) = element {
                    write!(f, " at element {e}")?;
                }
                write!(f, ", residual {relative_residual:.2e}")
            }
            StressOutcome::Rejected { error } => write!(f, "rejected input: {error}"),
            StressOutcome::SilentlyWrong { what } => write!(f, "SILENTLY WRONG: {what}"),
            StressOutcome::WrongStability {
                reported,
                below,
                within,
            } => write!(
                f,
                "WRONG STABILITY: {reported} negative eigenvalue(s) reported, dense count {below} below -tau and {within} below +tau"
            ),
            StressOutcome::Panicked { message } => write!(f, "PANIC: {message}"),
        }
    }
}

/// The short name of a termination reason (`MaxIterations`, ...).
pub fn reason_name(r: Termination) -> String {
    format!("{r:?}")
}

/// A stable name of a validity finding: `element_slope`,
/// `midplane_strain`, `prestressed_strain`, `self_contact`, or the
/// warning's own kind.
pub fn finding_name(w: &Warning) -> &'static str {
    match w {
        Warning::MidplaneStrain { .. } => "midplane_strain",
        Warning::PrestressedStrain { .. } => "prestressed_strain",
        other => other.kind(),
    }
}

/// One case: inputs, outcome and measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct StressCase {
    /// Index in the run (with the seed, it fixes the inputs).
    pub index: usize,
    /// The inputs of the last draw.
    pub inputs: StressInputs,
    /// [`inside_envelope`](super::inside_envelope) of the inputs.
    pub inside_envelope: bool,
    /// Draws rejected by validation before the one kept.
    pub rejected_draws: usize,
    /// The field each rejected draw was rejected for
    /// (`actuator.geometry.h2`, `partition.lengths[3]`, ...).
    pub rejected_fields: Vec<String>,
    /// How it ended.
    pub outcome: StressOutcome,
    /// Elements of the solution (the automatic partition's choice).
    pub solved_elements: Option<usize>,
    /// Rounds of splits the automatic partition took (`Solved::splits`:
    /// halvings of a start that did not solve included).
    pub refinements: Option<usize>,
    /// Newton iterations (returned solutions and reported failures).
    pub iterations: Option<usize>,
    /// Continuation steps (returned solutions).
    pub continuation_steps: Option<usize>,
    /// The iterations by phase and the globalisation's counts (returned
    /// solutions; [`fpc::finger::StepCounts`]).
    pub steps: Option<fpc::finger::StepCounts>,
    /// Recomputed `||g_scaled||_inf / stiffness` (returned solutions).
    pub residual: Option<f64>,
    /// [`Solution::negative_eigenvalues`](fpc::Solution::negative_eigenvalues) (returned solutions).
    pub negative_eigenvalues: Option<usize>,
    /// Dense eigenvalue counts below `-tau` and below `+tau` (solutions on
    /// at most [`DENSE_CHECK_MAX_ELEMENTS`](super::DENSE_CHECK_MAX_ELEMENTS) elements).
    pub dense_negative: Option<(usize, usize)>,
    /// Smallest scaled-Hessian eigenvalue over the stiffness scale (at most
    /// [`CONDITIONING_MAX_ELEMENTS`](super::CONDITIONING_MAX_ELEMENTS) elements).
    pub min_eig: Option<f64>,
    /// `lambda_min / G` (module docs).
    pub conditioning: Option<f64>,
    /// Largest element end rotation `|eta_i|` (rad) of a returned solution.
    pub max_rotation: Option<f64>,
    /// The distinct validity findings of a returned solution
    /// ([`finding_name`]), in order.
    pub findings: Vec<&'static str>,
    /// The distinct notes of a returned solution (the kinds of its
    /// warnings that are not validity findings, such as the automatic
    /// partition's `partition_fold` and `partition_split_failed`), in order.
    pub notes: Vec<&'static str>,
    /// Findings that a re-check at [`FINE_VALIDITY_SAMPLES`](super::FINE_VALIDITY_SAMPLES) per element
    /// adds to the solution's (a measurement, not a failure).
    pub missed_findings: Vec<&'static str>,
    /// Wall-clock time of the case (s).
    pub seconds: f64,
}

impl StressCase {
    /// Converged with at least one validity finding.
    pub fn warned(&self) -> bool {
        self.outcome == StressOutcome::Converged && !self.findings.is_empty()
    }

    /// Converged at an equilibrium the structured count calls unstable.
    pub fn unstable(&self) -> bool {
        self.outcome == StressOutcome::Converged && self.negative_eigenvalues.is_some_and(|k| k > 0)
    }
}

/// Counts over a class of cases with legal inputs.
#[derive(Debug, Clone, Default, PartialEq, serde::Serialize)]
pub struct Tally {
    /// Cases with legal inputs.
    pub cases: usize,
    /// Converged (and passed every check), with or without findings.
    pub converged: usize,
    /// Converged with validity findings.
    pub warned: usize,
    /// Honest failures to converge.
    pub failed: usize,
    /// Failures by reason name.
    pub failed_by_reason: BTreeMap<String, usize>,
    /// Converged cases per finding (a case counts once per kind).
    pub findings: BTreeMap<String, usize>,
    /// Converged at an unstable equilibrium.
    pub unstable: usize,
    /// Panics, silently wrong answers and wrong stability.
    pub bugs: usize,
}

impl Tally {
    fn add(&mut self, c: &StressCase) {
        if matches!(c.outcome, StressOutcome::Rejected { .. }) {
            return;
        }
        self.cases += 1;
        match &c.outcome {
            StressOutcome::Converged => {
                self.converged += 1;
                if c.warned() {
                    self.warned += 1;
                }
                if c.unstable() {
                    self.unstable += 1;
                }
                for f in &c.findings {
                    *self.findings.entry((*f).to_string()).or_insert(0) += 1;
                }
            }
            StressOutcome::Failed { reason, .. } => {
                self.failed += 1;
                *self
                    .failed_by_reason
                    .entry(reason_name(*reason))
                    .or_insert(0) += 1;
            }
            _ => self.bugs += 1,
        }
    }

    /// Converged without findings.
    pub fn clean(&self) -> usize {
        self.converged - self.warned
    }

    /// Converged over cases (`None` without cases).
    pub fn convergence_rate(&self) -> Option<f64> {
        (self.cases > 0).then(|| self.converged as f64 / self.cases as f64)
    }
}

/// Order statistics of a count (nearest rank).
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
pub struct Quantiles {
    /// How many values.
    pub n: usize,
    /// The median.
    pub median: usize,
    /// The 90th percentile.
    pub p90: usize,
    /// The 99th percentile.
    pub p99: usize,
    /// The largest.
    pub max: usize,
}

impl Quantiles {
    /// The quantiles of `v` (sorted in place); `None` when empty.
    pub fn of(v: &mut [usize]) -> Option<Quantiles> {
        v.sort_unstable();
        let n = v.len();
        let at = |q: f64| v[((q * n as f64).ceil() as usize).clamp(1, n) - 1];
        (n > 0).then(|| Quantiles {
            n,
            median: at(0.5),
            p90: at(0.9),
            p99: at(0.99),
            max: v[n - 1],
        })
    }
}

/// The outcome of a stress run.
#[derive(Debug, Clone, PartialEq)]
pub struct StressReport {
    /// The settings.
    pub config: StressConfig,
    /// Wall-clock time of the run.
    pub elapsed: Duration,
    /// The cases run, in order.
    pub cases: Vec<StressCase>,
}

impl StressReport {
    /// Cases run.
    pub fn cases_run(&self) -> usize {
        self.cases.len()
    }

    /// True when the budget (or the caller) stopped the run before every
    /// case ran.
    pub fn stopped_early(&self) -> bool {
        self.cases.len() < self.config.cases
    }

    fn count(&self, label: &str) -> usize {
        self.cases
            .iter()
            .filter(|c| c.outcome.label() == label)
            .count()
    }

    fn tally<'a>(&self, cases: impl Iterator<Item = &'a StressCase>) -> Tally {
        let mut t = Tally::default();
        for c in cases {
            t.add(c);
        }
        t
    }

    /// Every case with legal inputs.
    pub fn all(&self) -> Tally {
        self.tally(self.cases.iter())
    }

    /// The cases inside the validity envelope ([`inside_envelope`](super::inside_envelope)).
    pub fn inside(&self) -> Tally {
        self.tally(self.cases.iter().filter(|c| c.inside_envelope))
    }

    /// The cases outside the validity envelope.
    pub fn outside(&self) -> Tally {
        self.tally(self.cases.iter().filter(|c| !c.inside_envelope))
    }

    /// Counts per partition class (a fixed N, or `auto`).
    pub fn by_elements(&self) -> BTreeMap<PartitionKey, Tally> {
        let mut m: BTreeMap<PartitionKey, Tally> = BTreeMap::new();
        for c in &self.cases {
            m.entry(c.inputs.partition_key()).or_default().add(c);
        }
        m.retain(|_, t| t.cases > 0);
        m
    }

    /// Counts per element model.
    pub fn by_model(&self) -> BTreeMap<&'static str, Tally> {
        let mut m: BTreeMap<&'static str, Tally> = BTreeMap::new();
        for c in &self.cases {
            m.entry(c.inputs.model.name()).or_default().add(c);
        }
        m.retain(|_, t| t.cases > 0);
        m
    }

    /// The distribution of a count over the converged cases of coupled
    /// solves (`None` without any): `count` picks it from their steps.
    pub fn step_quantiles(
        &self,
        count: impl Fn(&fpc::finger::StepCounts) -> usize,
    ) -> Option<Quantiles> {
        let mut v: Vec<usize> = self
            .cases
            .iter()
            .filter(|c| c.outcome == StressOutcome::Converged)
            .filter_map(|c| c.steps.as_ref())
            .filter(|s| s.coupled + s.continuation > 0)
            .map(count)
            .collect();
        Quantiles::of(&mut v)
    }

    /// Converged cases (solutions that passed every check).
    pub fn converged(&self) -> usize {
        self.count("converged")
    }

    /// Honest failures to converge.
    pub fn failed(&self) -> usize {
        self.count("failed")
    }

    /// Honest failures by reason name.
    pub fn failed_by_reason(&self) -> BTreeMap<String, usize> {
        self.all().failed_by_reason
    }

    /// Cases whose every draw was rejected.
    pub fn rejected(&self) -> usize {
        self.count("rejected")
    }

    /// Draws rejected by validation over all cases.
    pub fn rejected_draws(&self) -> usize {
        self.cases.iter().map(|c| c.rejected_draws).sum()
    }

    /// Rejected draws by field, array indices dropped
    /// (`partition.lengths[3]` counts as `partition.lengths`).
    pub fn rejections_by_field(&self) -> BTreeMap<String, usize> {
        let mut m = BTreeMap::new();
        for f in self.cases.iter().flat_map(|c| &c.rejected_fields) {
            let key = f.split('[').next().unwrap_or(f).to_string();
            *m.entry(key).or_insert(0) += 1;
        }
        m
    }

    /// Panics caught.
    pub fn panics(&self) -> usize {
        self.count("panic")
    }

    /// Solutions that failed a check.
    pub fn silently_wrong(&self) -> usize {
        self.count("silently_wrong")
    }

    /// Solutions whose structured eigenvalue count disagrees with the
    /// dense count.
    pub fn wrong_stability(&self) -> usize {
        self.count("wrong_stability")
    }

    /// Unstable equilibria reported as stable: `stable == Some(true)` with
    /// a dense eigenvalue below `-tau`.
    pub fn unstable_reported_stable(&self) -> usize {
        self.cases
            .iter()
            .filter(|c| {
                matches!(
                    c.outcome,
                    StressOutcome::WrongStability { reported: 0, below, .. } if below > 0
                )
            })
            .count()
    }

    /// Solutions whose stability was checked against the dense count.
    pub fn stability_checked(&self) -> usize {
        self.cases
            .iter()
            .filter(|c| c.dense_negative.is_some() && c.negative_eigenvalues.is_some())
            .count()
    }

    /// Converged cases without a structured count (the Hessian could not
    /// be factorised).
    pub fn stability_unknown(&self) -> usize {
        self.cases
            .iter()
            .filter(|c| c.outcome == StressOutcome::Converged && c.negative_eigenvalues.is_none())
            .count()
    }

    /// Panics, silently wrong answers and wrong stability.
    pub fn bugs(&self) -> usize {
        self.cases.iter().filter(|c| c.outcome.is_bug()).count()
    }

    /// Cases with legal inputs (run minus rejected).
    pub fn legal(&self) -> usize {
        self.cases_run() - self.rejected()
    }

    /// Converged over legal cases (`None` without legal cases).
    pub fn convergence_rate(&self) -> Option<f64> {
        let legal = self.legal();
        (legal > 0).then(|| self.converged() as f64 / legal as f64)
    }

    /// Converged cases at an equilibrium the structured count calls
    /// unstable (a saddle: a legitimate root, not a rest state).
    pub fn unstable(&self) -> usize {
        self.cases.iter().filter(|c| c.unstable()).count()
    }

    /// Converged cases with validity findings.
    pub fn beyond_validity(&self) -> usize {
        self.cases.iter().filter(|c| c.warned()).count()
    }

    /// Converged cases where the finer re-check found a finding the
    /// solution does not carry.
    pub fn missed_findings(&self) -> usize {
        self.cases
            .iter()
            .filter(|c| !c.missed_findings.is_empty())
            .count()
    }

    /// The case with the largest recomputed residual.
    pub fn largest_residual(&self) -> Option<&StressCase> {
        self.cases
            .iter()
            .filter(|c| c.residual.is_some_and(f64::is_finite))
            .max_by(|a, b| a.residual.unwrap().total_cmp(&b.residual.unwrap()))
    }

    /// The converged case closest to singular (smallest `|conditioning|`).
    pub fn worst_conditioning(&self) -> Option<&StressCase> {
        self.cases
            .iter()
            .filter(|c| c.conditioning.is_some_and(f64::is_finite))
            .min_by(|a, b| {
                a.conditioning
                    .unwrap()
                    .abs()
                    .total_cmp(&b.conditioning.unwrap().abs())
            })
    }

    /// Failures, panics, silently wrong answers and wrong stability, in order.
    pub fn failures(&self) -> impl Iterator<Item = &StressCase> {
        self.cases.iter().filter(|c| {
            !matches!(
                c.outcome,
                StressOutcome::Converged | StressOutcome::Rejected { .. }
            )
        })
    }

    /// Inside-envelope cases that did not converge cleanly: failures, bugs
    /// and converged cases with findings (each a defect of the solver or
    /// of the envelope).
    pub fn inside_defects(&self) -> impl Iterator<Item = &StressCase> {
        self.cases.iter().filter(|c| {
            c.inside_envelope
                && (c.warned()
                    || !matches!(
                        c.outcome,
                        StressOutcome::Converged | StressOutcome::Rejected { .. }
                    ))
        })
    }
}

#[cfg(test)]
mod tests {
    use super::Quantiles;

    #[test]
    fn quantiles_are_nearest_ranks() {
        let mut v: Vec<usize> = (1..=100).rev().collect();
        let q = Quantiles::of(&mut v).unwrap();
        assert_eq!((q.n, q.median, q.p90, q.p99, q.max), (100, 50, 90, 99, 100));
        let q = Quantiles::of(&mut [7]).unwrap();
        assert_eq!((q.median, q.p99, q.max), (7, 7, 7));
        assert!(Quantiles::of(&mut []).is_none());
    }
}

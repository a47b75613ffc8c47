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
//! - the partition: automatic ([`fpc::solve_auto`]: boundaries on material
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
//! [`MIN_ELEMENT_FRACTION`](fpc::MIN_ELEMENT_FRACTION) `lx`) is an
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

use std::collections::BTreeMap;
use std::fmt;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use fpc_newton::{min_eigenvalue, negative_eigenvalues, Termination};

use fpc::{
    Actuator, ActuatorParams, Channel, Coefficients, Finger, Geometry, InputError, Load, ModelId,
    Partition, Solution, SolveError, SolveOptions, Warning,
};

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

/// Relative thicknesses of the default stack: CL, regular EMC, fluidic
/// layer, prestressed EMC (mm).
const STACK: [f64; 4] = [0.4, 1.9, 4.0, 1.9];

/// The validity envelope's bounds ([`inside_envelope`]; docs/stress.md
/// says how they were found and checks them on other seeds).
pub mod envelope {
    /// Largest prestrain: above it the mid-plane strain of the unloaded
    /// finger nears its 0.20 limit, and the prestressed layer's strain its
    /// 0.6 limit once pressure stretches it.
    pub const MAX_EPS0: f64 = 0.5;
    /// Largest pressure (kPa): above it the fluidic layer's stretch takes
    /// the strains past their limits and, on thin stacks, the reversed
    /// curl closes on itself.
    pub const MAX_PRESSURE_KPA: f64 = 400.0;
    /// The pressure (kPa) whose uncurling offsets a prestrain of 1 in the
    /// curl estimate ([`StressInputs::curl`](super::StressInputs::curl)).
    pub const PRESSURE_PER_PRESTRAIN_KPA: f64 = 1000.0;
    /// Largest curl estimate `|eps0 - P / 1000 kPa| lx / H`: the paper's
    /// finger at eps0 = 0.25 has 3.4; from about 7.5 on, the unloaded (or
    /// the reversed) finger turns through a full circle into self contact.
    pub const MAX_CURL: f64 = 7.0;
    /// Largest load strain `|F| lx H / D` over eps0: a tip load whose
    /// bending strain `M z / D` (at `M = |F| lx`, `z = H`) reaches a
    /// fraction of the prestrain compresses the prestressed layer below
    /// zero strain (folding) or stretches the laminate past the strain
    /// limits (unfolding).
    pub const MAX_LOAD_STRAIN_OVER_EPS0: f64 = 0.15;
    /// Longest element of a drawn partition over `lx`: elements of at most
    /// `lx / 12` stay within the slope limit wherever the curl estimate
    /// does (the automatic partition needs no bound: it splits).
    pub const MAX_ELEMENT_FRACTION: f64 = 1.0 / 12.0;
}

/// True when a case's inputs lie inside the validity envelope, where the
/// solutions are expected to converge and to satisfy every validity limit
/// (docs/stress.md gives the evidence):
///
/// - the default stack's proportions, uniformly scaled (no per-lamina
///   jitter: that moves the neutral axis and the prestress moment in ways
///   the thickness alone does not capture);
/// - `eps0 <= 0.5` and `P <= 400 kPa` (the strain limits);
/// - the curl estimate `|eps0 - P / 1000 kPa| lx / H <= 7` (self contact
///   of the curled, or reversed, finger; it bounds the thickness from
///   below for a given prestrain and pressure);
/// - the load strain `|F| lx H / D <= 0.15 eps0`, with `D = F_ref lx^2`
///   ([`force_scale`]): `relative_load * H / lx` (folding loads compress the
///   prestressed layer below zero strain);
/// - the automatic partition, or a drawn one whose longest element is at
///   most `lx / 12` (the slope limit).
pub fn inside_envelope(i: &StressInputs) -> bool {
    use envelope::*;
    let partition_ok = i.auto_partition
        || i.lengths.iter().fold(0.0f64, |m, &l| m.max(l))
            <= MAX_ELEMENT_FRACTION * i.geometry.lx * (1.0 + 1e-12);
    !i.jittered
        && i.eps0 <= MAX_EPS0
        && i.pressure_kpa <= MAX_PRESSURE_KPA
        && i.curl().abs() <= MAX_CURL
        && i.load_strain() <= MAX_LOAD_STRAIN_OVER_EPS0 * i.eps0
        && partition_ok
}

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

/// The inputs of one case.
#[derive(Debug, Clone, PartialEq)]
pub struct StressInputs {
    /// Element model.
    pub model: ModelId,
    /// Prestrain.
    pub eps0: f64,
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Tip force along X (N).
    pub fx: f64,
    /// Tip force along Z (N).
    pub fz: f64,
    /// Tip load magnitude over the force scale (0: no tip load).
    pub relative_load: f64,
    /// The force scale `F_ref` (N) of the stack ([`force_scale`]; 0 when
    /// no draw was accepted).
    pub force_scale: f64,
    /// Solved on the automatic partition ([`fpc::solve_auto`]).
    pub auto_partition: bool,
    /// Element count N drawn (0 for the automatic partition).
    pub elements: usize,
    /// Element lengths, root to tip (mm; empty for the automatic partition).
    pub lengths: Vec<f64>,
    /// Longest over shortest element (1 for the automatic partition).
    pub length_ratio: f64,
    /// Scale of the whole layer stack (1: the default thicknesses).
    pub thickness_scale: f64,
    /// Per-lamina factors and channel heights redrawn.
    pub jittered: bool,
    /// Extra per-lamina factors (CL, regular EMC, fluidic layer, PEMC).
    pub lamina_factors: [f64; 4],
    /// The geometry handed to [`Actuator::new`].
    pub geometry: Geometry,
    /// The channel handed to [`Actuator::new`].
    pub channel: Channel,
    /// Ribs modelled.
    pub ribs: bool,
}

impl StressInputs {
    /// The scene's load.
    pub fn load(&self) -> Load {
        Load::unloaded()
            .with_pressure_kpa(self.pressure_kpa)
            .with_tip_force(self.fx, self.fz)
    }

    /// Validates the inputs into an actuator.
    pub fn actuator(&self) -> Result<Actuator, InputError> {
        let mut params = ActuatorParams {
            geometry: self.geometry,
            channel: self.channel,
            ..ActuatorParams::default()
        };
        params.pemc.eps0 = self.eps0;
        Actuator::new(params)
    }

    /// The drawn partition (`None` for the automatic partition).
    pub fn partition(&self) -> Result<Option<Partition>, InputError> {
        if self.auto_partition {
            Ok(None)
        } else {
            Partition::custom(self.lengths.clone(), self.geometry.lx).map(Some)
        }
    }

    /// The curl estimate `(eps0 - P / 1000 kPa) lx / H`: the rest curl's
    /// turning scales as `eps0 lx / H` (the prestress moment over the
    /// bending stiffness, times the length), and pressure unbends it
    /// ([`envelope::PRESSURE_PER_PRESTRAIN_KPA`]); negative for a
    /// reversed curl.
    pub fn curl(&self) -> f64 {
        (self.eps0 - self.pressure_kpa / envelope::PRESSURE_PER_PRESTRAIN_KPA) * self.geometry.lx
            / self.geometry.h
    }

    /// The tip load's bending strain scale `|F| lx H / D`, with
    /// `D = F_ref lx^2`: `relative_load * H / lx`.
    pub fn load_strain(&self) -> f64 {
        self.relative_load * self.geometry.h / self.geometry.lx
    }

    /// The partition's label: `auto` or N.
    pub fn partition_key(&self) -> PartitionKey {
        if self.auto_partition {
            PartitionKey::Auto
        } else {
            PartitionKey::Count(self.elements)
        }
    }
}

impl fmt::Display for StressInputs {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b, c, d] = self.lamina_factors;
        write!(
            f,
            "model={} eps0={:.4} P={:.1}kPa F=({:.4e},{:.4e})N ({:.3e} F_ref, F_ref={:.4e}N) N={} ratio={:.1} stack={:.3}x[{:.2},{:.2},{:.2},{:.2}] H={:.3}mm h3a={:.3} h3b={:.3} ribs={}",
            self.model,
            self.eps0,
            self.pressure_kpa,
            self.fx,
            self.fz,
            self.relative_load,
            self.force_scale,
            self.partition_key(),
            self.length_ratio,
            self.thickness_scale,
            a,
            b,
            c,
            d,
            self.geometry.h,
            self.channel.h3a,
            self.channel.h3b,
            if self.ribs { "on" } else { "off" }
        )
    }
}

/// A partition class: a fixed element count, or the automatic partition.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum PartitionKey {
    /// N drawn elements.
    Count(usize),
    /// [`fpc::solve_auto`].
    Auto,
}

impl fmt::Display for PartitionKey {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PartitionKey::Count(n) => write!(f, "{n}"),
            PartitionKey::Auto => f.write_str("auto"),
        }
    }
}

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
        /// [`Solution::negative_eigenvalues`].
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
    /// [`inside_envelope`] of the inputs.
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
    /// Times the automatic partition split elements after a solve.
    pub refinements: Option<usize>,
    /// Newton iterations (returned solutions and reported failures).
    pub iterations: Option<usize>,
    /// Continuation steps (returned solutions).
    pub continuation_steps: Option<usize>,
    /// Recomputed `||g_scaled||_inf / stiffness` (returned solutions).
    pub residual: Option<f64>,
    /// [`Solution::negative_eigenvalues`] (returned solutions).
    pub negative_eigenvalues: Option<usize>,
    /// Dense eigenvalue counts below `-tau` and below `+tau` (solutions on
    /// at most [`DENSE_CHECK_MAX_ELEMENTS`] elements).
    pub dense_negative: Option<(usize, usize)>,
    /// Smallest scaled-Hessian eigenvalue over the stiffness scale (at most
    /// [`CONDITIONING_MAX_ELEMENTS`] elements).
    pub min_eig: Option<f64>,
    /// `lambda_min / G` (module docs).
    pub conditioning: Option<f64>,
    /// Largest element end rotation `|eta_i|` (rad) of a returned solution.
    pub max_rotation: Option<f64>,
    /// The distinct validity findings of a returned solution
    /// ([`finding_name`]), in order.
    pub findings: Vec<&'static str>,
    /// Findings that a re-check at [`FINE_VALIDITY_SAMPLES`] per element
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

    /// True when the budget stopped the run before every case ran.
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

    /// The cases inside the validity envelope ([`inside_envelope`]).
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

/// Runs `cases` stress cases from `seed` (every element count) until done
/// or `budget` is spent; `progress(done, total)` is called after each case.
pub fn stress(
    seed: u64,
    cases: usize,
    budget: Duration,
    progress: impl FnMut(usize, usize),
) -> StressReport {
    stress_with(&StressConfig::new(seed, cases, budget), progress)
}

/// [`stress`] with every setting.
pub fn stress_with(config: &StressConfig, mut progress: impl FnMut(usize, usize)) -> StressReport {
    let start = Instant::now();
    let mut out = Vec::with_capacity(config.cases);
    for index in 0..config.cases {
        if start.elapsed() >= config.budget {
            break;
        }
        out.push(run_case(config, index));
        progress(index + 1, config.cases);
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

/// The force scale `F_ref = D / lx^2` (N) of an actuator: `D` (N mm^2) is
/// the laminate bending stiffness of the solid strip about its neutral
/// axis, `ly (sum Q11 z^2 dz - (sum Q11 z dz)^2 / sum Q11 dz)` over the
/// constraining layer, the regular EMC, the fluidic layer and the
/// prestressed layer at its law's small-strain modulus `p1` (the channel
/// and the ribs, both inside the compliant fluidic layer, are ignored).
/// It depends on the stack and the materials only, not on eps0, the model
/// or the partition. `F_ref` bends a cantilever of stiffness `D` by about
/// a radian at small deflections; the Euler load of the clamped-free
/// strip is `pi^2 / 4 F_ref`. The default stack's is 0.672 N.
pub fn force_scale(actuator: &Actuator) -> f64 {
    let g = actuator.geometry();
    let (pz0, pz1) = actuator.pemc_z();
    let mut boxes: Vec<(f64, f64, f64)> = actuator
        .linear_layers()
        .iter()
        .map(|l| (l.z0, l.z1, l.q.q11))
        .collect();
    boxes.push((pz0, pz1, actuator.pemc().law.p1));
    let (mut a, mut b, mut d) = (0.0, 0.0, 0.0);
    for (z0, z1, q) in boxes {
        a += q * (z1 - z0);
        b += q * (z1 * z1 - z0 * z0) / 2.0;
        d += q * (z1.powi(3) - z0.powi(3)) / 3.0;
    }
    let stiffness = g.ly * (d - b * b / a);
    stiffness / (g.lx * g.lx)
}

/// Why a case has no actuator to solve.
enum NoFinger {
    Rejected(String),
    Panicked(String),
}

/// Draws until validation accepts (at most [`MAX_DRAWS`] times).
fn draw_case(
    seed: u64,
    index: usize,
    max_elements: usize,
) -> (StressInputs, Vec<String>, Result<Actuator, NoFinger>) {
    let mut rng = CaseRng::for_case(seed, index);
    let mut rejected = Vec::new();
    loop {
        let (mut inputs, angle) = draw(&mut rng, max_elements);
        let validated = catch_unwind(AssertUnwindSafe(|| {
            let act = inputs.actuator()?;
            inputs.partition()?;
            let scale = force_scale(&act);
            Ok::<_, InputError>((act, scale))
        }));
        match validated {
            Err(p) => {
                let m = format!("while validating: {}", panic_message(p));
                return (inputs, rejected, Err(NoFinger::Panicked(m)));
            }
            Ok(Ok((act, scale))) => {
                // an undefined scale (not seen) leaves the scene unloaded
                let scale = if scale.is_finite() && scale > 0.0 {
                    scale
                } else {
                    0.0
                };
                inputs.force_scale = scale;
                let f = inputs.relative_load * scale;
                inputs.fx = f * angle.cos();
                inputs.fz = f * angle.sin();
                return (inputs, rejected, Ok(act));
            }
            Ok(Err(e)) => {
                if rejected.len() + 1 >= MAX_DRAWS {
                    return (inputs, rejected, Err(NoFinger::Rejected(e.to_string())));
                }
                rejected.push(e.field().to_string());
            }
        }
    }
}

fn panic_message(p: Box<dyn std::any::Any + Send>) -> String {
    if let Some(s) = p.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = p.downcast_ref::<String>() {
        s.clone()
    } else {
        "(non-string panic payload)".to_string()
    }
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
        let a = fpc::solve_auto(inputs.model, act, inputs.ribs, &load, &opts)?;
        Ok((a.finger, a.solution, a.refinements))
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
        residual: None,
        negative_eigenvalues: None,
        dense_negative: None,
        min_eig: None,
        conditioning: None,
        max_rotation: None,
        findings: Vec::new(),
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
                message: panic_message(p),
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
        Ok(Err(e @ SolveError::TargetNotReached { .. })) => {
            c.outcome = StressOutcome::SilentlyWrong {
                what: format!("a plain solve reported a target: {e}"),
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
            c.residual = Some(m.residual);
            c.negative_eigenvalues = sol.negative_eigenvalues;
            c.dense_negative = m.dense_negative;
            c.min_eig = m.min_eig;
            c.conditioning = m.conditioning;
            c.max_rotation = Some(m.max_rotation).filter(|r| r.is_finite());
            c.findings = m.findings;
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

struct Checked {
    residual: f64,
    max_rotation: f64,
    dense_negative: Option<(usize, usize)>,
    min_eig: Option<f64>,
    conditioning: Option<f64>,
    findings: Vec<&'static str>,
    missed: Vec<&'static str>,
    wrong: Option<String>,
}

impl Checked {
    fn wrong(what: String) -> Checked {
        Checked {
            residual: f64::INFINITY,
            max_rotation: f64::NAN,
            dense_negative: None,
            min_eig: None,
            conditioning: None,
            findings: Vec::new(),
            missed: Vec::new(),
            wrong: Some(what),
        }
    }
}

/// The distinct finding names of a list of warnings, in order.
fn finding_names(ws: &[Warning]) -> Vec<&'static str> {
    let mut out: Vec<&'static str> = Vec::new();
    for w in ws.iter().filter(|w| w.is_validity()) {
        let n = finding_name(w);
        if !out.contains(&n) {
            out.push(n);
        }
    }
    out
}

/// The independent checks of a returned solution (module docs).
fn check(finger: &Finger, load: &Load, sol: &Solution) -> Checked {
    let stiffness = finger.stiffness_scale();
    let k = &sol.coefficients;
    let mut wrong = Vec::new();
    if k.elements() != finger.len() || k.per_element() != finger.unknowns_per_element() {
        return Checked::wrong(format!(
            "{} coefficient sets of {} for {} elements of {}",
            k.elements(),
            k.per_element(),
            finger.len(),
            finger.unknowns_per_element()
        ));
    }
    if sol.element_lengths != finger.element_lengths() {
        wrong.push("element lengths differ from the finger's".to_string());
    }
    if sol.stable != sol.negative_eigenvalues.map(|n| n == 0) {
        wrong.push(format!(
            "stable {:?} but {:?} negative eigenvalues",
            sol.stable, sol.negative_eigenvalues
        ));
    }
    if !k.as_slice().iter().all(|v| v.is_finite()) {
        wrong.push("non-finite coefficient".into());
    }
    if !(sol.tip.iter().all(|v| v.is_finite()) && sol.end_angle.is_finite()) {
        wrong.push(format!(
            "non-finite tip {:?} or end angle {}",
            sol.tip, sol.end_angle
        ));
    }
    if !sol.energy.is_finite() {
        wrong.push(format!("non-finite energy {}", sol.energy));
    }
    let Ok((energy, g)) = finger.gradient(load, k) else {
        return Checked::wrong("coefficients the finger rejects".into());
    };
    let s = finger.unknown_scales();
    if s.len() != g.len() {
        return Checked::wrong(format!(
            "{} unknown scales for {} unknowns",
            s.len(),
            g.len()
        ));
    }
    let mut residual: f64 = 0.0;
    for (gi, si) in g.iter().zip(&s) {
        let v = (gi * si).abs();
        // NaN poisons the maximum
        residual = if v.is_nan() {
            f64::NAN
        } else {
            residual.max(v)
        };
    }
    residual /= stiffness;
    if residual.is_nan() || residual > RESIDUAL_LIMIT {
        wrong.push(format!(
            "recomputed residual {residual:.3e} > {RESIDUAL_LIMIT:.0e} (solver reported {:.3e})",
            sol.report.residual_norm
        ));
    }
    let energy_tol = 1e-9 * (energy.abs() + stiffness);
    if (energy - sol.energy).abs().is_nan() || (energy - sol.energy).abs() > energy_tol {
        wrong.push(format!(
            "energy {} differs from the recomputed {}",
            sol.energy, energy
        ));
    }
    let (tip, _) = finger.tip(k).unwrap_or(([f64::NAN; 2], f64::NAN));
    let lx = finger.length();
    let tip_err = (tip[0] - sol.tip[0]).abs().max((tip[1] - sol.tip[1]).abs());
    if tip_err.is_nan() || tip_err > 1e-9 * lx {
        wrong.push(format!(
            "tip {:?} differs from the recomputed {:?}",
            sol.tip, tip
        ));
    }
    let findings = finding_names(&sol.warnings);
    let missed = finger
        .validity(k, FINE_VALIDITY_SAMPLES)
        .map(|w| {
            finding_names(&w)
                .into_iter()
                .filter(|n| !findings.contains(n))
                .collect()
        })
        .unwrap_or_default();
    let (dense_negative, min_eig, conditioning) =
        if wrong.is_empty() && finger.len() <= DENSE_CHECK_MAX_ELEMENTS {
            dense_stability(finger, load, k, &s, stiffness)
        } else {
            (None, None, None)
        };
    let max_rotation = k
        .iter()
        .enumerate()
        .filter_map(|(i, ki)| finger.element_end(i, ki))
        .map(|e| e[2].abs())
        .fold(0.0, f64::max);
    Checked {
        residual,
        max_rotation,
        dense_negative,
        min_eig,
        conditioning,
        findings,
        missed,
        wrong: (!wrong.is_empty()).then(|| wrong.join("; ")),
    }
}

/// The dense count of negative eigenvalues of `finger`'s Hessian at raw
/// coefficients `k` under `load`: the eigenvalues of the scaled Hessian
/// over the stiffness below `-tau` and below `+tau`
/// ([`STABILITY_TOLERANCE`]), from `fpc_newton`'s dense eigensolver
/// (`O(n^3)`; the stress test calls it for at most
/// [`DENSE_CHECK_MAX_ELEMENTS`] elements). `None` when the Hessian is not
/// finite or the eigensolver fails.
pub fn dense_negative_eigenvalues(
    finger: &Finger,
    load: &Load,
    k: &Coefficients,
) -> Option<(usize, usize)> {
    let s = finger.unknown_scales();
    dense_stability(finger, load, k, &s, finger.stiffness_scale()).0
}

/// The dense eigenvalue counts below `-tau` and `+tau` of the scaled
/// Hessian over the stiffness, and (for at most
/// [`CONDITIONING_MAX_ELEMENTS`] elements) `lambda_min / stiffness` and
/// `lambda_min / G`.
#[allow(clippy::type_complexity)]
fn dense_stability(
    finger: &Finger,
    load: &Load,
    k: &Coefficients,
    s: &[f64],
    stiffness: f64,
) -> (Option<(usize, usize)>, Option<f64>, Option<f64>) {
    let Ok((_, _, mut h)) = finger.hessian(load, k) else {
        return (None, None, None);
    };
    let n = s.len();
    if h.len() != n * n {
        return (None, None, None);
    }
    for j in 0..n {
        for i in 0..n {
            h[i + n * j] *= s[i] * s[j] / stiffness;
        }
    }
    let lmin = min_eigenvalue(n, &h);
    if !lmin.is_finite() {
        return (None, None, None);
    }
    let tau = STABILITY_TOLERANCE;
    let counts = if lmin > tau {
        Some((0, 0))
    } else {
        let shifted = |shift: f64| {
            let mut m = h.clone();
            for i in 0..n {
                m[i + n * i] += shift;
            }
            negative_eigenvalues(n, &m)
        };
        shifted(tau).zip(shifted(-tau))
    };
    let (min_eig, conditioning) = if finger.len() <= CONDITIONING_MAX_ELEMENTS {
        let gersh = (0..n)
            .map(|i| (0..n).map(|j| h[i + n * j].abs()).sum::<f64>())
            .fold(0.0, f64::max);
        (Some(lmin), Some(lmin / gersh).filter(|v| v.is_finite()))
    } else {
        (None, None)
    };
    (counts, min_eig, conditioning)
}

/// The random stream of one case: fastrand's generator, seeded from the
/// run's seed and the case index, so a case does not depend on the cases
/// before it (an early stop does not change later cases).
#[derive(Debug, Clone)]
struct CaseRng(fastrand::Rng);

impl CaseRng {
    fn for_case(seed: u64, index: usize) -> CaseRng {
        // the index picks a stream; fastrand mixes the seed itself
        let stream = fastrand::Rng::with_seed(index as u64).u64(..);
        CaseRng(fastrand::Rng::with_seed(seed ^ stream))
    }

    /// Uniform in [0, 1).
    fn unit(&mut self) -> f64 {
        self.0.f64()
    }

    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.unit()
    }

    fn log_range(&mut self, lo: f64, hi: f64) -> f64 {
        self.range(lo.ln(), hi.ln()).exp()
    }

    fn chance(&mut self, p: f64) -> bool {
        self.unit() < p
    }

    fn below(&mut self, n: usize) -> usize {
        self.0.usize(..n.max(1))
    }
}

/// One draw of every input (module docs) and the tip load's direction
/// (rad from +X); validation and the load in newtons are the caller's.
fn draw(rng: &mut CaseRng, max_elements: usize) -> (StressInputs, f64) {
    use std::f64::consts::{FRAC_PI_2, PI};
    let model = ModelId::ALL[rng.below(ModelId::ALL.len())];
    let eps0 = rng.range(0.01, 0.6);
    let pressure_kpa = if rng.chance(0.2) {
        0.0
    } else {
        rng.range(0.0, 600.0)
    };
    let (relative_load, angle) = if rng.chance(0.3) {
        (0.0, 0.0)
    } else {
        let f = rng.log_range(1e-3, 30.0);
        let u = rng.unit();
        let sign = if rng.chance(0.5) { 1.0 } else { -1.0 };
        let angle = if u < 1.0 / 7.0 {
            if sign > 0.0 {
                0.0
            } else {
                PI
            }
        } else if u < 2.0 / 7.0 {
            sign * FRAC_PI_2
        } else {
            rng.range(-PI, PI)
        };
        (f, angle)
    };
    // the partition: automatic, or a weighted, capped element count
    let auto_partition = rng.chance(AUTO_FRACTION);
    let max_elements = max_elements.max(1);
    let allowed: Vec<(usize, f64)> = STRESS_ELEMENT_COUNTS
        .iter()
        .zip(ELEMENT_WEIGHTS)
        .filter(|(&n, _)| n <= max_elements)
        .map(|(&n, w)| (n, w))
        .collect();
    let total: f64 = allowed.iter().map(|(_, w)| w).sum();
    let mut pick = rng.unit() * total;
    let mut elements = allowed.last().map_or(1, |a| a.0);
    for &(n, w) in &allowed {
        if pick < w {
            elements = n;
            break;
        }
        pick -= w;
    }
    let lx = Geometry::default().lx;
    let lengths = if elements == 1 || rng.chance(0.3) {
        vec![lx / elements as f64; elements]
    } else {
        let ratio = rng.log_range(1.0, 100.0);
        let mut u: Vec<f64> = (0..elements).map(|_| rng.unit()).collect();
        let lo = rng.below(elements);
        let mut hi = rng.below(elements - 1);
        if hi >= lo {
            hi += 1;
        }
        u[lo] = 0.0;
        u[hi] = 1.0;
        let raw: Vec<f64> = u.iter().map(|&u| ratio.powf(u)).collect();
        let sum: f64 = raw.iter().sum();
        raw.iter().map(|r| r * lx / sum).collect()
    };
    let (lengths, elements, length_ratio) = if auto_partition {
        (Vec::new(), 0, 1.0)
    } else {
        let (lmin, lmax) = lengths
            .iter()
            .fold((f64::INFINITY, 0.0f64), |(a, b), &l| (a.min(l), b.max(l)));
        (lengths, elements, lmax / lmin)
    };
    // the layer stack
    let thickness_scale = rng.log_range(0.3, 3.0);
    let jittered = rng.chance(0.35);
    let mut lamina_factors = [1.0; 4];
    if jittered {
        for f in &mut lamina_factors {
            *f = rng.log_range(0.5, 2.0);
        }
    }
    let t: Vec<f64> = STACK
        .iter()
        .zip(lamina_factors)
        .map(|(t, f)| t * f * thickness_scale)
        .collect();
    let h = t.iter().sum::<f64>();
    let h1 = h / 2.0 - t[0];
    let h2 = h1 - t[1];
    let h3 = t[2] - h2;
    let d = Geometry::default();
    let dc = Channel::default();
    let (fa, fb) = if jittered {
        (rng.range(0.15, 0.95), rng.range(0.15, 0.95))
    } else {
        (dc.h3a / d.h2, dc.h3b / d.h3)
    };
    let geometry = Geometry { h, h1, h2, h3, ..d };
    let channel = Channel {
        h3a: fa * h2,
        h3b: fb * h3,
        ..dc
    };
    let ribs = rng.chance(0.5);
    (
        StressInputs {
            model,
            eps0,
            pressure_kpa,
            fx: 0.0,
            fz: 0.0,
            relative_load,
            force_scale: 0.0,
            auto_partition,
            elements,
            lengths,
            length_ratio,
            thickness_scale,
            jittered,
            lamina_factors,
            geometry,
            channel,
            ribs,
        },
        angle,
    )
}

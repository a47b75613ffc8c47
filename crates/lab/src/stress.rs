//! Numerical stress test: seeded random scenes with extreme but legal
//! inputs, each solved with the default options (tip-only output) and
//! checked independently of the solver.
//!
//! A case draws, from a fastrand stream fixed by the seed and the case
//! index:
//!
//! - the prestrain `eps0` uniform in [0.01, 0.6];
//! - the pressure: 0 (one case in five) or uniform in [0, 600] kPa, from
//!   the curled finger past flattening into reversed curvature;
//! - the tip load: none (three cases in ten), otherwise `Fx` in [-3, 10] N
//!   (positive pulls the finger straight, negative compresses it towards
//!   buckling) and `Fz` in [-5, 5] N (folds it), each zero one time in
//!   seven;
//! - N from {1, 2, 3, 4, 8, 16, 32, 64, 128}, with weights that fall for
//!   the large counts (their coupled solves cost `O(N^3)` per iteration),
//!   capped by [`StressConfig::max_elements`];
//! - equal elements (three in ten, and always for N = 1), otherwise
//!   lengths `r^u_i` with `u_i` uniform in [0, 1] (one element at each
//!   end of the range) and `r` log-uniform in [1, 100], normalised to
//!   `lx` ([`Partition::custom`]);
//! - the layer stack scaled by `s` log-uniform in [0.3, 3]; in about one
//!   case in three each lamina's thickness is further multiplied by its
//!   own factor, log-uniform in [0.5, 2], and the channel's heights
//!   within the fluidic layer are redrawn (fractions 0.15 to 0.95 of the
//!   layer's part above and below the mid-plane);
//! - ribs on or off.
//!
//! A draw that [`Actuator::new`] or [`Partition::custom`] rejects (the
//! mid-plane outside the fluidic layer, an element shorter than
//! [`MIN_ELEMENT_FRACTION`](crate::MIN_ELEMENT_FRACTION) `lx`) is an
//! expected outcome, not a failure: it is counted and the whole case is
//! drawn again, up to [`MAX_DRAWS`] times; a case whose every draw was
//! rejected is reported as rejected input.
//!
//! Checks on a returned solution, all independent of the solver's own
//! report: the raw gradient is recomputed with [`Finger::gradient`],
//! scaled by `(1, 1/L^2, 1, 1/L)` per element, and its infinity norm over
//! [`Finger::stiffness_scale`] must be at most [`RESIDUAL_LIMIT`]; the
//! tip, end angle, energy and every coefficient must be finite, and the
//! tip and energy must agree with [`Finger::tip`] and the energy
//! [`Finger::gradient`] returns at the returned coefficients. A violation
//! is a *silently wrong answer*.
//! A panic anywhere (drawing, validation, solve, check) is caught and
//! reported: the library must never panic on user input. Both are bugs.
//!
//! Conditioning, per converged case: `lambda_min` is the smallest
//! eigenvalue of the scaled Hessian (unknowns `(a1, a3 L^2, b1, c2 L)`)
//! at the solution, and `G = max_i sum_j |H_ij|` its Gershgorin bound,
//! which is at least the largest eigenvalue. The case records
//! `lambda_min / stiffness` and `conditioning = lambda_min / G`: for a
//! stable equilibrium it is a lower bound on `1 / cond(H)` (small means
//! nearly singular); a negative value marks an unstable equilibrium (a
//! saddle), which is a legitimate root of the equations but not a state
//! the finger rests in. The case also records the largest element end
//! rotation `max |eta_i|`; above [`ROTATION_LIMIT`] the converged state
//! lies outside the element's kinematics ([`StressReport::beyond_validity`]).

use std::collections::BTreeMap;
use std::fmt;
use std::panic::{catch_unwind, AssertUnwindSafe};
use std::time::{Duration, Instant};

use fpc_newton::{min_eigenvalue, Termination};

use fpc::{
    Actuator, ActuatorParams, Channel, Finger, Geometry, InputError, Load, Partition, Solution,
    SolveError, SolveOptions,
};

/// Largest accepted recomputed residual, `||g_scaled||_inf` over the
/// stiffness scale (the solver's own tolerance is 1e-11).
pub const RESIDUAL_LIMIT: f64 = 1e-9;

/// Element end rotation (rad) beyond which a converged solution is
/// counted as outside the model's validity ([`StressReport::beyond_validity`]):
/// the element's end tangent is perpendicular to its root tangent or turned
/// back, far from the moderate rotations of its von Karman kinematics.
pub const ROTATION_LIMIT: f64 = std::f64::consts::FRAC_PI_2;

/// Draws per case before it counts as rejected input.
pub const MAX_DRAWS: usize = 4;

/// The element counts drawn, and their relative weights.
pub const STRESS_ELEMENT_COUNTS: [usize; 9] = [1, 2, 3, 4, 8, 16, 32, 64, 128];
const ELEMENT_WEIGHTS: [f64; 9] = [10.0, 10.0, 10.0, 12.0, 14.0, 14.0, 12.0, 6.0, 3.0];

/// Relative thicknesses of the default stack: CL, regular EMC, fluidic
/// layer, prestressed EMC (mm).
const STACK: [f64; 4] = [0.4, 1.9, 4.0, 1.9];

/// Settings of a stress run.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct StressConfig {
    /// Seed of the case generator.
    pub seed: u64,
    /// Cases to run (fewer when the budget runs out).
    pub cases: usize,
    /// Wall-clock budget: no case starts after it is spent.
    pub budget: Duration,
    /// Largest element count drawn (counts above it are never drawn;
    /// at least 1).
    pub max_elements: usize,
}

impl StressConfig {
    /// `cases` cases from `seed` within `budget`, every element count.
    pub fn new(seed: u64, cases: usize, budget: Duration) -> StressConfig {
        StressConfig {
            seed,
            cases,
            budget,
            max_elements: 128,
        }
    }
}

/// The inputs of one case.
#[derive(Debug, Clone, PartialEq)]
pub struct StressInputs {
    /// Prestrain.
    pub eps0: f64,
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Tip force along X (N).
    pub fx: f64,
    /// Tip force along Z (N).
    pub fz: f64,
    /// Element count N.
    pub elements: usize,
    /// Element lengths, root to tip (mm).
    pub lengths: Vec<f64>,
    /// Longest over shortest element.
    pub length_ratio: f64,
    /// Scale of the whole layer stack (1: the default thicknesses).
    pub thickness_scale: f64,
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

    /// Validates the inputs into a finger.
    pub fn finger(&self) -> Result<Finger, InputError> {
        let mut params = ActuatorParams {
            geometry: self.geometry,
            channel: self.channel,
            ..ActuatorParams::default()
        };
        params.pemc.eps0 = self.eps0;
        let act = Actuator::new(params)?;
        let part = Partition::custom(self.lengths.clone(), self.geometry.lx)?;
        Ok(Finger::new(&act, &part, self.ribs))
    }
}

impl fmt::Display for StressInputs {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        let [a, b, c, d] = self.lamina_factors;
        write!(
            f,
            "eps0={:.4} P={:.1}kPa F=({:.3},{:.3})N N={} ratio={:.1} stack={:.3}x[{:.2},{:.2},{:.2},{:.2}] H={:.3}mm ribs={}",
            self.eps0,
            self.pressure_kpa,
            self.fx,
            self.fz,
            self.elements,
            self.length_ratio,
            self.thickness_scale,
            a,
            b,
            c,
            d,
            self.geometry.h,
            if self.ribs { "on" } else { "off" }
        )
    }
}

/// How one case ended.
#[derive(Debug, Clone, PartialEq)]
pub enum StressOutcome {
    /// Solved, and the solution passed every check.
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
    /// A panic was caught (a bug).
    Panicked {
        /// The panic message.
        message: String,
    },
}

impl StressOutcome {
    /// A short label: `converged`, `failed`, `rejected`, `silently_wrong`, `panic`.
    pub fn label(&self) -> &'static str {
        match self {
            StressOutcome::Converged => "converged",
            StressOutcome::Failed { .. } => "failed",
            StressOutcome::Rejected { .. } => "rejected",
            StressOutcome::SilentlyWrong { .. } => "silently_wrong",
            StressOutcome::Panicked { .. } => "panic",
        }
    }

    /// True for panics and silently wrong answers.
    pub fn is_bug(&self) -> bool {
        matches!(
            self,
            StressOutcome::SilentlyWrong { .. } | StressOutcome::Panicked { .. }
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
            StressOutcome::Panicked { message } => write!(f, "PANIC: {message}"),
        }
    }
}

/// The short name of a termination reason (`MaxIterations`, ...).
pub fn reason_name(r: Termination) -> String {
    format!("{r:?}")
}

/// One case: inputs, outcome and measurements.
#[derive(Debug, Clone, PartialEq)]
pub struct StressCase {
    /// Index in the run (with the seed, it fixes the inputs).
    pub index: usize,
    /// The inputs of the last draw.
    pub inputs: StressInputs,
    /// Draws rejected by validation before the one kept.
    pub rejected_draws: usize,
    /// The field each rejected draw was rejected for
    /// (`actuator.geometry.h2`, `partition.lengths[3]`, ...).
    pub rejected_fields: Vec<String>,
    /// How it ended.
    pub outcome: StressOutcome,
    /// Newton iterations (returned solutions and reported failures).
    pub iterations: Option<usize>,
    /// Continuation steps (returned solutions).
    pub continuation_steps: Option<usize>,
    /// Recomputed `||g_scaled||_inf / stiffness` (returned solutions).
    pub residual: Option<f64>,
    /// Smallest scaled-Hessian eigenvalue over the stiffness scale.
    pub min_eig: Option<f64>,
    /// `lambda_min / G` (module docs).
    pub conditioning: Option<f64>,
    /// Largest element end rotation `|eta_i|` (rad) of a returned solution.
    pub max_rotation: Option<f64>,
    /// Wall-clock time of the case (s).
    pub seconds: f64,
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
        let mut m = BTreeMap::new();
        for c in &self.cases {
            if let StressOutcome::Failed { reason, .. } = c.outcome {
                *m.entry(reason_name(reason)).or_insert(0) += 1;
            }
        }
        m
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

    /// Legal cases and converged cases per element count N.
    pub fn by_elements(&self) -> BTreeMap<usize, (usize, usize)> {
        let mut m = BTreeMap::new();
        for c in &self.cases {
            if matches!(c.outcome, StressOutcome::Rejected { .. }) {
                continue;
            }
            let e = m.entry(c.inputs.elements).or_insert((0, 0));
            e.0 += 1;
            if c.outcome == StressOutcome::Converged {
                e.1 += 1;
            }
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

    /// Panics plus silently wrong answers.
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

    /// Converged cases whose equilibrium is unstable (`min_eig < 0`).
    pub fn unstable(&self) -> usize {
        self.cases
            .iter()
            .filter(|c| c.outcome == StressOutcome::Converged && c.min_eig.is_some_and(|e| e < 0.0))
            .count()
    }

    /// Converged cases with an element rotated by more than
    /// [`ROTATION_LIMIT`]: solutions of the discrete equations that lie
    /// outside the model's small-rotation kinematics (too few elements).
    pub fn beyond_validity(&self) -> usize {
        self.cases
            .iter()
            .filter(|c| {
                c.outcome == StressOutcome::Converged
                    && c.max_rotation.is_some_and(|r| r > ROTATION_LIMIT)
            })
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

    /// Failures, panics and silently wrong answers, in order.
    pub fn failures(&self) -> impl Iterator<Item = &StressCase> {
        self.cases.iter().filter(|c| {
            !matches!(
                c.outcome,
                StressOutcome::Converged | StressOutcome::Rejected { .. }
            )
        })
    }
}

/// Runs `cases` stress cases from `seed` (every element count up to 128)
/// until done or `budget` is spent; `progress(done, total)` is called
/// after each case.
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

/// The inputs of case `index` of a run from `seed` (element counts up to
/// `max_elements`) and the number of draws validation rejected before
/// them. When all [`MAX_DRAWS`] draws were rejected, the inputs are the
/// last draw's. Deterministic: the same arguments give the same inputs.
pub fn stress_inputs(seed: u64, index: usize, max_elements: usize) -> (StressInputs, usize) {
    let (inputs, rejected, _) = draw_case(seed, index, max_elements);
    (inputs, rejected.len())
}

/// Why a case has no finger to solve.
enum NoFinger {
    Rejected(String),
    Panicked(String),
}

/// Draws until validation accepts (at most [`MAX_DRAWS`] times).
fn draw_case(
    seed: u64,
    index: usize,
    max_elements: usize,
) -> (StressInputs, Vec<String>, Result<Finger, NoFinger>) {
    let mut rng = CaseRng::for_case(seed, index);
    let mut rejected = Vec::new();
    loop {
        let inputs = draw(&mut rng, max_elements);
        match catch_unwind(AssertUnwindSafe(|| inputs.finger())) {
            Err(p) => {
                let m = format!("while validating: {}", panic_message(p));
                return (inputs, rejected, Err(NoFinger::Panicked(m)));
            }
            Ok(Ok(finger)) => return (inputs, rejected, Ok(finger)),
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

fn run_case(config: &StressConfig, index: usize) -> StressCase {
    let t0 = Instant::now();
    let (inputs, rejected_fields, finger) = draw_case(config.seed, index, config.max_elements);
    let mut c = StressCase {
        index,
        inputs,
        rejected_draws: rejected_fields.len(),
        rejected_fields,
        outcome: StressOutcome::Converged,
        iterations: None,
        continuation_steps: None,
        residual: None,
        min_eig: None,
        conditioning: None,
        max_rotation: None,
        seconds: 0.0,
    };
    let finger = match finger {
        Ok(f) => f,
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
    let result = catch_unwind(AssertUnwindSafe(|| {
        let r = finger.solve(&load, &SolveOptions::default().tip_only());
        match r {
            Ok(sol) => {
                let m = check(&finger, &load, &sol);
                (Ok(sol), Some(m))
            }
            Err(e) => (Err(e), None),
        }
    }));
    match result {
        Err(p) => {
            c.outcome = StressOutcome::Panicked {
                message: panic_message(p),
            };
        }
        Ok((
            Err(SolveError::NotConverged {
                reason,
                iterations,
                relative_residual,
                element,
                ..
            }),
            _,
        )) => {
            c.iterations = Some(iterations);
            c.outcome = StressOutcome::Failed {
                reason,
                element,
                relative_residual,
            };
        }
        Ok((Err(e @ SolveError::TargetNotReached { .. }), _)) => {
            c.outcome = StressOutcome::Rejected {
                error: format!("at solve: {e}"),
            };
        }
        Ok((Err(SolveError::Input(e)), _)) => {
            c.outcome = StressOutcome::Rejected {
                error: format!("at solve: {e}"),
            };
        }
        Ok((Ok(sol), m)) => {
            let m = m.expect("checked with the solution");
            c.iterations = Some(sol.report.iterations);
            c.continuation_steps = Some(sol.report.continuation_steps);
            c.residual = Some(m.residual);
            c.min_eig = m.min_eig;
            c.conditioning = m.conditioning;
            c.max_rotation = Some(m.max_rotation).filter(|r| r.is_finite());
            if let Some(what) = m.wrong {
                c.outcome = StressOutcome::SilentlyWrong { what };
            }
        }
    }
    c.seconds = t0.elapsed().as_secs_f64();
    c
}

struct Checked {
    residual: f64,
    max_rotation: f64,
    min_eig: Option<f64>,
    conditioning: Option<f64>,
    wrong: Option<String>,
}

/// The independent checks of a returned solution (module docs).
fn check(finger: &Finger, load: &Load, sol: &Solution) -> Checked {
    let stiffness = finger.stiffness_scale();
    let k = &sol.coefficients;
    let mut wrong = Vec::new();
    if k.elements() != finger.len() || k.per_element() != finger.unknowns_per_element() {
        wrong.push(format!(
            "{} coefficient sets of {} for {} elements of {}",
            k.elements(),
            k.per_element(),
            finger.len(),
            finger.unknowns_per_element()
        ));
        return Checked {
            residual: f64::INFINITY,
            max_rotation: f64::NAN,
            min_eig: None,
            conditioning: None,
            wrong: Some(wrong.join("; ")),
        };
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
        return Checked {
            residual: f64::INFINITY,
            max_rotation: f64::NAN,
            min_eig: None,
            conditioning: None,
            wrong: Some("coefficients the finger rejects".into()),
        };
    };
    let s = finger.unknown_scales();
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
    // conditioning of the scaled Hessian
    let (min_eig, conditioning) = if wrong.is_empty() {
        let (_, _, mut h) = finger
            .hessian(load, k)
            .unwrap_or_else(|_| (f64::NAN, Vec::new(), vec![f64::NAN; s.len() * s.len()]));
        let n = s.len();
        for j in 0..n {
            for i in 0..n {
                h[i + n * j] *= s[i] * s[j];
            }
        }
        let lmin = min_eigenvalue(n, &h);
        let gersh = (0..n)
            .map(|i| (0..n).map(|j| h[i + n * j].abs()).sum::<f64>())
            .fold(0.0, f64::max);
        let cond = lmin / gersh;
        (
            Some(lmin / stiffness).filter(|v| v.is_finite()),
            Some(cond).filter(|v| v.is_finite()),
        )
    } else {
        (None, None)
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
        min_eig,
        conditioning,
        wrong: (!wrong.is_empty()).then(|| wrong.join("; ")),
    }
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

/// One draw of every input (module docs); validation is the caller's.
fn draw(rng: &mut CaseRng, max_elements: usize) -> StressInputs {
    let eps0 = rng.range(0.01, 0.6);
    let pressure_kpa = if rng.chance(0.2) {
        0.0
    } else {
        rng.range(0.0, 600.0)
    };
    let (fx, fz) = if rng.chance(0.3) {
        (0.0, 0.0)
    } else {
        let fx = if rng.chance(1.0 / 7.0) {
            0.0
        } else {
            rng.range(-3.0, 10.0)
        };
        let fz = if rng.chance(1.0 / 7.0) {
            0.0
        } else {
            rng.range(-5.0, 5.0)
        };
        (fx, fz)
    };
    // element count: weighted, capped
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
    // lengths
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
    let (lmin, lmax) = lengths
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &l| (a.min(l), b.max(l)));
    // the layer stack
    let thickness_scale = rng.log_range(0.3, 3.0);
    let jitter = rng.chance(0.35);
    let mut lamina_factors = [1.0; 4];
    if jitter {
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
    let (fa, fb) = if jitter {
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
    StressInputs {
        eps0,
        pressure_kpa,
        fx,
        fz,
        elements,
        lengths,
        length_ratio: lmax / lmin,
        thickness_scale,
        lamina_factors,
        geometry,
        channel,
        ribs,
    }
}

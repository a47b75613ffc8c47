//! What a finger solve is asked (its options, a starting guess) and what
//! it answers (the solution and its report).

use crate::coefficients::Coefficients;
use crate::error::{positive, InputError, Warning};

/// How a scene is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Strategy {
    /// Decoupled element solves when there is no tip load, the coupled
    /// system otherwise.
    #[default]
    Auto,
    /// Always the coupled system (for checks and benchmarks).
    Coupled,
}

/// Largest number of mid-plane samples per element.
pub const MAX_SAMPLES_PER_ELEMENT: usize = 4096;

/// Largest number of mid-plane samples of one solution (elements times
/// [`SolveOptions::samples_per_element`]): each limit alone allows 4
/// million points (about 160 MB as JSON); 65 536 draw any figure.
pub const MAX_SHAPE_POINTS: usize = 65_536;

/// Largest Newton iteration limit per solve ([`SolveOptions::max_iter`]):
/// far above what a solve that converges takes (tens), and a bound on the
/// time one that does not can spend.
pub const MAX_NEWTON_ITERATIONS: usize = 10_000;

/// Largest relative residual a solve may be asked for
/// ([`SolveOptions::rtol`]): a looser one is no equilibrium, and a huge one
/// overflows the absolute tolerance.
pub const MAX_RTOL: f64 = 1e-2;

/// Smallest relative residual a solve may be asked for
/// ([`SolveOptions::rtol`]): about half a double's epsilon (2.2e-16), below
/// which the residual is rounding and a solve can only stall.
pub const MIN_RTOL: f64 = 1e-16;

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveOptions {
    /// Relative residual: `||grad Pi||_inf` over the finger's stiffness scale
    /// (in [`MIN_RTOL`, `MAX_RTOL`]).
    pub rtol: f64,
    /// Newton iteration limit per solve (at most
    /// [`MAX_NEWTON_ITERATIONS`]).
    pub max_iter: usize,
    /// Decoupled or coupled path.
    pub strategy: Strategy,
    /// Sample the mid-plane and fit a circle (off for tip-only output).
    pub shape: bool,
    /// Count the Hessian's negative eigenvalues from its factorisation (off
    /// for tip-only output, then `Solution::negative_eigenvalues` is `None`).
    pub stability: bool,
    /// Mid-plane samples per element when `shape` is on (at most
    /// [`MAX_SAMPLES_PER_ELEMENT`], and at most [`MAX_SHAPE_POINTS`] times
    /// the number of elements).
    pub samples_per_element: usize,
    /// Fall back to continuation when Newton fails from the guess: load
    /// continuation for tip loads; per element, pressure continuation from
    /// the straight element at zero pressure; and, when no unloaded
    /// equilibrium is found to start a loaded solve from, Newton from the
    /// straight finger.
    pub continuation: bool,
    /// Newton's step cap in the scaled unknowns (dimensionless strains).
    /// The prestressed law's quintic makes the energy unbounded below at
    /// large stretch, so an uncapped step from a poor guess can leave the
    /// physical basin for good; 0.25 never limits a step near equilibrium.
    /// The cap acts as a trust region's radius: a step on a positive
    /// definite Hessian cut to it and taken whole doubles it (up to 16
    /// times `max_step`), a damped or shifted step resets it; a chain
    /// whose cap grew and failed is solved again with the cap held at
    /// `max_step` (docs/stress.md, "A chain's growing cap").
    pub max_step: f64,
}

impl Default for SolveOptions {
    fn default() -> SolveOptions {
        SolveOptions {
            rtol: 1e-11,
            max_iter: 60,
            strategy: Strategy::Auto,
            shape: true,
            stability: true,
            samples_per_element: 16,
            continuation: true,
            max_step: 0.25,
        }
    }
}

impl SolveOptions {
    /// Tip-only output: no shape sampling, no circle fit, no eigenvalue.
    pub fn tip_only(mut self) -> SolveOptions {
        self.shape = false;
        self.stability = false;
        self
    }

    pub(crate) fn validate(&self) -> Result<(), InputError> {
        positive(crate::Field::SolveRtol, self.rtol)?;
        crate::error::require(
            self.rtol <= MAX_RTOL,
            crate::Field::SolveRtol,
            self.rtol,
            || format!("must be at most {MAX_RTOL:e} (a looser residual is no equilibrium)"),
        )?;
        crate::error::require(
            self.rtol >= MIN_RTOL,
            crate::Field::SolveRtol,
            self.rtol,
            || {
                format!("must be at least {MIN_RTOL:e} (a tighter residual is below double precision's rounding)")
            },
        )?;
        positive(crate::Field::SolveMaxStep, self.max_step)?;
        if !(1..=MAX_NEWTON_ITERATIONS).contains(&self.max_iter) {
            return Err(InputError::OutOfRange {
                field: crate::Field::SolveMaxIter,
                value: self.max_iter as f64,
                rule: format!("must lie in [1, {MAX_NEWTON_ITERATIONS}]"),
            });
        }
        if self.shape && !(1..=MAX_SAMPLES_PER_ELEMENT).contains(&self.samples_per_element) {
            return Err(InputError::OutOfRange {
                field: crate::Field::SolveSamplesPerElement,
                value: self.samples_per_element as f64,
                rule: format!(
                    "must lie in [1, {MAX_SAMPLES_PER_ELEMENT}] when the shape is sampled"
                ),
            });
        }
        Ok(())
    }

    /// [`SolveOptions::validate`], and the shape's samples on `elements`
    /// elements at most [`MAX_SHAPE_POINTS`].
    pub(crate) fn validate_on(&self, elements: usize) -> Result<(), InputError> {
        self.validate()?;
        let points = elements.saturating_mul(self.samples_per_element);
        crate::error::require(
            !self.shape || points <= MAX_SHAPE_POINTS,
            crate::Field::SolveSamplesPerElement,
            self.samples_per_element as f64,
            || {
                format!(
                    "with {elements} elements gives {points} mid-plane samples, more than {MAX_SHAPE_POINTS}"
                )
            },
        )
    }
}

/// How a solve went.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SolveReport {
    /// Why it stopped (always converged in a returned solution).
    #[serde(serialize_with = "serialize_display")]
    pub reason: fpc_newton::Termination,
    /// Newton iterations (summed over element solves and continuation steps).
    pub iterations: usize,
    /// `||grad Pi||_inf` in scaled units over the stiffness scale.
    pub residual_norm: f64,
    /// Kernel evaluations: energy, gradient and Hessian calls.
    pub evaluations: usize,
    /// True when the coupled system was solved (false: decoupled elements).
    pub coupled: bool,
    /// Continuation steps taken (0: Newton from the guess sufficed).
    pub continuation_steps: usize,
    /// Where the iterations went (they sum to `iterations`).
    pub steps: StepCounts,
}

/// A solve's Newton iterations by where they were spent, and how its
/// globalisation acted on them. `element + coupled + continuation` is
/// [`SolveReport::iterations`]; `chord`, `shifted` and `damped` count
/// among all of them, `grown` the step cap's doublings and `extended` the
/// doublings of shifted steps.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq, serde::Serialize)]
pub struct StepCounts {
    /// Element-by-element solves: the unloaded start of a coupled solve
    /// (or the whole of a decoupled one), retries and pressure
    /// continuation included.
    pub element: usize,
    /// Coupled Newton iterations on the loaded finger from its start.
    pub coupled: usize,
    /// Coupled Newton iterations inside load continuation (or a target's
    /// trace) steps, when Newton from the start did not converge.
    pub continuation: usize,
    /// Accepted chord steps (the last factorisation reused).
    pub chord: usize,
    /// Accepted steps along a modified Hessian (the Hessian not positive
    /// definite there): shifted, or with one element's modified pivots.
    pub shifted: usize,
    /// Accepted steps the line search shortened.
    pub damped: usize,
    /// Times the step cap doubled: a Newton step cut to the cap and taken
    /// whole lets the next one be twice as long ([`SolveOptions::max_step`]).
    pub grown: usize,
    /// Times a shifted step taken whole was doubled while the energy kept
    /// falling (along negative curvature the shift keeps a step short of
    /// where the energy stops falling).
    pub extended: usize,
}

impl std::fmt::Display for StepCounts {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{} element, {} coupled, {} in continuation; {} chord, {} shifted, {} damped, {} grown, {} extended",
            self.element,
            self.coupled,
            self.continuation,
            self.chord,
            self.shifted,
            self.damped,
            self.grown,
            self.extended
        )
    }
}

impl std::ops::AddAssign for StepCounts {
    fn add_assign(&mut self, o: StepCounts) {
        self.element += o.element;
        self.coupled += o.coupled;
        self.continuation += o.continuation;
        self.chord += o.chord;
        self.shifted += o.shifted;
        self.damped += o.damped;
        self.grown += o.grown;
        self.extended += o.extended;
    }
}

impl StepCounts {
    /// Adds the globalisation counts of Newton report `r`.
    pub(crate) fn globalisation(&mut self, r: &fpc_newton::Report) {
        self.chord += r.chord_steps;
        self.shifted += r.shifted_steps;
        self.damped += r.damped_steps;
        self.grown += r.grown_steps;
        self.extended += r.extended_steps;
    }
}

/// An equilibrium of one finger. Serializes with the units in the keys
/// (`tip_mm`, `end_angle_rad`, ...; the README lists them).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Solution {
    /// Tip position (X, Z) in the finger frame (mm).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// Angle of the tip tangent from the X axis (rad).
    #[serde(rename = "end_angle_rad")]
    pub end_angle: f64,
    /// Least-squares circle radius of the samples (`None`: nearly straight or not sampled).
    #[serde(rename = "radius_mm")]
    pub radius: Option<f64>,
    /// Total potential energy `Pi` (N mm).
    #[serde(rename = "energy_nmm")]
    pub energy: f64,
    /// Negative eigenvalues of the Hessian (its inertia, from the
    /// structured factorisation; 0: a stable equilibrium); `None` when not
    /// computed (`SolveOptions::stability` off).
    pub negative_eigenvalues: Option<usize>,
    /// `negative_eigenvalues == 0` when computed.
    pub stable: Option<bool>,
    /// The element unknowns.
    pub coefficients: Coefficients,
    /// Mid-plane samples from root to tip (empty for tip-only output).
    #[serde(rename = "points_mm")]
    pub points: Vec<[f64; 2]>,
    /// Undeformed element lengths (mm), root to tip.
    #[serde(rename = "element_lengths_mm")]
    pub element_lengths: Vec<f64>,
    /// Where the answer leaves the model's assumptions, and the actuator's
    /// notes: empty when every assumption holds (docs/model.md section 8).
    pub warnings: Vec<Warning>,
    /// Solver report.
    pub report: SolveReport,
}

impl Solution {
    /// True when no warning says the answer is outside the model.
    pub fn is_within_model(&self) -> bool {
        !self.warnings.iter().any(Warning::is_validity)
    }
}

/// Serializes a value by its `Display` text.
fn serialize_display<T: std::fmt::Display, S: serde::Serializer>(
    v: &T,
    s: S,
) -> Result<S::Ok, S::Error> {
    s.collect_str(v)
}

/// Checks a starting guess: one coefficient set per element, every value finite.
pub(crate) fn check_guess(
    guess: &Coefficients,
    elements: usize,
    per_element: usize,
) -> Result<(), InputError> {
    if guess.elements() != elements || guess.per_element() != per_element {
        return Err(InputError::OutOfRange {
            field: crate::Field::Guess,
            value: guess.elements() as f64,
            rule: format!(
                "must hold one set of {per_element} coefficients per element ({elements}); it holds {} of {}",
                guess.elements(),
                guess.per_element()
            ),
        });
    }
    match guess.as_slice().iter().find(|v| !v.is_finite()) {
        Some(&value) => Err(InputError::NotFinite {
            field: crate::Field::Guess,
            value,
        }),
        None => Ok(()),
    }
}

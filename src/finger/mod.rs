//! One finger: the chained composite model over any [`ElementModel`]
//! (docs/model.md section 4).
//!
//! The public types here do not depend on the model: a [`Finger`] holds
//! its elements in an enum with one variant per generated model (static
//! dispatch, `model_enum!` and `match_model!` of the generated
//! `models.rs`), so the model is a run-time choice ([`ModelId`]) while
//! every solve runs monomorphised code.
//!
//! The files, lowest first (each uses only those above it; `tests/layers.rs`
//! checks that no file imports in a circle):
//!
//! - `load.rs`: pressure, pressure factor and tip force;
//! - `options.rs`: what a solve is asked and what it answers;
//! - `curve.rs`: the mid-plane as exact polynomial curves, one per element;
//! - `problem.rs`: the elements of one finger and its energy, tip and shape;
//! - `chain.rs`: the coupled Newton problem in scaled unknowns, with the
//!   exact chain derivatives of the tip load and the condensation of the
//!   element-local unknowns;
//! - `bordered.rs`: the chain with one unknown load fixed by one target;
//! - `newton_policy.rs`: how Newton is run on a finger: its options, the
//!   flags of a one-element or a chain solve, the fixed-cap path a failed
//!   solve takes again, Newton in straightened unknowns;
//! - `element_solve.rs`: one element solved alone (decoupled scenes), with
//!   its retries and pressure continuation;
//! - `pool.rs`: the spare workspace a finger keeps for its next solver;
//! - `solver.rs`: decoupled and coupled solves, continuation fallbacks,
//!   stability and the validity checks of a solution;
//! - `path.rs`: load paths by pseudo-arclength continuation;
//! - `target.rs`: target solves and target paths;
//! - this file: [`Finger`], the public face over every model.

mod assembly;
mod bordered;
mod chain;
#[cfg(test)]
mod contact_tests;
mod curve;
mod element_solve;
#[cfg(test)]
mod lane_tests;
mod load;
mod newton_policy;
mod options;
mod path;
mod pool;
mod problem;
mod solver;
mod straighten;
mod target;

use std::sync::Arc;

use crate::actuator::Actuator;
use crate::coefficients::Coefficients;
use crate::element::packed::ElementLanes;
use crate::error::{InputError, Warning};
use crate::lanes::Width;
use crate::model::{ElementModel, ModelId, ModelVisitor};
use crate::partition::Partition;
use crate::solve_error::SolveError;

pub use bordered::TargetProblem;
pub use curve::{Affine2, PolyCurve};
pub use fpc_newton::PathTermination;
pub use load::{Load, MAX_KAPPA, VACUUM_GAUGE_MPA};
pub use options::{
    Solution, SolveOptions, SolveReport, StepCounts, Strategy, MAX_NEWTON_ITERATIONS, MAX_RTOL,
    MAX_SAMPLES_PER_ELEMENT, MAX_SHAPE_POINTS, MIN_RTOL,
};
pub use path::{Fold, LoadPath, LoadPathSpec, LoadPoint};
pub use solver::VALIDITY_SAMPLES;
pub use target::{TargetFold, Traced};

use options::check_guess;

pub(crate) use chain::Chain;
use pool::Pooled;
pub(crate) use problem::FingerCore;
use solver::{Guess, SolverCore};

/// A finger's shared core for model `M`.
type Shared<M> = Arc<Pooled<M>>;

crate::model::model_enum! {
    /// A finger's elements for its model, one variant per generated model:
    /// every call on a [`Finger`] is a `match` on the model, then
    /// monomorphised code (no trait object).
    #[derive(Debug, Clone)]
    pub(crate) enum Core = Shared
}

crate::model::model_enum! {
    /// A solver workspace for a finger's model ([`Solver`]).
    pub(crate) enum Solvers<'a> = SolverCore
}

/// `with_core!(finger, c => body)`: `body` with `c` the finger's typed
/// core (`&Arc<Pooled<M>>`, which derefs to `FingerCore<M>`, for the finger's model `M`).
macro_rules! with_core {
    ($finger:expr, $c:ident => $body:expr) => {
        crate::model::match_model!(&$finger.core, Core($c) => $body)
    };
}

/// Something done with a finger's model-typed core (the way
/// [`Finger::visit_core`] hands it to generic code above the finger, such
/// as the sensitivities).
pub(crate) trait CoreVisitor {
    /// What the visit returns.
    type Output;
    /// Runs with the core of model `M`.
    fn visit<M: ElementModel>(self, core: &FingerCore<M>) -> Self::Output;
}

/// A finger: elements with their moments, ready to solve.
#[derive(Debug, Clone)]
pub struct Finger {
    core: Core,
    warnings: Vec<Warning>,
}

struct LawCheck<'a>(&'a Actuator);

impl ModelVisitor for LawCheck<'_> {
    type Output = Option<Warning>;
    fn visit<M: ElementModel>(self) -> Self::Output {
        let pemc = self.0.pemc();
        let tangent = M::psi(pemc.eps0, &pemc.law)[2];
        // NaN (the law overflows) counts as not positive
        (tangent.is_nan() || tangent <= 0.0).then_some(Warning::SofteningPrestressLaw {
            eps0: pemc.eps0,
            tangent: tangent.is_finite().then_some(tangent),
        })
    }
}

/// The notes on an actuator as model `model` reads it: the actuator's own
/// (a prestrain outside the fitted range, ...) and the model's law (a
/// softening prestressed law at eps0). Every finger and solution carries them.
pub fn input_warnings(model: ModelId, actuator: &Actuator) -> Vec<Warning> {
    let mut w = actuator.warnings().to_vec();
    w.extend(model.visit(LawCheck(actuator)));
    w
}

impl Finger {
    /// Builds the elements of `actuator` split by `partition` (ribs
    /// optional) with the default element model (the paper's).
    pub fn new(actuator: &Actuator, partition: &Partition, ribs: bool) -> Finger {
        Finger::with_model(ModelId::default(), actuator, partition, ribs)
    }

    /// Builds the elements with element model `model`.
    pub fn with_model(
        model: ModelId,
        actuator: &Actuator,
        partition: &Partition,
        ribs: bool,
    ) -> Finger {
        let core = crate::model::model_of_id!(
            model,
            M => Core(Arc::new(Pooled::new(FingerCore::<M>::new(actuator, partition, ribs))))
        );
        Finger {
            core,
            warnings: input_warnings(model, actuator),
        }
    }

    /// The default actuator at prestrain `eps0`, `n` equal elements, ribs on.
    pub fn paper(eps0: f64, n: usize) -> Result<Finger, InputError> {
        let act = Actuator::paper(eps0)?;
        let part = Partition::equal(act.geometry().lx, n)?;
        Ok(Finger::new(&act, &part, true))
    }

    /// The same finger with its element potentials, gradients and
    /// Hessians evaluated `width` elements at a time (or at the widest
    /// width below it this processor runs; [`crate::lanes`]). A finger is built with the widest
    /// ([`Width::detect`]); every width gives the same results bit for bit,
    /// so this is for comparing their speed.
    pub fn with_lane_width(&self, width: Width) -> Finger {
        let core = crate::model::map_model!(&self.core, Core(c) => Core({
            let mut core = c.core.clone();
            core.lanes = ElementLanes::new(&core.elements, width);
            Arc::new(Pooled::new(core))
        }));
        Finger {
            core,
            warnings: self.warnings.clone(),
        }
    }

    /// The width the finger's element pass is evaluated at.
    pub fn lane_width(&self) -> Width {
        with_core!(self, c => c.lanes.width())
    }

    /// Runs `visitor` with the finger's model-typed core.
    pub(crate) fn visit_core<V: CoreVisitor>(&self, visitor: V) -> V::Output {
        with_core!(self, c => visitor.visit(&**c))
    }

    /// The element model.
    pub fn model(&self) -> ModelId {
        with_core!(self, c => c.model())
    }

    /// Unknowns per element.
    pub fn unknowns_per_element(&self) -> usize {
        with_core!(self, c => c.unknowns())
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        with_core!(self, c => c.lengths()).len()
    }

    /// True for a finger without elements (never built by the constructors).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Undeformed element lengths (mm), root to tip.
    pub fn element_lengths(&self) -> &[f64] {
        with_core!(self, c => c.lengths())
    }

    /// The strip's width `Ly` (mm).
    pub fn width(&self) -> f64 {
        with_core!(self, c => c.width())
    }

    /// The modelled length `Lx` (mm): the sum of the element lengths.
    pub fn length(&self) -> f64 {
        with_core!(self, c => c.lengths()).iter().sum()
    }

    /// Notes about the actuator and the model's law (a prestrain outside
    /// the fitted range, ...); every solution carries them too.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// Stiffness scale (N mm) that makes residuals relative.
    pub fn stiffness_scale(&self) -> f64 {
        with_core!(self, c => c.stiffness())
    }

    /// The raw value of one unit of each of the solver's scaled unknowns,
    /// element by element (the model's `scaled` statement): the solver's
    /// residual is the raw gradient times these, over
    /// [`Finger::stiffness_scale`].
    pub fn unknown_scales(&self) -> Vec<f64> {
        with_core!(self, c => c.unscale())
    }

    /// Zero coefficients (the straight finger) of the right shape.
    pub fn straight(&self) -> Coefficients {
        Coefficients::zeros(self.len(), self.unknowns_per_element())
    }

    fn check(&self, k: &Coefficients) -> Result<(), InputError> {
        check_guess(k, self.len(), self.unknowns_per_element())
    }

    /// Total potential energy at raw coefficients.
    pub fn energy(&self, load: &Load, k: &Coefficients) -> Result<f64, InputError> {
        self.check(k)?;
        Ok(with_core!(self, c => c.energy(load, k)))
    }

    /// Tip position and end angle at raw coefficients, as a solution
    /// reports them (the chain walked once, one `atan2` for the angle).
    pub fn tip(&self, k: &Coefficients) -> Result<([f64; 2], f64), InputError> {
        self.check(k)?;
        Ok(with_core!(self, c => c.tip(k)))
    }

    /// Mid-plane samples from the root (included) to the tip, `per_element`
    /// per element (at most [`MAX_SAMPLES_PER_ELEMENT`], and
    /// [`MAX_SHAPE_POINTS`] in all).
    pub fn shape(&self, k: &Coefficients, per_element: usize) -> Result<Vec<[f64; 2]>, InputError> {
        self.check(k)?;
        let points = per_element.saturating_mul(self.len());
        if !(1..=MAX_SAMPLES_PER_ELEMENT).contains(&per_element) || points > MAX_SHAPE_POINTS {
            return Err(InputError::OutOfRange {
                field: crate::Field::SamplesPerElement,
                value: per_element as f64,
                rule: format!(
                    "must lie in [1, {MAX_SAMPLES_PER_ELEMENT}], and at most {MAX_SHAPE_POINTS} samples in all ({} elements)",
                    self.len()
                ),
            });
        }
        Ok(with_core!(self, c => c.shape(k, per_element)))
    }

    /// The mid-plane as exact curves, one per element, root to tip, in the
    /// finger frame (docs/model.md M14 in the frames of M10): element `i`'s
    /// polynomial in its local `x` over `[0, L_i]`, rotated by the chain
    /// angle `theta_i` and translated to the element's root `p_{i-1}`. The
    /// curves meet end to start, the first starts at the root and the last
    /// ends at [`Finger::tip`], and they agree with [`Finger::shape`]'s
    /// samples (to rounding). An error names `coefficients` when the
    /// state is so large that the curves overflow.
    pub fn midplane_curves(&self, k: &Coefficients) -> Result<Vec<PolyCurve>, InputError> {
        self.check(k)?;
        let curves = with_core!(self, c => c.midplane_curves(k));
        if curves.iter().all(PolyCurve::is_finite) {
            Ok(curves)
        } else {
            Err(InputError::Inconsistent {
                field: crate::Field::Coefficients,
                rule: "the mid-plane's coefficients overflow".into(),
            })
        }
    }

    /// Total potential energy and its gradient with respect to the raw
    /// coefficients (element by element).
    pub fn gradient(&self, load: &Load, k: &Coefficients) -> Result<(f64, Vec<f64>), InputError> {
        self.check(k)?;
        Ok(with_core!(self, c => chain::gradient(c, load, k)))
    }

    /// Total potential energy, gradient and full Hessian (column-major,
    /// `n x n` for `n` unknowns in all) with respect to the raw coefficients.
    pub fn hessian(
        &self,
        load: &Load,
        k: &Coefficients,
    ) -> Result<(f64, Vec<f64>, Vec<f64>), InputError> {
        self.check(k)?;
        Ok(with_core!(self, c => chain::hessian(c, load, k)))
    }

    /// One element's potential (or, with `family`, one integral family of
    /// the model alone, without coefficient), gradient and upper-triangle
    /// Hessian at the element's raw unknowns `k`. `None` for an element or
    /// family out of range or `k` of the wrong length.
    pub fn element_hessian(
        &self,
        element: usize,
        family: Option<usize>,
        load: &Load,
        k: &[f64],
    ) -> Option<(f64, Vec<f64>, Vec<f64>)> {
        with_core!(self, c => c.element_hessian(element, family, load, k))
    }

    /// One element's end `[Xe, Ze, eta]` in its own frame.
    pub fn element_end(&self, element: usize, k: &[f64]) -> Option<[f64; 3]> {
        with_core!(self, c => c.element_end(element, k))
    }

    /// The validity findings of a state (docs/model.md section 8), with
    /// `samples` checks per element.
    pub fn validity(&self, k: &Coefficients, samples: usize) -> Result<Vec<Warning>, InputError> {
        self.check(k)?;
        Ok(with_core!(self, c => c.validity(k, samples.clamp(1, MAX_SAMPLES_PER_ELEMENT))))
    }

    /// The mid-plane's signed curvature (1/mm; negative curls towards -Z)
    /// at `per_element` points per element, element-major, at the middles
    /// of equal sub-intervals.
    pub fn curvatures(&self, k: &Coefficients, per_element: usize) -> Result<Vec<f64>, InputError> {
        self.check(k)?;
        Ok(with_core!(self, c => c.curvatures(k, per_element.clamp(1, MAX_SAMPLES_PER_ELEMENT))))
    }

    /// The coupled finger as a Newton problem in the solver's scaled
    /// unknowns (raw coefficients over [`Finger::unknown_scales`], element
    /// by element): energy, exact gradient and the structured Hessian with
    /// its `O(N)` factorisation (fpc-newton's [`Hessian`](fpc_newton::Hessian)
    /// and [`LinearSystem`](fpc_newton::LinearSystem)). For external solvers
    /// and benchmarks.
    pub fn problem(&self, load: &Load) -> Problem<'_> {
        Problem {
            inner: with_core!(self, c => chain::problem(c, load)),
        }
    }

    /// Solves a scene from the straight finger (or, with a tip load, from
    /// the unloaded equilibrium at the same pressure).
    pub fn solve(&self, load: &Load, opts: &SolveOptions) -> Result<Solution, SolveError> {
        Solver::new(self).solve(load, None, opts)
    }

    /// Solves a scene from given coefficients, taken to be near the answer
    /// (a nearby load's equilibrium). From the scene's rest state, its
    /// equilibrium without the tip force, [`Finger::solve_from_rest`] is
    /// faster.
    pub fn solve_from(
        &self,
        load: &Load,
        guess: &Coefficients,
        opts: &SolveOptions,
    ) -> Result<Solution, SolveError> {
        Solver::new(self).solve(load, Some(guess), opts)
    }

    /// Solves a scene from its rest state `rest`: the raw coefficients of
    /// the equilibrium of the same finger and pressure without the tip
    /// force, which a cold [`Finger::solve`] computes for itself. Newton
    /// takes it the way a cold solve takes its own (in the straightened
    /// unknowns of docs/model.md section 4.2), which under a tip load needs
    /// fewer Hessians than [`Finger::solve_from`], made for guesses near
    /// the answer (3 against 5 on the standard tip-loaded case). Any
    /// coefficients of the right length are accepted: a start that is not
    /// at rest may cost iterations, never accuracy.
    pub fn solve_from_rest(
        &self,
        load: &Load,
        rest: &Coefficients,
        opts: &SolveOptions,
    ) -> Result<Solution, SolveError> {
        Solver::new(self).solve_from_rest(load, rest, opts)
    }

    /// Solves a scene for its state, tip and end angle only (no energy,
    /// stability, shape or validity findings): for intermediate results
    /// that are not handed to users.
    pub(crate) fn solve_tip(
        &self,
        load: &Load,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
        trusted: bool,
    ) -> Result<solver::TipSolve, SolveError> {
        let mut s = Solver::new(self);
        s.trust_start(trusted);
        s.solve_tip(load, guess, opts)
    }

    /// [`Finger::solve_from`] from a guess known to be close to the
    /// equilibrium (a nested refinement level's prolongated state).
    pub(crate) fn solve_trusted(
        &self,
        load: &Load,
        guess: &Coefficients,
        opts: &SolveOptions,
    ) -> Result<Solution, SolveError> {
        let mut s = Solver::new(self);
        s.trust_start(true);
        s.solve(load, Some(guess), opts)
    }
}

/// A finger's Newton problem ([`Finger::problem`]).
pub struct Problem<'a> {
    inner: Box<dyn fpc_newton::Hessian + 'a>,
}

impl fpc_newton::Energy for Problem<'_> {
    fn dim(&self) -> usize {
        self.inner.dim()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.inner.energy(x)
    }
}

impl fpc_newton::Gradient for Problem<'_> {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.inner.gradient(x, g)
    }
}

impl fpc_newton::Hessian for Problem<'_> {
    fn hessian(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.inner.hessian(x, g)
    }
    fn stages_hessian(&self) -> bool {
        self.inner.stages_hessian()
    }
}

impl fpc_newton::LinearSystem for Problem<'_> {
    fn diagonal_range(&self) -> (f64, f64) {
        self.inner.diagonal_range()
    }
    fn factor(
        &mut self,
        tau: f64,
        kind: fpc_newton::PivotKind,
    ) -> Result<fpc_newton::Inertia, fpc_newton::FactorError> {
        self.inner.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.inner.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.inner.apply(x, out)
    }
}

/// A reusable solver workspace (no allocation per Newton iteration; reuse
/// it across the points of a sweep).
pub struct Solver<'a> {
    inner: Solvers<'a>,
}

/// `with_solver!(solver, s => body)`: `body` with `s` the solver's typed
/// workspace (`&mut SolverCore<M>`).
macro_rules! with_solver {
    ($solver:expr, $s:ident => $body:expr) => {
        crate::model::match_model!(&mut $solver.inner, Solvers($s) => $body)
    };
}

impl<'a> Solver<'a> {
    /// A workspace for `finger`.
    pub fn new(finger: &'a Finger) -> Solver<'a> {
        Solver {
            inner: crate::model::map_model!(
                &finger.core,
                Core(c) => Solvers(SolverCore::new(c, &finger.warnings))
            ),
        }
    }

    /// Solves a scene; `guess` are raw coefficients taken to be near the
    /// answer (for the rest state, [`Solver::solve_from_rest`]).
    pub fn solve(
        &mut self,
        load: &Load,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
    ) -> Result<Solution, SolveError> {
        with_solver!(self, s => s.solve(load, guess, opts))
    }

    /// Solves a scene from its rest state ([`Finger::solve_from_rest`]).
    pub fn solve_from_rest(
        &mut self,
        load: &Load,
        rest: &Coefficients,
        opts: &SolveOptions,
    ) -> Result<Solution, SolveError> {
        with_solver!(self, s => {
            // this guess alone: the solver's own kind comes back after it
            let kind = std::mem::replace(&mut s.guess, Guess::Rest);
            let r = s.solve(load, Some(rest), opts);
            s.guess = kind;
            r
        })
    }

    /// Solves for the state, tip and end angle only ([`Finger::solve_tip`]).
    pub(crate) fn solve_tip(
        &mut self,
        load: &Load,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
    ) -> Result<solver::TipSolve, SolveError> {
        with_solver!(self, s => s.solve_tip(load, guess, opts))
    }

    /// Says that the guesses are close to the equilibrium (nested
    /// iteration).
    pub(crate) fn trust_start(&mut self, on: bool) {
        with_solver!(self, s => s.guess = if on { Guess::Trusted } else { Guess::Near })
    }

    /// Takes a chain's shifted steps as the shift gives them, without
    /// doubling them (the path of a solve before they were doubled; see
    /// `plan::Auto`).
    pub(crate) fn keep_shifted_steps(&mut self) {
        with_solver!(self, s => s.double_shifted = false)
    }

    /// Solves a [`TargetProblem`] from `guess` (raw coefficients, ideally a
    /// nearby equilibrium) and a starting `lambda`; returns the equilibrium
    /// and the `lambda` that meets the target. `ctol_mm` bounds the target
    /// residual.
    pub fn solve_target(
        &mut self,
        problem: &TargetProblem,
        guess: &Coefficients,
        lambda0: f64,
        ctol_mm: f64,
        opts: &SolveOptions,
    ) -> Result<(Solution, f64), SolveError> {
        with_solver!(self, s => s.solve_target(problem, guess, lambda0, ctol_mm, opts))
    }

    /// Traces the equilibria of `problem`'s load family from `start` (an
    /// equilibrium of the family at `lambda0`) as the target moves from the
    /// start's own `weights . tip` to `problem.target`, the way an object's
    /// position is imposed when a gripper closes on it: each step a bordered
    /// Newton solve from a predictor, accepted only when it stays on the
    /// curve (see [`Traced`]); a fold in the target ends the trace short of
    /// it ([`Traced::Fold`]). `ctol_mm` bounds the target residual.
    pub fn trace_target(
        &mut self,
        problem: &TargetProblem,
        start: &Coefficients,
        lambda0: f64,
        ctol_mm: f64,
        opts: &SolveOptions,
    ) -> Result<Traced, SolveError> {
        with_solver!(self, s => s.trace_target(problem, start, lambda0, ctol_mm, opts))
    }

    /// `dT / dlambda` of `problem`'s family at `start`, which decides the
    /// way a trace from it goes (`None`: a singular tangent).
    pub(crate) fn target_slope_at(
        &mut self,
        problem: &TargetProblem,
        start: &Coefficients,
        lambda0: f64,
    ) -> Option<f64> {
        with_solver!(self, s => s.target_slope_at(problem, start, lambda0))
    }

    /// Follows the equilibrium path of a load family by pseudo-arclength
    /// continuation from `guess` (see [`LoadPathSpec`]): through folds,
    /// which it locates and reports with the load and shape there. `visit`
    /// sees every accepted point and ends the path by returning `false`.
    pub fn follow_load(
        &mut self,
        spec: &LoadPathSpec,
        guess: &Coefficients,
        opts: &SolveOptions,
        visit: &mut dyn FnMut(&LoadPoint<'_>) -> bool,
    ) -> Result<LoadPath, SolveError> {
        with_solver!(self, s => s.follow_load(spec, guess, opts, visit))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rest start is for its own solve: a solver told that its guesses
    /// are trusted (a refinement level's) is so again after it.
    #[test]
    fn a_rest_start_leaves_the_solvers_guess_kind_alone() {
        let f = Finger::paper(0.25, 4).unwrap();
        let opts = SolveOptions::default();
        let rest = f.solve(&Load::unloaded(), &opts).unwrap();
        let load = Load::unloaded().with_tip_force(0.5, 0.3);
        let mut s = Solver::new(&f);
        s.trust_start(true);
        let solved = s.solve_from_rest(&load, &rest.coefficients, &opts).unwrap();
        assert!(solved.report.reason.is_converged());
        with_solver!(s, c => assert_eq!(c.guess, Guess::Trusted));
        s.trust_start(false);
        s.solve_from_rest(&load, &rest.coefficients, &opts).unwrap();
        with_solver!(s, c => assert_eq!(c.guess, Guess::Near));
    }
}

//! What a [`Palc`](super::Palc) run hands out: accepted points, events,
//! the observer interface, the report and the stored [`Branch`].

use crate::linear::Inertia;
use core::fmt;

/// Which way to leave the start: the sign of `d lambda / ds` there.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// The load increases from the start.
    Increasing,
    /// The load decreases from the start.
    Decreasing,
}

/// An observer's answer to an accepted point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Control {
    /// Go on.
    Continue,
    /// End the branch here (this point is its last one):
    /// [`PathTermination::Stopped`].
    Stop,
}

/// An accepted point of the branch, as handed to a [`PathObserver`].
#[derive(Clone, Copy, Debug)]
pub struct PathPoint<'a> {
    /// 0 for the start, then 1, 2, ... per accepted step.
    pub index: usize,
    /// The load.
    pub lambda: f64,
    /// The state (`||g(x, lambda)||_inf <= gtol`).
    pub x: &'a [f64],
    /// State part of the unit tangent (weighted norm, see [`Palc`](super::Palc)).
    pub tangent_x: &'a [f64],
    /// Load part of the unit tangent, `d lambda / ds`: its sign changes
    /// at folds.
    pub tangent_lambda: f64,
    /// Inertia of `H` here (`negative == 0`: stable at fixed load).
    pub inertia: Inertia,
    /// For a path problem with a constraint ([`Path::constraint`](super::Path::constraint)):
    /// the inertia of `H` restricted to the constraint's tangent space
    /// (`negative == 0`: stable with the constraint held); `None` without
    /// a constraint or where it is not determined (singular).
    pub restricted: Option<Inertia>,
    /// Pseudo-arclength from the start: the sum of the weighted chord
    /// lengths between accepted points.
    pub arclength: f64,
    /// Newton iterations the corrector needed for this point.
    pub corrector_iterations: usize,
}

impl PathPoint<'_> {
    /// True when `H` is positive definite (a strict local minimum of the
    /// energy at fixed load).
    pub fn is_stable(&self) -> bool {
        self.inertia.is_positive_definite()
    }
}

/// What kind of event lies between two accepted points.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum EventKind {
    /// A limit point: `d lambda / ds` changes sign (and, for a simple
    /// fold, one eigenvalue of `H` changes sign).
    Fold,
    /// The number of negative eigenvalues of `H` changes without a fold: a
    /// possible branch point (bifurcation). Reported only; the driver
    /// stays on the branch it follows.
    PossibleBifurcation,
}

/// A located event, as handed to a [`PathObserver`] (before the accepted
/// point that follows it).
#[derive(Clone, Copy, Debug)]
pub struct PathEvent<'a> {
    /// Fold or possible bifurcation.
    pub kind: EventKind,
    /// The load at the located point.
    pub lambda: f64,
    /// The state at the located point (an equilibrium within `event_tol`
    /// of the event along the branch, see [`Palc`](super::Palc)).
    pub x: &'a [f64],
    /// Pseudo-arclength of the located point from the start.
    pub arclength: f64,
    /// Inertia of `H` at the accepted point before the event.
    pub inertia_before: Inertia,
    /// Inertia of `H` at the accepted point after the event.
    pub inertia_after: Inertia,
    /// `d lambda / ds` at the located point (about 0 for a located fold).
    pub tangent_lambda: f64,
    /// True when the event was bracketed to `event_tol`; false when a
    /// corrector solve failed or `max_locate_iterations` ran out (then the
    /// point is the best one found, at worst the accepted point after it).
    pub located: bool,
    /// Index of the accepted point before the event.
    pub after_point: usize,
}

/// Receives the accepted points and events of [`Palc::follow`](super::Palc::follow), in order.
/// Any `FnMut(&PathPoint) -> Control` closure is an observer that ignores
/// events.
pub trait PathObserver {
    /// An accepted point; the answer decides whether the branch goes on.
    fn point(&mut self, point: &PathPoint<'_>) -> Control;
    /// An event between the previous accepted point and the next one
    /// (delivered before that next point). Default: ignored.
    fn event(&mut self, event: &PathEvent<'_>) {
        let _ = event;
    }
}

impl<F: FnMut(&PathPoint<'_>) -> Control> PathObserver for F {
    fn point(&mut self, point: &PathPoint<'_>) -> Control {
        self(point)
    }
}

/// Why a branch ended. Only the first three are normal ends.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum PathTermination {
    /// The load reached the target, and the last point lies exactly on it.
    ReachedTarget,
    /// The observer (stop predicate) returned [`Control::Stop`].
    Stopped,
    /// `max_steps` steps were accepted.
    MaxSteps,
    /// A step failed at `min_step` (corrector, turn, singular `H`): the
    /// branch could not be continued.
    StepTooSmall,
    /// As `StepTooSmall`, the last failure being a non-finite (or refused)
    /// evaluation or a non-finite Hessian: the branch runs into a region
    /// where the problem cannot be evaluated. Non-finite values are never
    /// accepted as points.
    NonFinite,
    /// The start could not be converged at fixed load within
    /// `max_corrector_iterations` (or its tangent not computed: `H`
    /// singular there).
    StartFailed,
    /// Invalid options, or a non-finite start load or target: nothing was
    /// evaluated.
    InvalidInput,
}

impl fmt::Display for PathTermination {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            PathTermination::ReachedTarget => "reached the target load",
            PathTermination::Stopped => "stopped by the observer",
            PathTermination::MaxSteps => "step limit reached",
            PathTermination::StepTooSmall => "step fell below min_step",
            PathTermination::NonFinite => "non-finite evaluation at min_step",
            PathTermination::StartFailed => "the start did not converge",
            PathTermination::InvalidInput => "invalid options or parameters",
        })
    }
}

/// Summary of one [`Palc::follow`](super::Palc::follow) (or [`Palc::branch`](super::Palc::branch)).
#[derive(Clone, Debug, PartialEq)]
pub struct PathReport {
    /// Why the branch ended.
    pub termination: PathTermination,
    /// Accepted steps (points after the start).
    pub steps: usize,
    /// Rejected steps (each retried shorter).
    pub rejected: usize,
    /// Events reported.
    pub events: usize,
    /// Calls to [`Path::eval`](super::Path::eval).
    pub evaluations: usize,
    /// Factorisations of `H`.
    pub factorizations: usize,
    /// Newton iterations over every corrector solve (accepted, rejected,
    /// start, landing and event location).
    pub corrector_iterations: usize,
    /// Corrector solves spent locating events.
    pub locate_solves: usize,
    /// Load at the last accepted point (the start load if none).
    pub lambda: f64,
    /// Pseudo-arclength of the last accepted point.
    pub arclength: f64,
    /// The step length the next step would have tried.
    pub step: f64,
}

impl PathReport {
    pub(super) fn new(lambda: f64, step: f64) -> PathReport {
        PathReport {
            termination: PathTermination::InvalidInput,
            steps: 0,
            rejected: 0,
            events: 0,
            evaluations: 0,
            factorizations: 0,
            corrector_iterations: 0,
            locate_solves: 0,
            lambda,
            arclength: 0.0,
            step,
        }
    }
}

impl fmt::Display for PathReport {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{} at lambda = {:.6e} (s = {:.4e}) after {} steps ({} rejected, {} events; {} evaluations, {} factorisations, {} corrector iterations, {} locate solves)",
            self.termination,
            self.lambda,
            self.arclength,
            self.steps,
            self.rejected,
            self.events,
            self.evaluations,
            self.factorizations,
            self.corrector_iterations,
            self.locate_solves
        )
    }
}

/// An accepted point stored in a [`Branch`].
#[derive(Clone, Debug, PartialEq)]
pub struct BranchPoint {
    /// The load.
    pub lambda: f64,
    /// The state.
    pub x: Vec<f64>,
    /// `d lambda / ds` (unit tangent, weighted norm).
    pub tangent_lambda: f64,
    /// Inertia of `H`.
    pub inertia: Inertia,
    /// Pseudo-arclength from the start.
    pub arclength: f64,
}

impl BranchPoint {
    /// True when `H` is positive definite.
    pub fn is_stable(&self) -> bool {
        self.inertia.is_positive_definite()
    }
}

/// An event stored in a [`Branch`] (fields as in [`PathEvent`]).
#[derive(Clone, Debug, PartialEq)]
pub struct BranchEvent {
    /// Fold or possible bifurcation.
    pub kind: EventKind,
    /// The load at the located point.
    pub lambda: f64,
    /// The state at the located point.
    pub x: Vec<f64>,
    /// Pseudo-arclength of the located point.
    pub arclength: f64,
    /// Inertia at the accepted point before.
    pub inertia_before: Inertia,
    /// Inertia at the accepted point after.
    pub inertia_after: Inertia,
    /// `d lambda / ds` at the located point.
    pub tangent_lambda: f64,
    /// Bracketed to `event_tol`.
    pub located: bool,
    /// Index (in [`Branch::points`]) of the accepted point before it.
    pub after_point: usize,
}

/// A followed branch, stored: every accepted point (`O(steps * n)`), every
/// event, and the report. [`Palc::follow`](super::Palc::follow) with an observer avoids the
/// storage.
#[derive(Clone, Debug, PartialEq)]
pub struct Branch {
    /// The accepted points, the start first.
    pub points: Vec<BranchPoint>,
    /// The events, in order along the branch.
    pub events: Vec<BranchEvent>,
    /// Why and where it ended, and what it cost.
    pub report: PathReport,
}

impl Branch {
    /// The folds.
    pub fn folds(&self) -> impl Iterator<Item = &BranchEvent> {
        self.events.iter().filter(|e| e.kind == EventKind::Fold)
    }

    /// The last accepted point (the start if no step was accepted; `None`
    /// only if the start failed).
    pub fn last(&self) -> Option<&BranchPoint> {
        self.points.last()
    }
}

/// The observer behind [`Palc::branch`](super::Palc::branch): stores every
/// point and event, and asks `stop` about each point.
pub(super) struct Collect<S> {
    pub(super) points: Vec<BranchPoint>,
    pub(super) events: Vec<BranchEvent>,
    pub(super) stop: S,
}

impl<S: FnMut(&PathPoint<'_>) -> Control> PathObserver for Collect<S> {
    fn point(&mut self, p: &PathPoint<'_>) -> Control {
        self.points.push(BranchPoint {
            lambda: p.lambda,
            x: p.x.to_vec(),
            tangent_lambda: p.tangent_lambda,
            inertia: p.inertia,
            arclength: p.arclength,
        });
        (self.stop)(p)
    }
    fn event(&mut self, e: &PathEvent<'_>) {
        self.events.push(BranchEvent {
            kind: e.kind,
            lambda: e.lambda,
            x: e.x.to_vec(),
            arclength: e.arclength,
            inertia_before: e.inertia_before,
            inertia_after: e.inertia_after,
            tangent_lambda: e.tangent_lambda,
            located: e.located,
            after_point: e.after_point,
        });
    }
}

//! Pseudo-arclength continuation (PALC) of a parametrised equilibrium
//! `g(x, lambda) = 0`, through limit points, with fold and stability events;
//! and the inertia of a Hessian restricted to a constraint's tangent space.
//!
//! The method, its step control and event location are documented on
//! [`Palc`].

use crate::bordered::{Bordered, BorderedEval};
use crate::dense::{all_finite, dot, norm_inf};
use crate::linear::{FactorError, Inertia};
use crate::options::{LinearBackend, OptionsError, PalcOptions};
use crate::problem::{DenseMatrix, LinearSystem};
use crate::semiseparable::PivotKind;
use core::fmt;

// ---------------------------------------------------------------- problem

/// A parametrised equilibrium `g(x, lambda) = 0` to follow: the Hessian
/// `H = d g / d x` of the last [`Path::eval`] is the problem's
/// [`LinearSystem`] (symmetric, possibly indefinite; the driver factorises
/// it with [`PivotKind::Symmetric`] and needs `apply` at the same point).
///
/// Evaluations should not allocate: the driver's own workspace is
/// allocated once, in [`Palc::new`].
pub trait Path: LinearSystem {
    /// Number of state unknowns `n` (the load `lambda` is extra).
    fn dim(&self) -> usize;
    /// Writes `g(x, lambda)` into `g` and `d g / d lambda` into `g_lambda`
    /// (both of length `n`) and keeps `H` at `(x, lambda)`. Returns `false`
    /// when the point cannot be evaluated; non-finite entries are detected
    /// by the driver. Either way the step is shortened and retried.
    fn eval(&mut self, x: &[f64], lambda: f64, g: &mut [f64], g_lambda: &mut [f64]) -> bool;
}

impl<P: Path + ?Sized> Path for &mut P {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, g: &mut [f64], g_lambda: &mut [f64]) -> bool {
        (**self).eval(x, lambda, g, g_lambda)
    }
}

/// A [`Bordered`] problem as a [`Path`]: its `g`, `g_lambda` and `H` are
/// used, its target equation (`c`, `c_x`, `c_lambda`) is ignored (the
/// arclength equation replaces it). Holds one [`BorderedEval`] (allocated
/// once).
pub struct BorderedPath<P> {
    /// The wrapped problem.
    pub problem: P,
    eval: BorderedEval,
}

impl<P: Bordered> BorderedPath<P> {
    /// Wraps `problem` (its `dim()` fixes the size).
    pub fn new(problem: P) -> BorderedPath<P> {
        let n = problem.dim();
        BorderedPath {
            problem,
            eval: BorderedEval::new(n),
        }
    }

    /// The last evaluation of the wrapped problem (its target equation
    /// included).
    pub fn last(&self) -> &BorderedEval {
        &self.eval
    }
}

impl<P: Bordered> Path for BorderedPath<P> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, g: &mut [f64], g_lambda: &mut [f64]) -> bool {
        let ok = self.problem.eval(x, lambda, &mut self.eval);
        g.copy_from_slice(&self.eval.g);
        g_lambda.copy_from_slice(&self.eval.g_lambda);
        ok
    }
}

impl<P: LinearSystem> LinearSystem for BorderedPath<P> {
    fn diagonal_range(&self) -> (f64, f64) {
        self.problem.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.problem.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.problem.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.problem.apply(x, out)
    }
}

/// A path problem that writes its Hessian densely (wrap it in
/// [`DensePath`]).
pub trait DensePathProblem {
    /// Number of state unknowns `n`.
    fn dim(&self) -> usize;
    /// As [`Path::eval`], with `H` written into `h` (column-major `n * n`,
    /// at least the lower triangle).
    fn eval(
        &mut self,
        x: &[f64],
        lambda: f64,
        g: &mut [f64],
        g_lambda: &mut [f64],
        h: &mut [f64],
    ) -> bool;
}

impl<P: DensePathProblem + ?Sized> DensePathProblem for &mut P {
    fn dim(&self) -> usize {
        (**self).dim()
    }
    fn eval(
        &mut self,
        x: &[f64],
        lambda: f64,
        g: &mut [f64],
        g_lambda: &mut [f64],
        h: &mut [f64],
    ) -> bool {
        (**self).eval(x, lambda, g, g_lambda, h)
    }
}

/// A [`DensePathProblem`] as a [`Path`] (dense Bunch-Kaufman for its
/// Hessian, allocated once, factorising without allocation).
pub struct DensePath<P> {
    /// The wrapped problem.
    pub problem: P,
    /// Its Hessian and factorisation.
    pub matrix: DenseMatrix,
}

impl<P: DensePathProblem> DensePath<P> {
    /// Wraps `problem` (its `dim()` fixes the size).
    pub fn new(problem: P) -> DensePath<P> {
        let n = problem.dim();
        DensePath {
            problem,
            matrix: DenseMatrix::new(n, LinearBackend::Auto),
        }
    }
}

impl<P: DensePathProblem> Path for DensePath<P> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }
    fn eval(&mut self, x: &[f64], lambda: f64, g: &mut [f64], g_lambda: &mut [f64]) -> bool {
        self.problem
            .eval(x, lambda, g, g_lambda, self.matrix.matrix_mut())
    }
}

impl<P> LinearSystem for DensePath<P> {
    fn diagonal_range(&self) -> (f64, f64) {
        self.matrix.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.matrix.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.matrix.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.matrix.apply(x, out)
    }
}

// ----------------------------------------------------------------- output

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
    /// State part of the unit tangent (weighted norm, see [`Palc`]).
    pub tangent_x: &'a [f64],
    /// Load part of the unit tangent, `d lambda / ds`: its sign changes
    /// at folds.
    pub tangent_lambda: f64,
    /// Inertia of `H` here (`negative == 0`: stable at fixed load).
    pub inertia: Inertia,
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
    /// of the event along the branch, see [`Palc`]).
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

/// Receives the accepted points and events of [`Palc::follow`], in order.
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

impl PathTermination {
    /// True for the normal ends: `ReachedTarget`, `Stopped`, `MaxSteps`.
    pub fn is_normal(self) -> bool {
        matches!(
            self,
            PathTermination::ReachedTarget | PathTermination::Stopped | PathTermination::MaxSteps
        )
    }
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

/// Summary of one [`Palc::follow`] (or [`Palc::branch`]).
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
    /// Calls to [`Path::eval`].
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
    fn new(lambda: f64, step: f64) -> PathReport {
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
/// event, and the report. [`Palc::follow`] with an observer avoids the
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

struct Collect<S> {
    points: Vec<BranchPoint>,
    events: Vec<BranchEvent>,
    stop: S,
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

// ----------------------------------------------------------------- driver

/// A point of the branch with its tangent and inertia.
#[derive(Clone, Debug)]
struct State {
    x: Vec<f64>,
    lambda: f64,
    tx: Vec<f64>,
    tl: f64,
    inertia: Inertia,
    iterations: usize,
}

impl State {
    fn new(n: usize) -> State {
        State {
            x: vec![0.0; n],
            lambda: 0.0,
            tx: vec![0.0; n],
            tl: 0.0,
            inertia: Inertia::default(),
            iterations: 0,
        }
    }
}

/// Evaluation buffers and elimination scratch.
#[derive(Clone, Debug)]
struct Work {
    theta2: f64,
    g: Vec<f64>,
    gl: Vec<f64>,
    /// `H^-1 g_lambda` at the current factorisation.
    w: Vec<f64>,
    rx: Vec<f64>,
    dx: Vec<f64>,
    r: Vec<f64>,
    hx: Vec<f64>,
    start: Vec<f64>,
}

/// Why a corrector (or a step) failed.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Failure {
    NonFinite,
    Singular,
    NotConverged,
    TooFar,
    Turned,
    Events,
}

/// The constraint row of a corrector solve.
#[derive(Clone, Copy)]
enum Row<'a> {
    /// `<t_base, z - z_base>_theta = ds`.
    Arclength { base: &'a State, ds: f64 },
    /// `lambda = value`.
    Lambda(f64),
}

/// The border of a tangent solve.
#[derive(Clone, Copy)]
enum Border<'a> {
    /// `<t_prev, t>_theta > 0`.
    Tangent(&'a State),
    /// `sign(t_l) = sign`.
    Lambda(f64),
}

/// `||a - b||_theta` for states `(ax, al)`, `(bx, bl)`.
fn distance(theta2: f64, ax: &[f64], al: f64, bx: &[f64], bl: f64) -> f64 {
    let s: f64 = ax.iter().zip(bx).map(|(a, b)| (a - b) * (a - b)).sum();
    (s + theta2 * (al - bl) * (al - bl)).sqrt()
}

/// Solves `[H g_l; c^T cl] (dx, dl) = (rx, rc)` (`c = 0` when `None`) with
/// `H` factorised in `p` and `ws.w = H^-1 g_l`: block elimination and one
/// step of iterative refinement. Reads `ws.rx`, leaves `dx` in `ws.dx`,
/// returns `dl`.
fn bordered_solve<P: LinearSystem + ?Sized>(
    p: &mut P,
    ws: &mut Work,
    c: Option<&[f64]>,
    cl: f64,
    rc: f64,
) -> f64 {
    let dotc = |v: &[f64]| c.map_or(0.0, |c| dot(c, v));
    ws.dx.copy_from_slice(&ws.rx);
    p.solve(&mut ws.dx);
    let den = cl - dotc(&ws.w);
    let dl = (rc - dotc(&ws.dx)) / den;
    for (d, w) in ws.dx.iter_mut().zip(&ws.w) {
        *d -= w * dl;
    }
    p.apply(&ws.dx, &mut ws.hx);
    for i in 0..ws.r.len() {
        ws.r[i] = ws.rx[i] - ws.hx[i] - ws.gl[i] * dl;
    }
    let rr = rc - dotc(&ws.dx) - cl * dl;
    p.solve(&mut ws.r);
    let ddl = (rr - dotc(&ws.r)) / den;
    for ((d, r), w) in ws.dx.iter_mut().zip(&ws.r).zip(&ws.w) {
        *d += r - w * ddl;
    }
    dl + ddl
}

/// Newton on `g = 0` plus `row`, from the guess in `out`; on success `H`
/// is factorised at the converged point (inertia in `out`), `ws.g`, `ws.gl`
/// and `ws.w` hold the evaluation there. `max_dist`: largest distance of an
/// iterate from the guess.
fn correct<P: Path + ?Sized>(
    p: &mut P,
    o: &PalcOptions,
    ws: &mut Work,
    row: Row<'_>,
    out: &mut State,
    max_dist: f64,
    rep: &mut PathReport,
) -> Result<(), Failure> {
    ws.start.copy_from_slice(&out.x);
    let l_start = out.lambda;
    let mut k = 0usize;
    loop {
        if !(out.lambda.is_finite() && all_finite(&out.x)) {
            return Err(Failure::NonFinite);
        }
        rep.evaluations += 1;
        if !p.eval(&out.x, out.lambda, &mut ws.g, &mut ws.gl)
            || !all_finite(&ws.g)
            || !all_finite(&ws.gl)
        {
            return Err(Failure::NonFinite);
        }
        rep.factorizations += 1;
        out.inertia = p.factor(0.0, PivotKind::Symmetric).map_err(|e| match e {
            FactorError::NonFinite { .. } => Failure::NonFinite,
            _ => Failure::Singular,
        })?;
        ws.w.copy_from_slice(&ws.gl);
        p.solve(&mut ws.w);
        if !all_finite(&ws.w) {
            return Err(Failure::Singular);
        }
        if norm_inf(&ws.g) <= o.gtol {
            out.iterations = k;
            return Ok(());
        }
        if k >= o.max_corrector_iterations {
            return Err(Failure::NotConverged);
        }
        for (r, g) in ws.rx.iter_mut().zip(&ws.g) {
            *r = -g;
        }
        let dl = match row {
            Row::Arclength { base, ds } => {
                let cl = ws.theta2 * base.tl;
                let res = base
                    .tx
                    .iter()
                    .zip(&out.x)
                    .zip(&base.x)
                    .map(|((t, x), b)| t * (x - b))
                    .sum::<f64>()
                    + cl * (out.lambda - base.lambda)
                    - ds;
                bordered_solve(p, ws, Some(&base.tx), cl, -res)
            }
            Row::Lambda(value) => bordered_solve(p, ws, None, 1.0, value - out.lambda),
        };
        if !(dl.is_finite() && all_finite(&ws.dx)) {
            return Err(Failure::Singular);
        }
        for (x, d) in out.x.iter_mut().zip(&ws.dx) {
            *x += d;
        }
        out.lambda += dl;
        if let Row::Lambda(value) = row {
            // keep the prescribed load exact
            out.lambda = value;
        }
        k += 1;
        rep.corrector_iterations += 1;
        if distance(ws.theta2, &out.x, out.lambda, &ws.start, l_start) > max_dist {
            return Err(Failure::TooFar);
        }
    }
}

/// The unit tangent at the point `correct` just converged to (its
/// factorisation and `ws.w` current), oriented by `border`.
fn tangent<P: LinearSystem + ?Sized>(
    p: &mut P,
    ws: &mut Work,
    border: Border<'_>,
    out: &mut State,
) -> Result<(), Failure> {
    ws.rx.fill(0.0);
    let mu = match border {
        Border::Tangent(prev) => bordered_solve(p, ws, Some(&prev.tx), ws.theta2 * prev.tl, 1.0),
        Border::Lambda(sign) => bordered_solve(p, ws, None, 1.0, sign),
    };
    let norm = (dot(&ws.dx, &ws.dx) + ws.theta2 * mu * mu).sqrt();
    if !(norm.is_finite() && norm > 0.0) {
        return Err(Failure::Singular);
    }
    for (t, d) in out.tx.iter_mut().zip(&ws.dx) {
        *t = d / norm;
    }
    out.tl = mu / norm;
    Ok(())
}

/// Corrector at pseudo-arclength `s` along the step from `base` (Euler
/// predictor, then [`correct`] and [`tangent`]) into `out`.
fn step_to<P: Path + ?Sized>(
    p: &mut P,
    o: &PalcOptions,
    ws: &mut Work,
    base: &State,
    s: f64,
    out: &mut State,
    rep: &mut PathReport,
) -> Result<(), Failure> {
    for ((x, b), t) in out.x.iter_mut().zip(&base.x).zip(&base.tx) {
        *x = b + s * t;
    }
    out.lambda = base.lambda + s * base.tl;
    let max_dist = o.max_correction * s.abs().max(o.event_tol);
    correct(p, o, ws, Row::Arclength { base, ds: s }, out, max_dist, rep)?;
    tangent(p, ws, Border::Tangent(base), out)
}

/// Pseudo-arclength continuation driver and its workspace (all `O(n)`,
/// allocated by [`Palc::new`]; [`Palc::follow`] allocates nothing).
///
/// # The problem
///
/// A [`Path`] problem evaluates `g` (the gradient of an energy with respect
/// to `x`, `x` in `R^n`) and `g_lambda = d g / d lambda` at `(x, lambda)`,
/// and keeps the Hessian `H = d g / d x` there as its [`LinearSystem`]
/// (symmetric, possibly indefinite). [`BorderedPath`] turns any
/// [`Bordered`] problem into a `Path` (its target equation is ignored), and
/// [`DensePath`] wraps a problem that writes `H` densely
/// ([`DensePathProblem`]).
///
/// # The method
///
/// The branch is the curve `z(s) = (x(s), lambda(s))` of solutions,
/// parametrised by (pseudo-)arclength in the weighted norm
///
/// ```text
/// ||(dx, dlambda)||_theta = sqrt(||dx||_2^2 + theta^2 dlambda^2)
/// ```
///
/// (`theta` = [`PalcOptions::theta`]: one unit of the load counts as `theta`
/// units of the state). With `<a, b>_theta = a_x . b_x + theta^2 a_l b_l`:
///
/// * **Tangent** at an accepted point: `t = (t_x, t_l)` with
///   `H t_x + g_lambda t_l = 0`, `||t||_theta = 1`, oriented so that
///   `<t, t_prev>_theta > 0`. It is computed from the bordered system
///   `[H g_lambda; t_prev_x^T theta^2 t_prev_l] (v, mu) = (0, 1)` and
///   normalised; at the start the border is `(0, 1)` and the sign of `mu`
///   is the requested [`Direction`].
/// * **Predictor** (Euler): `z_p = z_0 + ds t_0`.
/// * **Corrector**: Newton on `g(z) = 0`, `<t_0, z - z_0>_theta = ds`, i.e.
///   on the hyperplane through `z_p` orthogonal to `t_0`. Each step solves
///
///   ```text
///   [ H          g_lambda       ] [dx]     [ g ]
///   [ t_0x^T     theta^2 t_0l   ] [dl] = - [ N ]
///   ```
///
///   by block elimination on the problem's factorisation of `H` (symmetric
///   pivots, [`PivotKind::Symmetric`]) with one step of iterative refinement
///   on the whole bordered system (as [`BorderedNewton`](crate::BorderedNewton)
///   does). At a simple fold `H` is singular but the bordered matrix is not
///   (`g_lambda` is not in the range of `H`, and `t_0x` is not orthogonal
///   to its null vector), so the corrector stays well posed through the
///   limit point; the refinement recovers what the elimination loses while
///   `H` is nearly singular. Only an `H` that is singular to the working
///   precision of its factorisation (a zero pivot) fails; the step is then
///   shortened and retried, so an accepted point never sits exactly on a
///   fold. Converged when `||g||_inf <= gtol` (the arclength equation is
///   linear and holds to rounding after the first Newton step).
/// * **Step control**: a step is rejected when the corrector does not
///   converge within `max_corrector_iterations`, an iterate strays farther
///   than `max_correction * ds` from the predictor, an evaluation or
///   factorisation is non-finite or singular, the tangent turns by more than
///   `acos(min_tangent_cos)`, or (with event detection) one step shows more
///   than one event; a rejected step is retried with `ds * shrink` (at least
///   `min_step`). After a corrector that needed at most `easy_iterations`
///   iterations the step grows by `grow` (at most `max_step`).
///
/// # Events
///
/// Every accepted point carries the inertia of `H` there (from the
/// factorisation the tangent needs anyway: no extra work), so its
/// stability (`negative == 0`: a local minimum of the energy in `x` at
/// fixed load). Between two accepted points:
///
/// * a sign change of `t_l` is a **fold** (limit point), [`EventKind::Fold`];
///   it is located by a safeguarded regula falsi (Illinois) on `t_l(s)`,
///   each trial a corrector solve at pseudo-arclength `s` along the step;
/// * a change of the number of negative eigenvalues without a sign change
///   of `t_l` is a **possible bifurcation** (branch point),
///   [`EventKind::PossibleBifurcation`], located by bisection on the
///   inertia. No branch switching is attempted.
///
/// A step whose endpoints show more than one event (a fold with a change of
/// the negative count other than one, or a change by more than one) is
/// retried shorter, so events are resolved one per step unless the step is
/// already at `min_step`. Two events closer together than one step with
/// no net change (two folds in one step) are not seen; `max_step` and
/// `min_tangent_cos` bound how far a step reaches.
///
/// Location tolerance: an event is bracketed to `event_tol` in the
/// pseudo-arclength `s` along the step, and the reported point is a
/// converged equilibrium (`||g||_inf <= gtol`) at one end of that bracket.
/// So its distance to the event is at most about `event_tol /
/// min_tangent_cos` in the weighted norm (in particular in `||x||_2`);
/// at a fold, where `d lambda / ds = 0`, its `lambda` is off by `O(event_tol^2)`
/// (times the curvature of `lambda(s)`). Corrector residuals add their own
/// `O(gtol / sigma_min)` to both.
///
/// # Output
///
/// [`Palc::follow`] hands every accepted point ([`PathPoint`]) and event
/// ([`PathEvent`]) to a [`PathObserver`] as borrowed slices and allocates
/// nothing once the [`Palc`] workspace exists (if the problem's
/// evaluations and factorisations do not allocate); the observer's answer
/// ([`Control`]) is the stop predicate. [`Palc::branch`] stores everything
/// in a [`Branch`] instead. Both end with a [`PathReport`].
///
/// # Restricted inertia
///
/// [`restricted_inertia`] and [`factor_restricted_inertia`] give the
/// inertia of `H` on the tangent space `{v : c_x . v = 0}` of a constraint
/// (the stability of a target-constrained equilibrium), from a symmetric
/// factorisation of `H` and the sign of one Schur complement (Haynsworth).
///
/// # Example
///
/// ```
/// use fpc_newton::{Control, DensePath, DensePathProblem, Direction, EventKind, Palc, PalcOptions};
///
/// /// E = x^4/4 - x^2/2 - lambda x: g = x^3 - x - lambda, a snap-through.
/// struct Snap;
/// impl DensePathProblem for Snap {
///     fn dim(&self) -> usize {
///         1
///     }
///     fn eval(&mut self, x: &[f64], l: f64, g: &mut [f64], gl: &mut [f64], h: &mut [f64]) -> bool {
///         g[0] = x[0].powi(3) - x[0] - l;
///         gl[0] = -1.0;
///         h[0] = 3.0 * x[0] * x[0] - 1.0;
///         true
///     }
/// }
///
/// let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
/// let mut p = DensePath::new(Snap);
/// // from the equilibrium near x = -1.32 at lambda = -1 up to lambda = +1
/// let branch = palc.branch(&mut p, &[-1.3], -1.0, Direction::Increasing, Some(1.0), |_| {
///     Control::Continue
/// });
/// assert_eq!(branch.report.termination, fpc_newton::PathTermination::ReachedTarget);
/// assert_eq!(branch.last().unwrap().lambda, 1.0);
/// let folds: Vec<_> = branch.folds().collect();
/// assert_eq!(folds.len(), 2);
/// let lf = 2.0 / (3.0 * 3f64.sqrt());
/// assert!((folds[0].lambda - lf).abs() < 1e-10 && (folds[1].lambda + lf).abs() < 1e-10);
/// assert_eq!(folds[0].kind, EventKind::Fold);
/// assert_eq!((folds[0].inertia_before.negative, folds[0].inertia_after.negative), (0, 1));
/// ```
#[derive(Clone, Debug)]
pub struct Palc {
    n: usize,
    opts: PalcOptions,
    cur: State,
    next: State,
    trial: State,
    event_x: Vec<f64>,
    ws: Work,
    started: bool,
}

impl Palc {
    /// A driver for `n` state unknowns.
    pub fn new(n: usize, opts: PalcOptions) -> Result<Palc, OptionsError> {
        opts.validate()?;
        Ok(Palc {
            n,
            opts,
            cur: State::new(n),
            next: State::new(n),
            trial: State::new(n),
            event_x: vec![0.0; n],
            ws: Work {
                theta2: opts.theta * opts.theta,
                g: vec![0.0; n],
                gl: vec![0.0; n],
                w: vec![0.0; n],
                rx: vec![0.0; n],
                dx: vec![0.0; n],
                r: vec![0.0; n],
                hx: vec![0.0; n],
                start: vec![0.0; n],
            },
            started: false,
        })
    }

    /// The options.
    pub fn options(&self) -> &PalcOptions {
        &self.opts
    }

    /// Replaces the options (validated; on error the old ones stay).
    pub fn set_options(&mut self, opts: PalcOptions) -> Result<(), OptionsError> {
        opts.validate()?;
        self.opts = opts;
        self.ws.theta2 = opts.theta * opts.theta;
        Ok(())
    }

    /// The last accepted point `(x, lambda)` of the last run (`None` before
    /// a run, or when its start failed).
    pub fn last_point(&self) -> Option<(&[f64], f64)> {
        self.started.then_some((&self.cur.x[..], self.cur.lambda))
    }

    /// The unit tangent `(t_x, t_lambda)` at [`Palc::last_point`].
    pub fn last_tangent(&self) -> Option<(&[f64], f64)> {
        self.started.then_some((&self.cur.tx[..], self.cur.tl))
    }

    fn view(&self, index: usize, arclength: f64) -> PathPoint<'_> {
        PathPoint {
            index,
            lambda: self.cur.lambda,
            x: &self.cur.x,
            tangent_x: &self.cur.tx,
            tangent_lambda: self.cur.tl,
            inertia: self.cur.inertia,
            arclength,
            corrector_iterations: self.cur.iterations,
        }
    }

    /// Follows the branch of `g(x, lambda) = 0` through `(x0, lambda0)`,
    /// handing every accepted point and event to `observer`.
    ///
    /// The start is first polished by Newton at fixed `lambda0` (at most
    /// `max_corrector_iterations` plain Newton steps, no line search: give
    /// an equilibrium or a close guess) and is point 0. The branch leaves it
    /// in `direction`; it ends at the first step that reaches or crosses
    /// `target` (if given; a start exactly at the target does not count),
    /// with a last point solved at `lambda = target` exactly (Newton at
    /// fixed load from the interpolation within the step); when the
    /// observer returns [`Control::Stop`]; after `max_steps` accepted steps;
    /// or when a step fails at `min_step` (see [`PathTermination`]).
    /// [`Palc::last_point`] then holds the last accepted point.
    ///
    /// Allocates nothing (the workspace is [`Palc::new`]'s), if the
    /// problem's evaluations, factorisations and solves and the observer do
    /// not.
    ///
    /// # Panics
    /// If `x0.len()` or `p.dim()` differ from the dimension given to
    /// [`Palc::new`] (programmer error).
    pub fn follow<P: Path + ?Sized, O: PathObserver + ?Sized>(
        &mut self,
        p: &mut P,
        x0: &[f64],
        lambda0: f64,
        direction: Direction,
        target: Option<f64>,
        observer: &mut O,
    ) -> PathReport {
        let n = self.n;
        assert_eq!(
            x0.len(),
            n,
            "Palc::follow: x0.len() must equal the dimension given to Palc::new"
        );
        assert_eq!(
            p.dim(),
            n,
            "Palc::follow: problem dim() must equal the dimension given to Palc::new"
        );
        let o = self.opts;
        let mut rep = PathReport::new(lambda0, o.initial_step);
        self.started = false;
        if o.validate().is_err() || !lambda0.is_finite() || target.is_some_and(|t| !t.is_finite()) {
            return rep;
        }

        // the start: Newton at fixed load, then the tangent
        self.cur.x.copy_from_slice(x0);
        self.cur.lambda = lambda0;
        let sign = match direction {
            Direction::Increasing => 1.0,
            Direction::Decreasing => -1.0,
        };
        let start = correct(
            p,
            &o,
            &mut self.ws,
            Row::Lambda(lambda0),
            &mut self.cur,
            f64::INFINITY,
            &mut rep,
        )
        .and_then(|()| tangent(p, &mut self.ws, Border::Lambda(sign), &mut self.cur));
        if let Err(f) = start {
            rep.termination = if f == Failure::NonFinite {
                PathTermination::NonFinite
            } else {
                PathTermination::StartFailed
            };
            return rep;
        }
        self.started = true;
        let mut arc = 0.0;
        if observer.point(&self.view(0, arc)) == Control::Stop {
            rep.termination = PathTermination::Stopped;
            return rep;
        }

        let theta2 = self.ws.theta2;
        let mut ds = o.initial_step;
        loop {
            if rep.steps >= o.max_steps {
                rep.termination = PathTermination::MaxSteps;
                break;
            }
            let mut landed = false;
            let attempt = step_to(p, &o, &mut self.ws, &self.cur, ds, &mut self.next, &mut rep)
                .and_then(|()| {
                    let cos =
                        dot(&self.cur.tx, &self.next.tx) + theta2 * self.cur.tl * self.next.tl;
                    if cos < o.min_tangent_cos {
                        return Err(Failure::Turned);
                    }
                    // the target: land on it exactly
                    let (l0, l1) = (self.cur.lambda, self.next.lambda);
                    let Some(t) = target else { return Ok(()) };
                    if l0 == t || (l1 - t).signum() == (l0 - t).signum() && l1 != t {
                        return Ok(());
                    }
                    let f = (t - l0) / (l1 - l0);
                    for (x1, x0) in self.next.x.iter_mut().zip(&self.cur.x) {
                        *x1 = x0 + f * (*x1 - x0);
                    }
                    self.next.lambda = t;
                    correct(
                        p,
                        &o,
                        &mut self.ws,
                        Row::Lambda(t),
                        &mut self.next,
                        o.max_correction * ds,
                        &mut rep,
                    )?;
                    tangent(p, &mut self.ws, Border::Tangent(&self.cur), &mut self.next)?;
                    landed = true;
                    Ok(())
                })
                .and_then(|()| {
                    if !o.detect_events || ds <= o.min_step {
                        return Ok(());
                    }
                    let (fold, dneg) = self.events_between();
                    if (fold && dneg.abs() != 1) || dneg.abs() > 1 {
                        Err(Failure::Events)
                    } else {
                        Ok(())
                    }
                });
            if let Err(f) = attempt {
                rep.rejected += 1;
                if ds <= o.min_step {
                    rep.termination = if f == Failure::NonFinite {
                        PathTermination::NonFinite
                    } else {
                        PathTermination::StepTooSmall
                    };
                    break;
                }
                ds = (ds * o.shrink).max(o.min_step);
                rep.step = ds;
                continue;
            }

            // accepted: events first, then the point
            if o.detect_events {
                let (fold, dneg) = self.events_between();
                if fold || dneg != 0 {
                    let kind = if fold {
                        EventKind::Fold
                    } else {
                        EventKind::PossibleBifurcation
                    };
                    let (located, lambda, tl) = self.locate(p, kind, &mut rep);
                    rep.events += 1;
                    let ev = PathEvent {
                        kind,
                        lambda,
                        x: &self.event_x,
                        arclength: arc
                            + distance(theta2, &self.event_x, lambda, &self.cur.x, self.cur.lambda),
                        inertia_before: self.cur.inertia,
                        inertia_after: self.next.inertia,
                        tangent_lambda: tl,
                        located,
                        after_point: rep.steps,
                    };
                    observer.event(&ev);
                }
            }
            arc += distance(
                theta2,
                &self.next.x,
                self.next.lambda,
                &self.cur.x,
                self.cur.lambda,
            );
            core::mem::swap(&mut self.cur, &mut self.next);
            rep.steps += 1;
            rep.lambda = self.cur.lambda;
            rep.arclength = arc;
            let easy = self.cur.iterations <= o.easy_iterations;
            if observer.point(&self.view(rep.steps, arc)) == Control::Stop {
                rep.termination = PathTermination::Stopped;
                break;
            }
            if landed {
                rep.termination = PathTermination::ReachedTarget;
                break;
            }
            if easy {
                ds = (ds * o.grow).min(o.max_step);
            }
            rep.step = ds;
        }
        rep
    }

    /// Like [`Palc::follow`], storing every point and event in a
    /// [`Branch`] (allocates `O(n)` per point); `stop` is the stop
    /// predicate (return [`Control::Continue`] to follow to the target or
    /// the other limits).
    pub fn branch<P: Path + ?Sized, S: FnMut(&PathPoint<'_>) -> Control>(
        &mut self,
        p: &mut P,
        x0: &[f64],
        lambda0: f64,
        direction: Direction,
        target: Option<f64>,
        stop: S,
    ) -> Branch {
        let mut c = Collect {
            points: Vec::new(),
            events: Vec::new(),
            stop,
        };
        let report = self.follow(p, x0, lambda0, direction, target, &mut c);
        Branch {
            points: c.points,
            events: c.events,
            report,
        }
    }

    /// `(fold, change of the negative count)` between `cur` and `next`.
    fn events_between(&self) -> (bool, isize) {
        let (a, b) = (self.cur.tl, self.next.tl);
        let fold = (a > 0.0 && b <= 0.0) || (a < 0.0 && b >= 0.0);
        let dneg = self.next.inertia.negative as isize - self.cur.inertia.negative as isize;
        (fold, dneg)
    }

    /// Locates the event between `cur` and `next` ([`Palc`] docs) into
    /// `event_x`; returns `(located, lambda, t_lambda)` of the point found.
    fn locate<P: Path + ?Sized>(
        &mut self,
        p: &mut P,
        kind: EventKind,
        rep: &mut PathReport,
    ) -> (bool, f64, f64) {
        let o = self.opts;
        let theta2 = self.ws.theta2;
        let (cur, next, trial) = (&self.cur, &self.next, &mut self.trial);
        // the step's length along the tangent at its start
        let s1 = cur
            .tx
            .iter()
            .zip(&next.x)
            .zip(&cur.x)
            .map(|((t, x1), x0)| t * (x1 - x0))
            .sum::<f64>()
            + theta2 * cur.tl * (next.lambda - cur.lambda);
        let tol = o.event_tol;
        // best point so far: the endpoint nearer the event
        let (mut best_l, mut best_t) = (next.lambda, next.tl);
        self.event_x.copy_from_slice(&next.x);
        if kind == EventKind::Fold && cur.tl.abs() < next.tl.abs() {
            (best_l, best_t) = (cur.lambda, cur.tl);
            self.event_x.copy_from_slice(&cur.x);
        }
        if !(s1.is_finite() && s1 > 0.0) {
            return (false, best_l, best_t);
        }
        let mut iters = 0usize;
        match kind {
            EventKind::Fold => {
                // Illinois on t_l(s), s in [0, s1], kept inside the bracket
                // by tol / 2 so that it shrinks to tol
                let (mut a, mut fa) = (0.0, cur.tl);
                let (mut b, mut fb) = (s1, next.tl);
                let mut width = s1;
                let mut stalls = 0usize;
                while (b - a).abs() > tol && fb != 0.0 {
                    if iters >= o.max_locate_iterations {
                        return (false, best_l, best_t);
                    }
                    iters += 1;
                    let (lo, hi) = if a < b { (a, b) } else { (b, a) };
                    let mut s = if stalls >= 2 {
                        stalls = 0;
                        0.5 * (a + b)
                    } else {
                        b - fb * (b - a) / (fb - fa)
                    };
                    if !s.is_finite() {
                        s = 0.5 * (a + b);
                    }
                    s = s.clamp(lo + 0.5 * tol, hi - 0.5 * tol);
                    rep.locate_solves += 1;
                    if step_to(p, &o, &mut self.ws, cur, s, trial, rep).is_err() {
                        return (false, best_l, best_t);
                    }
                    let fs = trial.tl;
                    if fs.abs() <= best_t.abs() {
                        (best_l, best_t) = (trial.lambda, fs);
                        self.event_x.copy_from_slice(&trial.x);
                    }
                    if (fs > 0.0) != (fb > 0.0) {
                        (a, fa) = (b, fb);
                    } else {
                        fa *= 0.5;
                    }
                    (b, fb) = (s, fs);
                    let w = (b - a).abs();
                    if w > 0.5 * width {
                        stalls += 1;
                    } else {
                        stalls = 0;
                        width = w;
                    }
                }
                (true, best_l, best_t)
            }
            EventKind::PossibleBifurcation => {
                // bisection on the negative count
                let n0 = cur.inertia.negative;
                let (mut a, mut b) = (0.0, s1);
                while b - a > tol {
                    if iters >= o.max_locate_iterations {
                        return (false, best_l, best_t);
                    }
                    iters += 1;
                    let m = 0.5 * (a + b);
                    rep.locate_solves += 1;
                    if step_to(p, &o, &mut self.ws, cur, m, trial, rep).is_err() {
                        return (false, best_l, best_t);
                    }
                    if trial.inertia.negative == n0 {
                        a = m;
                    } else {
                        b = m;
                        (best_l, best_t) = (trial.lambda, trial.tl);
                        self.event_x.copy_from_slice(&trial.x);
                    }
                }
                (true, best_l, best_t)
            }
        }
    }
}

// ------------------------------------------------------ restricted inertia

/// Why the restricted inertia could not be computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, thiserror::Error)]
pub enum RestrictedInertiaError {
    /// The constraint gradient `c_x` is zero or holds a non-finite entry.
    #[error("constraint gradient is zero or not finite")]
    DegenerateConstraint,
    /// `H` itself could not be factorised with symmetric pivots (in
    /// particular: `H` singular). The Schur-complement route needs `H`
    /// nonsingular, even where the bordered matrix is not singular.
    #[error("the Hessian could not be factorised: {0}")]
    Hessian(FactorError),
    /// The Schur complement `c_x^T H^-1 c_x` is zero, or its sign
    /// contradicts the inertia of `H`: the bordered matrix is (numerically)
    /// singular, i.e. the restricted Hessian has a zero eigenvalue.
    #[error("the bordered matrix is singular (zero restricted eigenvalue)")]
    Singular,
    /// `H^-1 c_x` is not finite.
    #[error("non-finite solve with the Hessian")]
    NonFinite,
}

/// The inertia of `H` restricted to the tangent space `{v : c_x . v = 0}`
/// of a constraint, i.e. of `Z^T H Z` for an orthonormal basis `Z` of that
/// space (dimension `n - 1`), from a symmetric factorisation of `H`.
///
/// `h` must hold a successful factorisation of `H` itself (`tau = 0`,
/// typically [`PivotKind::Symmetric`]) with inertia `inertia`, and `apply`
/// the same `H` (used for one step of iterative refinement of
/// `w = H^-1 c_x`). By Haynsworth's inertia additivity on the bordered
/// matrix `K = [[H, c_x], [c_x^T, 0]]`,
/// `inertia(K) = inertia(H) + inertia(-c_x^T H^-1 c_x)`, and since `K` is
/// congruent to `Z^T H Z` plus a 2 x 2 block with one positive and one
/// negative eigenvalue, the restricted inertia is that of `K` minus one
/// positive and one negative: with `sigma = c_x^T w`, `(p, q - 1)` for
/// `sigma < 0` and `(p - 1, q)` for `sigma > 0`, where `(p, q) = inertia`.
///
/// A nearly singular (but factorised) `H` is fine: the large component of
/// `w` along its near-null vector gives `sigma` the sign of the small
/// eigenvalue, which the restricted count then drops. An `H` singular to
/// the factorisation cannot be used (see
/// [`RestrictedInertiaError::Hessian`] from [`factor_restricted_inertia`]),
/// even when `K` is regular.
///
/// `work` is scratch of length at least `2 n`; nothing is allocated.
///
/// # Panics
/// If `c_x.len() * 2 > work.len()`.
pub fn restricted_inertia<L: LinearSystem + ?Sized>(
    h: &mut L,
    inertia: Inertia,
    c_x: &[f64],
    work: &mut [f64],
) -> Result<Inertia, RestrictedInertiaError> {
    let n = c_x.len();
    assert!(
        work.len() >= 2 * n,
        "restricted_inertia: work.len() must be at least 2 * c_x.len()"
    );
    let (w, r) = work.split_at_mut(n);
    restricted_inertia_with(h, inertia, c_x, w, &mut r[..n])
}

/// [`restricted_inertia`] with the scratch as two vectors of length `n`.
pub(crate) fn restricted_inertia_with<L: LinearSystem + ?Sized>(
    h: &mut L,
    inertia: Inertia,
    c_x: &[f64],
    w: &mut [f64],
    r: &mut [f64],
) -> Result<Inertia, RestrictedInertiaError> {
    if !all_finite(c_x) || c_x.iter().all(|&c| c == 0.0) {
        return Err(RestrictedInertiaError::DegenerateConstraint);
    }
    w.copy_from_slice(c_x);
    h.solve(w);
    // one step of iterative refinement: w += H^-1 (c - H w)
    h.apply(w, r);
    for (ri, ci) in r.iter_mut().zip(c_x) {
        *ri = ci - *ri;
    }
    h.solve(r);
    for (wi, ri) in w.iter_mut().zip(r.iter()) {
        *wi += ri;
    }
    if !all_finite(w) {
        return Err(RestrictedInertiaError::NonFinite);
    }
    let sigma = dot(c_x, w);
    let Inertia { positive, negative } = inertia;
    if sigma < 0.0 && negative > 0 {
        Ok(Inertia {
            positive,
            negative: negative - 1,
        })
    } else if sigma > 0.0 && positive > 0 {
        Ok(Inertia {
            positive: positive - 1,
            negative,
        })
    } else {
        Err(RestrictedInertiaError::Singular)
    }
}

/// Factorises `h` (`H`, symmetric pivots, no shift) and returns its
/// inertia restricted to `{v : c_x . v = 0}` ([`restricted_inertia`]).
/// `Err(Hessian(Singular))` when `H` is singular (the restricted inertia is
/// then not determined by this route, see [`restricted_inertia`]).
///
/// # Panics
/// If `c_x.len() * 2 > work.len()`.
pub fn factor_restricted_inertia<L: LinearSystem + ?Sized>(
    h: &mut L,
    c_x: &[f64],
    work: &mut [f64],
) -> Result<Inertia, RestrictedInertiaError> {
    let inertia = h
        .factor(0.0, PivotKind::Symmetric)
        .map_err(RestrictedInertiaError::Hessian)?;
    restricted_inertia(h, inertia, c_x, work)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::testutil::Lcg;

    /// `E = x^4/4 - x^2/2 - lambda x`: `g = x^3 - x - lambda`.
    struct Snap;
    impl DensePathProblem for Snap {
        fn dim(&self) -> usize {
            1
        }
        fn eval(
            &mut self,
            x: &[f64],
            l: f64,
            g: &mut [f64],
            gl: &mut [f64],
            h: &mut [f64],
        ) -> bool {
            g[0] = x[0].powi(3) - x[0] - l;
            gl[0] = -1.0;
            h[0] = 3.0 * x[0] * x[0] - 1.0;
            true
        }
    }

    fn work(n: usize, theta: f64) -> Work {
        Work {
            theta2: theta * theta,
            g: vec![0.0; n],
            gl: vec![0.0; n],
            w: vec![0.0; n],
            rx: vec![0.0; n],
            dx: vec![0.0; n],
            r: vec![0.0; n],
            hx: vec![0.0; n],
            start: vec![0.0; n],
        }
    }

    #[test]
    fn bordered_solve_is_accurate_next_to_a_singular_h() {
        // H = diag(eps, 1, 2), g_l = (1, 1, 1), border c = (1, 0, 1), cl = 0.5
        for eps in [1e-3, 1e-8, 1e-13] {
            let mut m = DenseMatrix::new(3, LinearBackend::Auto);
            let h = m.matrix_mut();
            h.fill(0.0);
            h[0] = eps;
            h[4] = 1.0;
            h[8] = 2.0;
            m.factor(0.0, PivotKind::Symmetric).unwrap();
            let mut ws = work(3, 1.0);
            ws.gl.copy_from_slice(&[1.0, 1.0, 1.0]);
            ws.w.copy_from_slice(&ws.gl);
            m.solve(&mut ws.w);
            ws.rx.copy_from_slice(&[0.3, -0.2, 0.7]);
            let c = [1.0, 0.0, 1.0];
            let dl = bordered_solve(&mut m, &mut ws, Some(&c), 0.5, 0.1);
            // residual of the bordered system
            let d = &ws.dx;
            let r = [
                eps * d[0] + dl - 0.3,
                d[1] + dl + 0.2,
                2.0 * d[2] + dl - 0.7,
                d[0] + d[2] + 0.5 * dl - 0.1,
            ];
            let rn = r.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            assert!(rn < 1e-14, "eps = {eps}: residual {rn:e}");
        }
    }

    #[test]
    fn tangent_is_unit_and_oriented() {
        let mut p = DensePath::new(Snap);
        let o = PalcOptions {
            theta: 2.0,
            ..Default::default()
        };
        let mut ws = work(1, o.theta);
        let mut rep = PathReport::new(0.0, 0.0);
        let mut s = State::new(1);
        s.x[0] = 1.5;
        s.lambda = 1.5f64.powi(3) - 1.5;
        correct(
            &mut p,
            &o,
            &mut ws,
            Row::Lambda(s.lambda),
            &mut s,
            f64::INFINITY,
            &mut rep,
        )
        .unwrap();
        tangent(&mut p, &mut ws, Border::Lambda(-1.0), &mut s).unwrap();
        // dx/dlambda = 1 / (3 x^2 - 1); t ~ (1/(3x^2-1), 1)
        let slope: f64 = 1.0 / (3.0 * 2.25 - 1.0);
        let norm = (slope * slope + 4.0).sqrt();
        assert!((s.tx[0] + slope / norm).abs() < 1e-14);
        assert!((s.tl + 1.0 / norm).abs() < 1e-14);
        assert!((s.tx[0].powi(2) + 4.0 * s.tl * s.tl - 1.0).abs() < 1e-14);
    }

    #[test]
    fn corrector_passes_a_fold_where_natural_continuation_cannot() {
        // from x slightly below -1/sqrt 3 (just before the fold at lambda = 2/(3 sqrt 3)),
        // a step along the tangent lands past the fold
        let mut p = DensePath::new(Snap);
        let o = PalcOptions::default();
        let mut ws = work(1, 1.0);
        let mut rep = PathReport::new(0.0, 0.0);
        let mut a = State::new(1);
        a.x[0] = -0.6;
        a.lambda = -0.216 + 0.6;
        correct(
            &mut p,
            &o,
            &mut ws,
            Row::Lambda(a.lambda),
            &mut a,
            f64::INFINITY,
            &mut rep,
        )
        .unwrap();
        tangent(&mut p, &mut ws, Border::Lambda(1.0), &mut a).unwrap();
        let mut b = State::new(1);
        step_to(&mut p, &o, &mut ws, &a, 0.1, &mut b, &mut rep).unwrap();
        assert!(b.x[0] > -1.0 / 3f64.sqrt(), "past the fold: x = {}", b.x[0]);
        assert!(b.tl < 0.0 && a.tl > 0.0);
        assert_eq!((a.inertia.negative, b.inertia.negative), (0, 1));
        let g = b.x[0].powi(3) - b.x[0] - b.lambda;
        assert!(g.abs() <= 1e-10);
    }

    #[test]
    fn restricted_inertia_small_cases() {
        let mut m = DenseMatrix::new(3, LinearBackend::Auto);
        let mut work = [0.0; 6];
        // H = diag(-1, 2, 3): constraint along the negative direction
        // removes it; along a positive one keeps it
        let set = |m: &mut DenseMatrix, d: [f64; 3]| {
            let h = m.matrix_mut();
            h.fill(0.0);
            for (i, v) in d.iter().enumerate() {
                h[i * 4] = *v;
            }
        };
        set(&mut m, [-1.0, 2.0, 3.0]);
        let r = factor_restricted_inertia(&mut m, &[1.0, 0.0, 0.0], &mut work).unwrap();
        assert_eq!(
            r,
            Inertia {
                positive: 2,
                negative: 0
            }
        );
        let r = factor_restricted_inertia(&mut m, &[0.0, 1.0, 0.0], &mut work).unwrap();
        assert_eq!(
            r,
            Inertia {
                positive: 1,
                negative: 1
            }
        );
        // nearly singular H: the near-null direction is constrained away
        set(&mut m, [-1e-14, 2.0, 3.0]);
        let r = factor_restricted_inertia(&mut m, &[1.0, 1.0, 0.0], &mut work).unwrap();
        assert_eq!(
            r,
            Inertia {
                positive: 2,
                negative: 0
            }
        );
        // singular H: an error, even though K is regular
        set(&mut m, [0.0, 2.0, 3.0]);
        assert!(matches!(
            factor_restricted_inertia(&mut m, &[1.0, 0.0, 0.0], &mut work),
            Err(RestrictedInertiaError::Hessian(_))
        ));
        // zero constraint
        set(&mut m, [1.0, 2.0, 3.0]);
        assert_eq!(
            factor_restricted_inertia(&mut m, &[0.0; 3], &mut work),
            Err(RestrictedInertiaError::DegenerateConstraint)
        );
        // K singular: H = diag(1, -1, 2), c = (1, 1, 0): c^T H^-1 c = 0
        set(&mut m, [1.0, -1.0, 2.0]);
        assert_eq!(
            factor_restricted_inertia(&mut m, &[1.0, 1.0, 0.0], &mut work),
            Err(RestrictedInertiaError::Singular)
        );
        // random: the sign rule against a direct count on a Householder basis
        let mut rng = Lcg::new(7);
        for _ in 0..50 {
            let n = 3;
            let mut a = [0.0; 9];
            for j in 0..n {
                for i in j..n {
                    let v = 2.0 * rng.sym();
                    a[i + n * j] = v;
                    a[j + n * i] = v;
                }
            }
            m.matrix_mut().copy_from_slice(&a);
            let c = [rng.sym(), rng.sym(), rng.sym()];
            let Ok(r) = factor_restricted_inertia(&mut m, &c, &mut work) else {
                continue;
            };
            let z = null_basis(&c);
            let red = reduce(n, &a, &z);
            let neg = crate::negative_eigenvalues(n - 1, &red).unwrap();
            assert_eq!(r.negative, neg);
            assert_eq!(r.positive + r.negative, n - 1);
        }
    }

    /// Orthonormal basis of `c`'s orthogonal complement (Householder),
    /// column-major `n x (n-1)`.
    fn null_basis(c: &[f64]) -> Vec<f64> {
        let n = c.len();
        let norm = dot(c, c).sqrt();
        let mut v = c.to_vec();
        v[0] += norm.copysign(c[0]);
        let vv = dot(&v, &v);
        let mut z = vec![0.0; n * (n - 1)];
        for j in 1..n {
            for i in 0..n {
                let e = if i == j { 1.0 } else { 0.0 };
                z[i + n * (j - 1)] = e - 2.0 * v[i] * v[j] / vv;
            }
        }
        z
    }

    fn reduce(n: usize, a: &[f64], z: &[f64]) -> Vec<f64> {
        let m = n - 1;
        let mut red = vec![0.0; m * m];
        for q in 0..m {
            for pcol in 0..m {
                let mut s = 0.0;
                for i in 0..n {
                    for j in 0..n {
                        s += z[i + n * pcol] * a[i + n * j] * z[j + n * q];
                    }
                }
                red[pcol + m * q] = s;
            }
        }
        red
    }

    #[test]
    fn invalid_input_evaluates_nothing() {
        let mut p = DensePath::new(Snap);
        let mut palc = Palc::new(1, PalcOptions::default()).unwrap();
        let r = palc.follow(
            &mut p,
            &[0.0],
            f64::NAN,
            Direction::Increasing,
            None,
            &mut |_: &PathPoint<'_>| Control::Continue,
        );
        assert_eq!(r.termination, PathTermination::InvalidInput);
        assert_eq!(r.evaluations, 0);
        let r = palc.follow(
            &mut p,
            &[0.0],
            0.0,
            Direction::Increasing,
            Some(f64::INFINITY),
            &mut |_: &PathPoint<'_>| Control::Continue,
        );
        assert_eq!(r.termination, PathTermination::InvalidInput);
        assert!(palc.last_point().is_none());
        assert!(Palc::new(
            1,
            PalcOptions {
                theta: 0.0,
                ..Default::default()
            }
        )
        .is_err());
        assert!(PalcOptions::default().with_steps(1.0, 0.1, 0.5).is_err());
        assert!(PalcOptions::default().with_event_tol(0.0).is_err());
    }
}

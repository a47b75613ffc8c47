//! Following an equilibrium path in a load parameter: the tip load
//! `F = base + lambda * direction` of a [`TargetProblem`] (its target is
//! not imposed), by fpc-newton's pseudo-arclength continuation, which
//! passes limit points (folds) where a load-controlled solve would jump or
//! fail. Every accepted point is handed to the caller with its tip and the
//! Hessian's inertia (stability at fixed load); folds are located and
//! reported with the load and the shape at the limit point.

use fpc_newton::{
    BorderedPath, Control, Direction, EventKind, Palc, PalcOptions, PathEvent, PathObserver,
    PathPoint, PathTermination,
};
use serde::Serialize;

use crate::error::{finite, InputError};

use crate::model::{ElementModel, Vector};
use crate::solve_error::SolveError;

use super::bordered::{BorderedChain, TargetProblem};
use super::options::{check_guess, SolveOptions};
use super::problem::FingerCore;
use super::solver::SolverCore;
use crate::coefficients::Coefficients;

/// An accepted point of a load path.
#[derive(Debug, Clone, Copy)]
pub struct LoadPoint<'a> {
    /// The load parameter.
    pub lambda: f64,
    /// The raw coefficients, element by element.
    pub coefficients: &'a [f64],
    /// The tip (mm, finger frame).
    pub tip: [f64; 2],
    /// Negative eigenvalues of the Hessian at fixed load (0: stable under
    /// load control).
    pub negative_eigenvalues: usize,
    /// Negative eigenvalues of the Hessian restricted to the family's
    /// target (`weights . tip` held: 0 is stable with the object holding
    /// the tip); `None` where that is not determined (singular).
    pub restricted_negative: Option<usize>,
    /// `d lambda / ds` along the path: negative after a fold.
    pub lambda_slope: f64,
}

/// A limit point of a load path: the load cannot be raised (or lowered)
/// further along the branch; under load control the finger snaps through
/// here.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Fold {
    /// The load parameter at the fold.
    pub lambda: f64,
    /// The tip at the fold (mm, finger frame).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
    /// The shape at the fold.
    #[serde(skip)]
    pub coefficients: Coefficients,
    /// Negative eigenvalues before and after.
    pub negative_before: usize,
    pub negative_after: usize,
    /// True for a fold (the load turns back); false for a possible branch
    /// point (the inertia changes while the load goes on).
    pub is_fold: bool,
}

/// How a followed path ended.
#[derive(Debug, Clone, PartialEq)]
pub struct LoadPath {
    /// Why it ended.
    pub termination: PathTermination,
    /// Folds and possible branch points met, in order.
    pub folds: Vec<Fold>,
    /// Accepted steps.
    pub steps: usize,
    /// Newton iterations of every corrector solve.
    pub iterations: usize,
    /// The last accepted state (raw coefficients) and its load.
    pub last: (Coefficients, f64),
}

/// Where a load path starts and where it may go.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LoadPathSpec {
    /// The load family (`base + lambda * direction`; the target is not
    /// imposed).
    pub problem: TargetProblem,
    /// The starting load parameter (the guess is an equilibrium there, or
    /// close to one).
    pub lambda0: f64,
    /// Follow the path towards increasing `lambda` (else decreasing).
    pub increasing: bool,
    /// End exactly at this load, if given.
    pub lambda_end: Option<f64>,
    /// The size of a typical load change (sets the arclength weight).
    pub lambda_scale: f64,
    /// Locate folds and changes of stability along the way (reported in
    /// [`LoadPath::folds`]); off, the path is only followed.
    pub events: bool,
}

/// The default continuation settings for a finger: steps in the scaled
/// unknowns (strains of order 0.01-0.1) and a load weight that makes one
/// `lambda_scale` of load count like a strain of 0.1.
fn palc_options(gtol: f64, lambda_scale: f64, events: bool) -> PalcOptions {
    PalcOptions {
        gtol,
        theta: 0.1 / lambda_scale.max(1e-12),
        initial_step: if events { 0.02 } else { PATH_FIRST_STEP },
        max_step: if events { 0.2 } else { PATH_MAX_STEP },
        grow: if events { 1.5 } else { 2.0 },
        min_step: 1e-9,
        max_steps: 20_000,
        detect_events: events,
        // where the inertia changes, steps of at most PATH_EVENT_STEP: a
        // branch passing close by is not jumped to
        event_step: PATH_EVENT_STEP,
        ..PalcOptions::default()
    }
}

/// The first and the largest step (weighted arclength) of a path followed
/// without locating events (a traced target): the corrector's contraction
/// and the tangent's turn still shorten every step that would leave the
/// branch.
const PATH_FIRST_STEP: f64 = 0.08;
const PATH_MAX_STEP: f64 = 0.4;
const PATH_EVENT_STEP: f64 = 1e-3;

struct Observer<'f, 'v, M: ElementModel> {
    finger: &'f FingerCore<M>,
    raw: Vec<f64>,
    visit: &'v mut dyn FnMut(&LoadPoint<'_>) -> bool,
    folds: Vec<Fold>,
    per: usize,
}

impl<M: ElementModel> Observer<'_, '_, M> {
    fn unscale(&mut self, y: &[f64]) {
        let n = M::Coeffs::LEN;
        for (i, s) in self.finger.unscale.iter().enumerate() {
            for j in 0..n {
                self.raw[n * i + j] = y[n * i + j] * s[j];
            }
        }
    }
}

impl<M: ElementModel> PathObserver for Observer<'_, '_, M> {
    fn point(&mut self, p: &PathPoint<'_>) -> Control {
        self.unscale(p.x);
        let tip = self.finger.tip_position(&self.raw);
        let point = LoadPoint {
            lambda: p.lambda,
            coefficients: &self.raw,
            tip,
            negative_eigenvalues: p.inertia.negative,
            restricted_negative: p.restricted.map(|i| i.negative),
            lambda_slope: p.tangent_lambda,
        };
        // a cancelled path stops at its next point ([`crate::cancel`])
        if (self.visit)(&point) && !crate::cancel::is_cancelled() {
            Control::Continue
        } else {
            Control::Stop
        }
    }

    fn event(&mut self, e: &PathEvent<'_>) {
        self.unscale(e.x);
        let tip = self.finger.tip_position(&self.raw);
        if let Ok(coefficients) = Coefficients::new(self.per, self.raw.clone()) {
            self.folds.push(Fold {
                lambda: e.lambda,
                tip,
                coefficients,
                negative_before: e.inertia_before.negative,
                negative_after: e.inertia_after.negative,
                is_fold: e.kind == EventKind::Fold,
            });
        }
    }
}

impl<M: ElementModel> SolverCore<'_, M> {
    /// Follows the equilibria of a load family ([`LoadPathSpec`]) from
    /// `guess`; `visit` sees every accepted point and ends the path by
    /// returning `false`. A cancelled path ([`crate::cancel`]) stops at
    /// its next point with [`SolveError::Cancelled`].
    pub fn follow_load(
        &mut self,
        spec: &LoadPathSpec,
        guess: &Coefficients,
        opts: &SolveOptions,
        visit: &mut dyn FnMut(&LoadPoint<'_>) -> bool,
    ) -> Result<LoadPath, SolveError> {
        crate::cancel::check()?;
        let LoadPathSpec {
            problem,
            lambda0,
            increasing,
            lambda_end,
            lambda_scale,
            events,
        } = spec;
        let (lambda0, increasing, lambda_end, lambda_scale) =
            (*lambda0, *increasing, *lambda_end, *lambda_scale);
        problem.base.validate()?;
        opts.validate_on(self.finger.len())?;
        finite(crate::Field::key("path.lambda0"), lambda0)?;
        finite(crate::Field::key("path.lambda_scale"), lambda_scale)?;
        if let Some(e) = lambda_end {
            finite(crate::Field::key("path.lambda_end"), e)?;
        }
        let f = self.finger;
        check_guess(guess, f.len(), M::Coeffs::LEN)?;
        self.load_guess(Some(guess));
        let n = self.y.len();
        let popts = palc_options(opts.rtol * f.stiffness, lambda_scale.abs(), *events);
        let mut palc = Palc::new(n, popts).map_err(|e| InputError::OutOfRange {
            field: crate::Field::key("path.lambda_scale"),
            value: lambda_scale,
            rule: e.to_string(),
        })?;
        let length: f64 = f.lengths.iter().sum();
        let bc = BorderedChain::new(&mut self.chain, *problem, f.stiffness / length);
        let mut path = BorderedPath::new(bc);
        let mut observer = Observer {
            finger: f,
            raw: vec![0.0; n],
            visit,
            folds: Vec::new(),
            per: M::Coeffs::LEN,
        };
        let direction = if increasing {
            Direction::Increasing
        } else {
            Direction::Decreasing
        };
        let start = self.y.clone();
        let report = palc.follow(
            &mut path,
            &start,
            lambda0,
            direction,
            lambda_end,
            &mut observer,
        );
        let (y, lambda) = match palc.last_point() {
            Some((y, l)) => (y.to_vec(), l),
            None => (start, lambda0),
        };
        crate::cancel::check()?;
        observer.unscale(&y);
        let last = Coefficients::new(M::Coeffs::LEN, observer.raw.clone())?;
        Ok(LoadPath {
            termination: report.termination,
            folds: observer.folds,
            steps: report.steps,
            iterations: report.corrector_iterations,
            last: (last, lambda),
        })
    }
}

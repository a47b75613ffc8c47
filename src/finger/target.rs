//! Target solves: the tip load depends on one unknown scalar `lambda`,
//! fixed by one equation on the tip position (docs/model.md section 6: the
//! unknown load joins the Newton system with the target as an extra
//! equation, solved by fpc-newton's bordered Newton).

use fpc_newton::{BorderedNewton, NewtonOptions};

use crate::error::{finite, positive, InputError};

use crate::model::{ElementModel, Vector};
use crate::solve_error::SolveError;

use super::bordered::{BorderedChain, TargetProblem};
use super::newton_policy::newton_options;
use super::options::{check_guess, Solution, SolveOptions, SolveReport, StepCounts};
use super::path::LoadPathSpec;
use super::solver::SolverCore;
use crate::coefficients::Coefficients;

/// Where a target path turns back before its target: the target cannot be
/// reached continuously from the start ([`Solver::trace_target`](super::Solver::trace_target)).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct TargetFold {
    /// The value of `weights . tip` (mm) where the path turns back: the
    /// last point the trace reached, within its step tolerance of the fold.
    #[serde(rename = "target_mm")]
    pub target: f64,
    /// The load parameter there.
    pub lambda: f64,
    /// The tip there (mm, finger frame).
    #[serde(rename = "tip_mm")]
    pub tip: [f64; 2],
}

/// A traced target path: the equilibrium at the target, or the fold that
/// stops the path short of it.
// one per trace, never stored in bulk: the solution stays unboxed
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone, PartialEq)]
pub enum Traced {
    /// The target was reached: the equilibrium, its `lambda`, and the
    /// path's accepted steps.
    Reached {
        solution: Solution,
        lambda: f64,
        steps: usize,
    },
    /// The path turns back before the target.
    Fold(TargetFold),
    /// The finger, held at the target, loses its stability on the way
    /// (the Hessian restricted to the target gets a negative eigenvalue):
    /// past this point it would snap off the path, so the target is not
    /// reached on it. The last stable point reached.
    Unstable(TargetFold),
    /// The trace spent its step budget before the target (a target
    /// approached only asymptotically, as the load grows without bound):
    /// the last point reached, as a [`TargetFold`], and the fraction of the
    /// way from the start's target to the target it covered.
    Stalled { last: TargetFold, reached: f64 },
}

/// How far along the load (N) a typical step of a traced target path
/// goes: the load's weight in the path's arclength (one of it counts like
/// a strain of 0.1), below the load's own size.
const TRACE_LAMBDA_SCALE: f64 = 1.0;

/// Accepted steps a traced target path may take before it is given up
/// (a target approached only as the load grows without bound).
const TRACE_MAX_POINTS: usize = 2000;

/// The largest load (N) a traced target path follows.
const TRACE_MAX_LAMBDA: f64 = 1e5;

/// A crossing's solve may move the state at most this fraction of the
/// bracketing step away from the interpolated start, plus
/// [`TRACE_CORRECTION_FLOOR`]: it stays on the bracketed piece of path.
const TRACE_MAX_CORRECTION: f64 = 0.5;

/// An absolute allowance (scaled unknowns, i.e. strain) on that move.
const TRACE_CORRECTION_FLOOR: f64 = 1e-9;

/// The distance in the target (mm) below which the start counts as being
/// at the target already.
const TRACE_AT_TARGET_MM: f64 = 1e-12;

impl<M: ElementModel> SolverCore<'_, M> {
    /// The bordered Newton solve of `problem` from `self.y` and `lambda`
    /// (both updated in place). Converged or not, the report says.
    fn bordered_solve(
        &mut self,
        problem: &TargetProblem,
        lambda: &mut f64,
        ctol_mm: f64,
        opts: &SolveOptions,
    ) -> Result<fpc_newton::Report, SolveError> {
        let f = self.finger;
        let length: f64 = f.lengths.iter().sum();
        let c_scale = f.stiffness / length;
        let nopts = NewtonOptions {
            ctol: ctol_mm * c_scale,
            ..newton_options(opts.rtol * f.stiffness, opts)?
        };
        let dim = self.y.len();
        self.bordered
            .get_or_insert_with(|| {
                BorderedNewton::new(dim, NewtonOptions::default())
                    .expect("the default options are valid")
            })
            .set_options(nopts)
            .map_err(|e| InputError::OutOfRange {
                field: crate::Field::key("target.ctol_mm"),
                value: ctol_mm,
                rule: e.to_string(),
            })?;
        let mut bc = BorderedChain::new(&mut self.chain, *problem, c_scale);
        let bordered = self.bordered.as_mut().expect("made above");
        Ok(bordered.solve(&mut bc, &mut self.y, lambda))
    }

    /// The finished solution of a converged [`Self::bordered_solve`] of
    /// `problem` at `lambda`: with `opts.stability`, the inertia of the
    /// Hessian restricted to the target constraint.
    fn finish_target(
        &mut self,
        problem: &TargetProblem,
        lambda: f64,
        r: &fpc_newton::Report,
        opts: &SolveOptions,
    ) -> Result<Solution, SolveError> {
        let f = self.finger;
        let length: f64 = f.lengths.iter().sum();
        // the target holds the tip: stability is that of the energy on the
        // constraint, the inertia of H restricted to c_x . v = 0 (None when
        // H is singular there, so the count is not known)
        let restricted = if opts.stability {
            let mut bc = BorderedChain::new(&mut self.chain, *problem, f.stiffness / length);
            let bordered = self.bordered.as_mut().expect("made by the solve");
            bordered.last_restricted_inertia(&mut bc).ok()
        } else {
            None
        };
        let report = SolveReport {
            reason: r.reason,
            iterations: r.iterations,
            residual_norm: r.residual_norm / f.stiffness,
            evaluations: r.hessian_evals,
            coupled: true,
            continuation_steps: 0,
            steps: StepCounts {
                coupled: r.iterations,
                ..StepCounts::default()
            },
        };
        let load = problem.load_at(lambda);
        let unconstrained = SolveOptions {
            stability: false,
            ..*opts
        };
        let mut sol = self.finish(&load, &unconstrained, report, false)?;
        if opts.stability {
            sol.negative_eigenvalues = restricted.map(|i| i.negative);
            sol.stable = sol.negative_eigenvalues.map(|k| k == 0);
        }
        Ok(sol)
    }

    /// Checks the inputs of a target solve or trace before any work.
    fn check_target_start(
        &self,
        problem: &TargetProblem,
        start: &Coefficients,
        lambda0: f64,
        ctol_mm: f64,
        opts: &SolveOptions,
    ) -> Result<(), SolveError> {
        crate::cancel::check()?;
        problem.validate()?;
        opts.validate()?;
        finite(crate::Field::key("target.lambda0"), lambda0)?;
        positive(crate::Field::key("target.ctol_mm"), ctol_mm)?;
        check_guess(start, self.finger.len(), M::Coeffs::LEN)?;
        Ok(())
    }

    /// Solves a [`TargetProblem`] from `guess` and a starting `lambda`.
    /// With `opts.stability`, the solution's `negative_eigenvalues` counts
    /// those of the Hessian restricted to the target constraint (the
    /// object holds the tip), `None` where the Hessian is singular.
    pub fn solve_target(
        &mut self,
        problem: &TargetProblem,
        guess: &Coefficients,
        lambda0: f64,
        ctol_mm: f64,
        opts: &SolveOptions,
    ) -> Result<(Solution, f64), SolveError> {
        self.check_target_start(problem, guess, lambda0, ctol_mm, opts)?;
        self.load_guess(Some(guess));
        let mut lambda = lambda0;
        let r = self.bordered_solve(problem, &mut lambda, ctol_mm, opts)?;
        if !r.reason.is_converged() || !lambda.is_finite() {
            return Err(self.not_converged(&r, None));
        }
        let sol = self.finish_target(problem, lambda, &r, opts)?;
        Ok((sol, lambda))
    }

    /// Traces the solutions of `problem`'s load family from `start` (an
    /// equilibrium of the family at `lambda0`) until its target value
    /// `weights . tip` reaches `problem.target`, as when a gripper closes
    /// on an object: the family's equilibrium path is followed from the
    /// start by pseudo-arclength continuation in the load (fpc-newton's
    /// Palc, which passes limit points in the load and rejects steps that
    /// would jump to another branch), in the direction that moves the
    /// target towards its value. The first crossing of the target is
    /// solved exactly by a bordered Newton solve started on the bracketing
    /// step. Where the target turns back before its value (a fold in the
    /// target: the object cannot be closed on further on this path) the
    /// trace ends with [`Traced::Fold`] at the last point before the turn;
    /// a path that goes on without reaching it within [`TRACE_MAX_POINTS`]
    /// steps or [`TRACE_MAX_LAMBDA`] of load ends with [`Traced::Stalled`].
    /// So an answer is the equilibrium reached continuously from the
    /// start, never one of another branch.
    pub fn trace_target(
        &mut self,
        problem: &TargetProblem,
        start: &Coefficients,
        lambda0: f64,
        ctol_mm: f64,
        opts: &SolveOptions,
    ) -> Result<Traced, SolveError> {
        self.check_target_start(problem, start, lambda0, ctol_mm, opts)?;
        let f = self.finger;
        let w = problem.weights;
        let target_of = |tip: [f64; 2]| w[0] * tip[0] + w[1] * tip[1];
        let (t0, t1) = (target_of(f.tip_position(start.as_slice())), problem.target);
        let at = |t: f64| TargetProblem {
            target: t,
            ..*problem
        };
        let tip_opts = opts.tip_only();
        let towards = (t1 - t0).signum();
        let mut iterations = 0;
        if (t1 - t0).abs() > TRACE_AT_TARGET_MM {
            // which way the load moves the target at the start (singular
            // there: try the load's own direction)
            let dt_dlambda = self.target_slope_at(problem, start, lambda0).unwrap_or(0.0);
            let first = dt_dlambda * towards >= 0.0;
            let mut crossing = None;
            for increasing in [first, !first] {
                let spec = LoadPathSpec {
                    problem: *problem,
                    lambda0,
                    increasing,
                    lambda_end: None,
                    lambda_scale: lambda0.abs().max(TRACE_LAMBDA_SCALE),
                    events: false,
                };
                let mut prev: (Vec<f64>, f64, f64) = (start.as_slice().to_vec(), lambda0, t0);
                let mut end = End::Open;
                let mut points = 0;
                let path = self.follow_load(&spec, start, &tip_opts, &mut |pt| {
                    points += 1;
                    let t = target_of(pt.tip);
                    if (t - t1) * towards >= 0.0 {
                        end = End::Crossed {
                            before: std::mem::take(&mut prev),
                            after: (pt.coefficients.to_vec(), pt.lambda, t),
                        };
                        return false;
                    }
                    if (t - prev.2) * towards < 0.0 {
                        end = End::Turned { points };
                        return false;
                    }
                    // the object holding the tip, the finger must stay
                    // stable on the way: past a loss of stability it
                    // would snap off this branch
                    if pt.restricted_negative.is_some_and(|k| k > 0) {
                        end = End::Unstable;
                        return false;
                    }
                    prev = (pt.coefficients.to_vec(), pt.lambda, t);
                    if points >= TRACE_MAX_POINTS || pt.lambda.abs() > TRACE_MAX_LAMBDA {
                        end = End::Budget;
                        return false;
                    }
                    true
                })?;
                iterations += path.iterations;
                let last = |prev: &(Vec<f64>, f64, f64)| TargetFold {
                    target: prev.2,
                    lambda: prev.1,
                    tip: f.tip_position(&prev.0),
                };
                match end {
                    End::Crossed { before, after } => {
                        crossing = Some((before, after));
                        break;
                    }
                    // the target moves the wrong way from the very start
                    // in this direction (the start is at a limit of the
                    // target): the other direction
                    End::Turned { points: 1 } if increasing == first => continue,
                    End::Turned { .. } => return Ok(Traced::Fold(last(&prev))),
                    End::Unstable => return Ok(Traced::Unstable(last(&prev))),
                    End::Budget | End::Open => {
                        return Ok(Traced::Stalled {
                            last: last(&prev),
                            reached: (prev.2 - t0) / (t1 - t0),
                        })
                    }
                }
            }
            let Some((before, after)) = crossing else {
                return Ok(Traced::Fold(TargetFold {
                    target: t0,
                    lambda: lambda0,
                    tip: f.tip_position(start.as_slice()),
                }));
            };
            // the crossing: a bordered solve from the linear interpolation
            // of the bracketing points, which must stay on that piece
            let q = ((t1 - before.2) / (after.2 - before.2)).clamp(0.0, 1.0);
            let guess: Vec<f64> = before
                .0
                .iter()
                .zip(&after.0)
                .map(|(a, b)| a + q * (b - a))
                .collect();
            let guess = Coefficients::new(M::Coeffs::LEN, guess)?;
            let scaled = |k: &[f64]| f.scaled(k);
            let (yb, ya, yg) = (
                scaled(&before.0),
                scaled(&after.0),
                scaled(guess.as_slice()),
            );
            self.load_guess(Some(&guess));
            let mut lambda = before.1 + q * (after.1 - before.1);
            let r = self.bordered_solve(&at(t1), &mut lambda, ctol_mm, opts)?;
            iterations += r.iterations;
            let stayed = dist(&self.y, &yg)
                <= TRACE_MAX_CORRECTION * dist(&ya, &yb) + TRACE_CORRECTION_FLOOR;
            if !(r.reason.is_converged() && lambda.is_finite() && stayed) {
                return Err(self.not_converged(&r, None));
            }
            let mut solution = self.finish_target(&at(t1), lambda, &r, opts)?;
            solution.report.iterations += iterations;
            solution.report.steps.continuation += iterations;
            return Ok(Traced::Reached {
                solution,
                lambda,
                steps: 1,
            });
        }
        // already at the target: the start, finished
        self.load_guess(Some(start));
        let mut lambda = lambda0;
        let r = self.bordered_solve(&at(t1), &mut lambda, ctol_mm, opts)?;
        if !r.reason.is_converged() || !lambda.is_finite() {
            return Err(self.not_converged(&r, None));
        }
        let solution = self.finish_target(&at(t1), lambda, &r, opts)?;
        Ok(Traced::Reached {
            solution,
            lambda,
            steps: 0,
        })
    }

    /// The rate `dT / dlambda` at which `problem`'s load family moves its
    /// target `weights . tip` at `start` (an equilibrium of the family at
    /// `lambda0`), from the bordered tangent there; `None` where the
    /// tangent is singular. A trace from `start` follows the load in the
    /// direction this says moves the target towards its value.
    pub fn target_slope_at(
        &mut self,
        problem: &TargetProblem,
        start: &Coefficients,
        lambda0: f64,
    ) -> Option<f64> {
        let f = self.finger;
        let w = problem.weights;
        let tip = f.tip_position(start.as_slice());
        let at_start = TargetProblem {
            target: w[0] * tip[0] + w[1] * tip[1],
            ..*problem
        };
        let c_scale = f.stiffness / f.lengths.iter().sum::<f64>();
        self.load_guess(Some(start));
        let mut dy = vec![0.0; self.y.len()];
        self.bordered_solver();
        let mut bc = BorderedChain::new(&mut self.chain, at_start, c_scale);
        let bordered = self.bordered.as_mut().expect("made above");
        let t = bordered
            .target_tangent(&mut bc, &self.y, lambda0, &mut dy)
            .ok()?;
        Some(1.0 / t.dlambda)
    }

    /// Makes the bordered solver on first use.
    fn bordered_solver(&mut self) {
        let dim = self.y.len();
        self.bordered.get_or_insert_with(|| {
            BorderedNewton::new(dim, NewtonOptions::default())
                .expect("the default options are valid")
        });
    }
}

/// How a traced target path ended.
enum End {
    /// Still going (the path itself ended: a numerical end).
    Open,
    /// The target was crossed between these points (raw coefficients,
    /// load, target).
    Crossed {
        before: (Vec<f64>, f64, f64),
        after: (Vec<f64>, f64, f64),
    },
    /// The target turned back at the path's `points`-th point.
    Turned { points: usize },
    /// The finger held at the target lost its stability.
    Unstable,
    /// The step or load budget ran out.
    Budget,
}

/// The Euclidean distance of two states.
fn dist(a: &[f64], b: &[f64]) -> f64 {
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y) * (x - y))
        .sum::<f64>()
        .sqrt()
}

//! Natural-parameter continuation with adaptive steps and a secant predictor.

use crate::options::ContinuationOptions;
use crate::report::{Report, Termination};

/// Outcome of [`continuation`].
#[derive(Clone, Debug, PartialEq)]
pub struct ContinuationReport {
    /// Parameter value of the last accepted state (`from` if none was accepted).
    pub reached: f64,
    /// Number of accepted steps.
    pub steps: usize,
    /// Number of rejected (failed) solves.
    pub rejected: usize,
    /// Sum of `iterations` over every solve, accepted or rejected.
    pub newton_iterations: usize,
    /// Report of the last solve attempted (an `InvalidInput` report if the
    /// driver refused to start).
    pub last: Report,
    /// True when the state at `to` was accepted.
    pub complete: bool,
}

/// Follows the solution of a parametrised problem from parameter `from` to
/// `to` (either direction).
///
/// `x` on entry is taken as the accepted state at `from` (solve there first
/// if it is only a guess); on return it holds the last accepted state, at
/// parameter `reached`. Each step calls `solve_at(t, x)`, which must
/// warm-start a solve at parameter `t` from the `x` it is given, leave its
/// result in `x`, and return its [`Report`]; a step is accepted when the
/// report says [`converged`](Report::converged). Every call makes at least
/// one solve (with `from == to`, a single solve at `to`).
///
/// Step control (absolute steps in parameter units): the first step is
/// `initial_step`; after an accepted solve that needed at most
/// `easy_iterations` iterations the step is multiplied by `grow` (capped at
/// `max_step`); after a failed solve `x` is restored to the last accepted
/// state and the step multiplied by `shrink`. The driver stops incomplete
/// when the step would fall below `min_step` or after `max_steps` solve
/// attempts (accepted + rejected). The last step is shortened to land
/// exactly on `to`.
///
/// Predictor (with `predictor = true`): once two states are accepted, the
/// start of the solve at `t` is the secant (linear) extrapolation
/// `x_1 + (t - t_1) / (t_1 - t_0) (x_1 - x_0)` through the last two accepted
/// states `(t_0, x_0)`, `(t_1, x_1)`; before that (and with `predictor =
/// false`) it is the last accepted state itself. A non-finite prediction
/// falls back to the last accepted state.
///
/// Allocates two state vectors once per call, nothing per step. Invalid
/// options or a non-finite `from`/`to` return at once (incomplete, `last`
/// = an `InvalidInput` report) without calling `solve_at`.
pub fn continuation<F: FnMut(f64, &mut [f64]) -> Report>(
    from: f64,
    to: f64,
    x: &mut [f64],
    opts: &ContinuationOptions,
    mut solve_at: F,
) -> ContinuationReport {
    let mut rep = ContinuationReport {
        reached: from,
        steps: 0,
        rejected: 0,
        newton_iterations: 0,
        last: Report::empty(Termination::InvalidInput),
        complete: false,
    };
    if opts.validate().is_err() || !from.is_finite() || !to.is_finite() {
        return rep;
    }
    let n = x.len();
    let dir = if to >= from { 1.0 } else { -1.0 };
    // Last accepted state (x1 at t1) and the one before (x0 at t0).
    let mut x1 = x.to_vec();
    let mut t1 = from;
    let mut x0 = vec![0.0; n];
    let mut t0 = f64::NAN;
    let mut have_two = false;
    let mut step = opts.initial_step;
    let mut attempts = 0usize;

    loop {
        if attempts >= opts.max_steps {
            break;
        }
        let remaining = (to - t1).abs();
        // Land exactly on `to` when within the step (or a hair beyond it).
        let t = if remaining <= step * (1.0 + 1e-12) {
            to
        } else {
            t1 + dir * step
        };

        // Predictor.
        let mut predicted = false;
        if opts.predictor && have_two {
            let r = (t - t1) / (t1 - t0);
            if r.is_finite() {
                for i in 0..n {
                    x[i] = x1[i] + r * (x1[i] - x0[i]);
                }
                predicted = x.iter().all(|v| v.is_finite());
            }
        }
        if !predicted {
            x.copy_from_slice(&x1);
        }

        let r = solve_at(t, x);
        attempts += 1;
        rep.newton_iterations += r.iterations;
        let ok = r.converged() && x.iter().all(|v| v.is_finite());
        let easy = r.iterations <= opts.easy_iterations;
        rep.last = r;
        if ok {
            core::mem::swap(&mut x0, &mut x1);
            x1.copy_from_slice(x);
            t0 = t1;
            t1 = t;
            have_two = t0 != t1;
            rep.steps += 1;
            rep.reached = t;
            if t == to {
                rep.complete = true;
                break;
            }
            if easy {
                step = (step * opts.grow).min(opts.max_step);
            }
        } else {
            x.copy_from_slice(&x1);
            rep.rejected += 1;
            step *= opts.shrink;
            if step < opts.min_step {
                break;
            }
        }
    }
    x.copy_from_slice(&x1);
    rep
}

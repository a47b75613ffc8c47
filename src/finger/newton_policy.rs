//! How Newton is run on a finger: its options from [`SolveOptions`], the
//! flags of a one-element or a chain solve, the fixed-cap path a failed
//! solve takes again, and Newton in straightened unknowns from a cold
//! start.

use fpc_newton::{Hessian, Newton, NewtonOptions, Report};

use crate::error::InputError;
use crate::model::ElementModel;

use super::chain::Chain;
use super::options::SolveOptions;
use super::straighten;

pub(crate) fn newton_options(gtol: f64, opts: &SolveOptions) -> Result<NewtonOptions, InputError> {
    let nopts = NewtonOptions {
        gtol,
        max_iter: opts.max_iter,
        max_step: opts.max_step,
        ..NewtonOptions::default()
    };
    nopts.validate().map_err(|e| InputError::OutOfRange {
        field: crate::Field::Solve,
        value: gtol,
        rule: e.to_string(),
    })?;
    Ok(nopts)
}
/// `opts` for a solve of one element (`single`) or a chain: the step cap
/// grows as a trust region's radius (fpc-newton's `step_growth`), and a
/// step along an indefinite Hessian taken whole is doubled while the
/// energy keeps falling (`extend_modified`; for a chain only with
/// `double_shifted`, the solver's default); for one element the negative
/// curvature is flipped (`modified_pivots`). Along a chain a flipped pivot
/// is a Schur complement's and can carry the finger into another basin
/// (docs/stress.md "Where the iterations go"), so a chain keeps the
/// shifted Hessian.
pub(crate) fn newton_flags(
    opts: NewtonOptions,
    single: bool,
    double_shifted: bool,
) -> NewtonOptions {
    NewtonOptions {
        modified_pivots: single,
        extend_modified: single || double_shifted,
        step_growth: true,
        ..opts
    }
}

/// `opts` along shifted Hessians with the fixed step cap: the path a
/// failed solve with growing or flipped steps takes again.
pub(crate) fn fixed_cap(opts: NewtonOptions) -> NewtonOptions {
    NewtonOptions {
        modified_pivots: false,
        extend_modified: false,
        step_growth: false,
        ..opts
    }
}

/// Where a one-element solve with modified pivots failed (its steps can
/// leap where the energy falls without bound, and miss an equilibrium
/// that the shifted path crawls to): switches `newton` to the shifted
/// path, for the caller to solve again from the same start, and returns
/// the options to restore; `None` where they were not on.
pub(crate) fn shifted_instead(newton: &mut Newton) -> Option<NewtonOptions> {
    let current = *newton.options();
    if !current.modified_pivots {
        return None;
    }
    // the same validated options with flags off: cannot fail
    let _ = newton.set_options(fixed_cap(current));
    Some(current)
}

/// Chord steps of a straightened solve go on to this fraction of `gtol`
/// (`NewtonOptions::chord_depth`): in the straightened unknowns more of a
/// solve's last steps are chord steps, and stopping them just under the
/// tolerance left a finger's tip up to 3e-6 mm off at N = 8, against
/// 1e-8 mm with them (docs/stress.md).
const STRAIGHT_CHORD_DEPTH: f64 = 1e-2;

/// Newton from a cold start in its own unknowns (src/finger/straighten.rs)
/// on a problem whose `straight` flag `set` switches; from a warm start
/// (`warm`: the caller's guess, already near the answer, where the valley
/// does not slow Newton) in the scaled unknowns, which costs less there.
/// `y` holds scaled unknowns before and after.
pub(crate) fn minimize_straight<M: ElementModel, P: Hessian + ?Sized>(
    newton: &mut Newton,
    p: &mut P,
    set: fn(&mut P, bool),
    y: &mut [f64],
    warm: bool,
) -> Report {
    if warm || M::STRAIGHTEN.is_empty() || !straighten::representable::<M>(y) {
        // (or a start so far out that the change overflows: Newton in the
        // scaled unknowns reports what it finds there)
        return newton.minimize(p, y);
    }
    let plain = *newton.options();
    // a depth in (0, 1] on validated options: cannot fail
    let _ = newton.set_options(NewtonOptions {
        chord_depth: STRAIGHT_CHORD_DEPTH,
        ..plain
    });
    straighten::to_newton::<M>(y);
    set(p, true);
    let r = newton.minimize(p, y);
    set(p, false);
    straighten::from_newton::<M>(y);
    let _ = newton.set_options(plain);
    r
}

pub(crate) fn chain_straight<M: ElementModel>(c: &mut Chain<'_, M>, on: bool) {
    c.straight = on;
}

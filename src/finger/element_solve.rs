//! One element solved alone (the decoupled scenes, without a tip load):
//! the element's problem in scaled unknowns, its Newton workspace, and the
//! solve with its retries and pressure continuation.

use fpc_newton::{
    Energy, FactorError, Gradient, Hessian, Inertia, LinearSystem, Newton, NewtonOptions,
    PivotKind, Report, Semiseparable, Termination,
};

use crate::model::{ElementModel, EnergyScalars, Vector};

use super::newton_policy::{minimize_straight, newton_flags};
use super::options::SolveReport;
use super::problem::FingerCore;
use super::straighten;

/// One element's Newton workspace and Hessian (decoupled solves).
pub(crate) struct Local {
    pub newton: Newton,
    pub matrix: Semiseparable,
}

/// The decoupled solves' workspace in `slot`, made on first use, with the
/// coupled solver's options.
pub(crate) fn local_workspace<'s, M: ElementModel>(
    slot: &'s mut Option<Local>,
    coupled: &Newton,
) -> &'s mut Local {
    let local = slot.get_or_insert_with(|| Local {
        newton: Newton::new(M::Coeffs::LEN, NewtonOptions::default()),
        matrix: Semiseparable::new(M::Coeffs::LEN, 1),
    });
    // the options were validated for the coupled solver: this cannot fail
    let _ = local
        .newton
        .set_options(newton_flags(*coupled.options(), true, true));
    local
}

/// Minimises one element's energy from `y` (the decoupled scenes). When
/// that fails: again from the straight element if `y` was a warm start,
/// then, with `continuation` and a pressure, by pressure continuation from
/// the straight element at zero pressure to the target (warm-starting each
/// step). Adds iterations, evaluations and continuation steps to `rep`;
/// returns the last report, its `iterations` counting every attempt.
pub(crate) fn solve_element<M: ElementModel>(
    newton: &mut Newton,
    p: &mut Single<'_, M>,
    y: &mut [f64],
    warm: bool,
    continuation: bool,
    rep: &mut SolveReport,
) -> Report {
    let before = rep.iterations;
    let tally = |r: &Report, rep: &mut SolveReport| {
        rep.iterations += r.iterations;
        rep.steps.element += r.iterations;
        rep.steps.globalisation(r);
        rep.evaluations += r.energy_evals + r.gradient_evals + r.hessian_evals;
    };
    let mut r = minimize_straight::<M, _>(newton, p, single_straight, y, warm);
    tally(&r, rep);
    if !r.reason.is_converged() && warm {
        y.fill(0.0);
        r = minimize_straight::<M, _>(newton, p, single_straight, y, false);
        tally(&r, rep);
    }
    let full = p.scalars;
    if !r.reason.is_converged() && continuation && full.kp != 0.0 {
        y.fill(0.0);
        p.scalars = EnergyScalars { kp: 0.0 };
        r = minimize_straight::<M, _>(newton, p, single_straight, y, false);
        tally(&r, rep);
        if r.reason.is_converged() {
            let copts = fpc_newton::ContinuationOptions::default();
            let cr = fpc_newton::continuation(0.0, 1.0, y, &copts, |t, y| {
                p.scalars = EnergyScalars { kp: t * full.kp };
                let r = minimize_straight::<M, _>(newton, p, single_straight, y, false);
                tally(&r, rep);
                r
            });
            rep.continuation_steps += cr.steps;
            r = cr.last;
            if !cr.complete && r.reason.is_converged() {
                r.reason = Termination::MaxIterations;
            }
        }
        p.scalars = full;
    }
    r.iterations = rep.iterations - before;
    r
}

fn single_straight<M: ElementModel>(p: &mut Single<'_, M>, on: bool) {
    p.straight = on;
}

/// One element in scaled unknowns (the decoupled scenes).
pub(crate) struct Single<'a, M: ElementModel> {
    finger: &'a FingerCore<M>,
    element: usize,
    scalars: EnergyScalars,
    pub matrix: &'a mut Semiseparable,
    /// In Newton's own unknowns, as [`Chain::straight`].
    straight: bool,
}

impl<'a, M: ElementModel> Single<'a, M> {
    pub fn new(
        finger: &'a FingerCore<M>,
        element: usize,
        scalars: EnergyScalars,
        matrix: &'a mut Semiseparable,
    ) -> Single<'a, M> {
        Single {
            finger,
            element,
            scalars,
            matrix,
            straight: false,
        }
    }

    /// The raw unknowns at Newton's `y` (straightened, scaled).
    fn raw(&self, y: &[f64]) -> M::Coeffs {
        let s = &self.finger.unscale[self.element];
        let mut x = M::Coeffs::from_fn(|i| y[i]);
        if self.straight {
            straighten::from_newton::<M>(x.as_mut());
        }
        M::Coeffs::from_fn(|i| x[i] * s[i])
    }
}

impl<M: ElementModel> Energy for Single<'_, M> {
    fn dim(&self) -> usize {
        M::Coeffs::LEN
    }
    fn energy(&mut self, y: &[f64]) -> f64 {
        self.finger.elements[self.element].energy(&self.raw(y), &self.scalars)
    }
}

impl<M: ElementModel> Gradient for Single<'_, M> {
    fn gradient(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        let (v, gk) = self.finger.elements[self.element].gradient(&self.raw(y), &self.scalars);
        let s = &self.finger.unscale[self.element];
        for i in 0..M::Coeffs::LEN {
            g[i] = gk[i] * s[i];
        }
        if self.straight {
            straighten::pull_back::<M, f64>(y, g);
        }
        v
    }
}

impl<M: ElementModel> Hessian for Single<'_, M> {
    fn hessian(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        let (v, gk, hk) = self.finger.elements[self.element].hessian(&self.raw(y), &self.scalars);
        let s = self.finger.unscale[self.element];
        let n = M::Coeffs::LEN;
        let straight = self.straight;
        for i in 0..n {
            g[i] = gk[i] * s[i];
        }
        self.matrix.fill_block(0, |h| {
            straighten::newton_block::<M, f64>(hk.as_ref(), s.as_ref(), y, g, straight, h);
        });
        if straight {
            straighten::pull_back::<M, f64>(y, g);
        }
        v
    }
}

impl<M: ElementModel> LinearSystem for Single<'_, M> {
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

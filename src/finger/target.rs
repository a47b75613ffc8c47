//! Target solves: the tip load depends on one unknown scalar `lambda`,
//! fixed by one equation on the tip position (docs/model.md section 6: the
//! unknown load joins the Newton system with the target as an extra
//! equation, solved by fpc-newton's bordered Newton).

use fpc_newton::{
    Bordered, BorderedEval, BorderedNewton, FactorError, Hessian, Inertia, LinearSystem,
    NewtonOptions, PivotKind,
};

use crate::error::{finite, positive, InputError, SolveError};
use crate::model::{ElementModel, Vector};

use super::chain::Chain;
use super::solver::{newton_options, SolverCore};
use super::{check_guess, Coefficients, Load, Solution, SolveOptions, SolveReport};

/// A scene whose tip load depends on one unknown scalar `lambda`,
/// `F = base + lambda * direction`, fixed by one target on the tip position:
/// `weights . tip = target` at equilibrium.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct TargetProblem {
    /// Pressure, kappa and the fixed part of the tip load.
    pub base: Load,
    /// Tip-load change per unit `lambda` (N, finger frame).
    pub direction: [f64; 2],
    /// Weights of the tip coordinates (X, Z) in the target.
    pub weights: [f64; 2],
    /// Target value of `weights . tip` (mm).
    pub target: f64,
}

impl TargetProblem {
    /// The load at a given `lambda`.
    pub fn load_at(&self, lambda: f64) -> Load {
        Load {
            fx: self.base.fx + lambda * self.direction[0],
            fz: self.base.fz + lambda * self.direction[1],
            ..self.base
        }
    }

    /// The straight homotopy between two problems at `t` in [0, 1].
    pub fn lerp(&self, to: &TargetProblem, t: f64) -> TargetProblem {
        let m = |a: f64, b: f64| a + t * (b - a);
        TargetProblem {
            base: Load {
                pressure: m(self.base.pressure, to.base.pressure),
                kappa: m(self.base.kappa, to.base.kappa),
                fx: m(self.base.fx, to.base.fx),
                fz: m(self.base.fz, to.base.fz),
            },
            direction: [
                m(self.direction[0], to.direction[0]),
                m(self.direction[1], to.direction[1]),
            ],
            weights: [
                m(self.weights[0], to.weights[0]),
                m(self.weights[1], to.weights[1]),
            ],
            target: m(self.target, to.target),
        }
    }

    pub(crate) fn validate(&self) -> Result<(), InputError> {
        self.base.validate()?;
        finite("target.direction[0]", self.direction[0])?;
        finite("target.direction[1]", self.direction[1])?;
        finite("target.weights[0]", self.weights[0])?;
        finite("target.weights[1]", self.weights[1])?;
        finite("target.value", self.target)?;
        if self.direction == [0.0, 0.0] || self.weights == [0.0, 0.0] {
            return Err(InputError::Inconsistent {
                field: "target".into(),
                rule: "the load direction and the target weights must not be zero".into(),
            });
        }
        Ok(())
    }
}

/// The chain under the load `problem.load_at(lambda)`, with the target
/// equation, as fpc-newton's bordered problem (and, through
/// `BorderedPath`, as a path in `lambda`).
pub(crate) struct BorderedChain<'c, 'a, M: ElementModel> {
    chain: &'c mut Chain<'a, M>,
    problem: TargetProblem,
    scratch: Vec<f64>,
    /// Stiffness scale over the finger length: weighs a tip error (mm) like
    /// the strain error it implies.
    c_scale: f64,
}

impl<'c, 'a, M: ElementModel> BorderedChain<'c, 'a, M> {
    pub(crate) fn new(
        chain: &'c mut Chain<'a, M>,
        problem: TargetProblem,
        c_scale: f64,
    ) -> BorderedChain<'c, 'a, M> {
        let n = fpc_newton::Energy::dim(&*chain);
        BorderedChain {
            chain,
            problem,
            scratch: vec![0.0; n],
            c_scale,
        }
    }
}

impl<M: ElementModel> Bordered for BorderedChain<'_, '_, M> {
    fn dim(&self) -> usize {
        fpc_newton::Energy::dim(&*self.chain)
    }

    fn eval(&mut self, y: &[f64], lambda: f64, out: &mut BorderedEval) -> bool {
        let load = self.problem.load_at(lambda);
        self.chain.set_load(&load);
        self.chain.force_chain = true;
        let v = self.chain.hessian(y, &mut out.g);
        self.chain
            .tip_gradient_scaled(self.problem.direction, &mut self.scratch);
        for (gl, t) in out.g_lambda.iter_mut().zip(&self.scratch) {
            *gl = -t;
        }
        self.chain
            .tip_gradient_scaled(self.problem.weights, &mut out.c_x);
        // the target equation in force units (mm times stiffness per length),
        // so the merit weighs a tip error like the strain error it implies
        let cs = self.c_scale;
        for cx in out.c_x.iter_mut() {
            *cx *= cs;
        }
        let w = self.problem.weights;
        out.c = cs * (w[0] * self.chain.tip[0] + w[1] * self.chain.tip[1] - self.problem.target);
        out.c_lambda = 0.0;
        self.chain.force_chain = false;
        v.is_finite() && out.is_finite()
    }
}

impl<M: ElementModel> LinearSystem for BorderedChain<'_, '_, M> {
    fn diagonal_range(&self) -> (f64, f64) {
        self.chain.diagonal_range()
    }
    fn factor(&mut self, tau: f64, kind: PivotKind) -> Result<Inertia, FactorError> {
        self.chain.factor(tau, kind)
    }
    fn solve(&mut self, b: &mut [f64]) {
        self.chain.solve(b)
    }
    fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.chain.apply(x, out)
    }
}

impl<M: ElementModel> SolverCore<'_, M> {
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
        problem.validate()?;
        opts.validate()?;
        finite("target.lambda0", lambda0)?;
        positive("target.ctol_mm", ctol_mm)?;
        let f = self.finger;
        check_guess(guess, f.len(), M::Coeffs::LEN)?;
        self.load_guess(Some(guess));
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
                field: "target.ctol_mm".into(),
                value: ctol_mm,
                rule: e.to_string(),
            })?;
        let mut lambda = lambda0;
        let mut bc = BorderedChain::new(&mut self.chain, *problem, c_scale);
        let bordered = self.bordered.as_mut().expect("made above");
        let r = bordered.solve(&mut bc, &mut self.y, &mut lambda);
        if !r.reason.is_converged() || !lambda.is_finite() {
            return Err(self.not_converged(&r, None));
        }
        // the target holds the tip: stability is that of the energy on the
        // constraint, the inertia of H restricted to c_x . v = 0 (None when
        // H is singular there, so the count is not known)
        let restricted = opts
            .stability
            .then(|| {
                let bordered = self.bordered.as_mut().expect("made above");
                bordered.last_restricted_inertia(&mut bc).ok()
            })
            .flatten();
        let report = SolveReport {
            reason: r.reason,
            iterations: r.iterations,
            residual_norm: r.residual_norm / f.stiffness,
            evaluations: r.hessian_evals,
            coupled: true,
            continuation_steps: 0,
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
        Ok((sol, lambda))
    }
}

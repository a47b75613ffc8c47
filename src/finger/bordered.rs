//! A finger whose tip load carries one unknown scalar fixed by one target
//! on the tip position: the problem ([`TargetProblem`]) and the bordered
//! Newton system it adds to the chain ([`BorderedChain`]).

use fpc_newton::{Bordered, BorderedEval, FactorError, Hessian, Inertia, LinearSystem, PivotKind};

use crate::error::{finite, InputError};
use crate::model::ElementModel;

use super::chain::Chain;
use super::load::Load;

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

    pub(crate) fn validate(&self) -> Result<(), InputError> {
        self.base.validate()?;
        finite(crate::Field::key("target.direction[0]"), self.direction[0])?;
        finite(crate::Field::key("target.direction[1]"), self.direction[1])?;
        finite(crate::Field::key("target.weights[0]"), self.weights[0])?;
        finite(crate::Field::key("target.weights[1]"), self.weights[1])?;
        finite(crate::Field::key("target.value"), self.target)?;
        if self.direction == [0.0, 0.0] || self.weights == [0.0, 0.0] {
            return Err(InputError::Inconsistent {
                field: crate::Field::key("target"),
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

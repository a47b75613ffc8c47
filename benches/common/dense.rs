//! The dense reference path for a finger's Newton problem: the structured
//! Hessian expanded into a dense `n x n` matrix column by column (`H e_j`
//! through [`LinearSystem::apply`], `O(N^2)` storage and work) and
//! factorised densely by fpc-newton's [`Dense`] adapter (`O(N^3)`). This
//! is the solve the finger used before the structured factorisation, kept
//! for tests (agreement) and benches (speed ratios). Shared by
//! benches/scaling.rs and tests/structured.rs through `#[path]`.

#![allow(dead_code)]

use fpc::finger::Problem;
use fpc::{Finger, Load};
use fpc_newton::{
    Dense, DenseHessian, Energy, Gradient, Hessian, LinearSystem, Newton, NewtonOptions, Report,
};

/// A finger problem that writes its Hessian densely.
pub struct DenseFinger<'a> {
    problem: Problem<'a>,
    unit: Vec<f64>,
}

impl<'a> DenseFinger<'a> {
    /// The dense form of `finger.problem(load)`.
    pub fn new(finger: &'a Finger, load: &Load) -> DenseFinger<'a> {
        let problem = finger.problem(load);
        let n = problem.dim();
        DenseFinger {
            problem,
            unit: vec![0.0; n],
        }
    }
}

impl Energy for DenseFinger<'_> {
    fn dim(&self) -> usize {
        self.problem.dim()
    }
    fn energy(&mut self, x: &[f64]) -> f64 {
        self.problem.energy(x)
    }
}

impl Gradient for DenseFinger<'_> {
    fn gradient(&mut self, x: &[f64], g: &mut [f64]) -> f64 {
        self.problem.gradient(x, g)
    }
}

impl DenseHessian for DenseFinger<'_> {
    fn hessian(&mut self, x: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let v = self.problem.hessian(x, g);
        let n = self.unit.len();
        for j in 0..n {
            self.unit[j] = 1.0;
            self.problem.apply(&self.unit, &mut h[j * n..(j + 1) * n]);
            self.unit[j] = 0.0;
        }
        v
    }
}

/// The Newton options the finger's solver uses for relative residual
/// `rtol` (the gradient tolerance scaled by the finger's stiffness).
pub fn newton_options(finger: &Finger, rtol: f64) -> NewtonOptions {
    NewtonOptions {
        gtol: rtol * finger.stiffness_scale(),
        ..NewtonOptions::default()
    }
}

/// Scaled unknowns of raw coefficients `k` (the solver's variables).
pub fn scaled(finger: &Finger, k: &[f64]) -> Vec<f64> {
    let s = finger.unknown_scales();
    k.iter().zip(s.iter().cycle()).map(|(k, s)| k / s).collect()
}

/// Newton on the structured problem from scaled `x`; returns the report.
pub fn solve_structured(
    finger: &Finger,
    load: &Load,
    opts: NewtonOptions,
    x: &mut [f64],
) -> Report {
    let mut p = finger.problem(load);
    let mut newton = Newton::new(x.len(), opts);
    newton.minimize(&mut p, x)
}

/// Newton on the dense reference path from scaled `x`.
pub fn solve_dense(finger: &Finger, load: &Load, opts: NewtonOptions, x: &mut [f64]) -> Report {
    let mut p = Dense::new(DenseFinger::new(finger, load));
    let mut newton = Newton::new(x.len(), opts);
    newton.minimize(&mut p, x)
}

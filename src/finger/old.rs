//! The chained composite model of one finger (docs/model.md section 4).
//!
//! Unknowns are scaled per element, `y = (a1, a3 L^2, b1, c2 L)`, so every
//! unknown is a dimensionless strain of order 0.01-0.1 and the Newton system
//! is well conditioned (raw `a3` and `c2` differ by four orders of
//! magnitude). The tip-load potential couples the elements through the
//! chain kinematics; its gradient and Hessian are assembled exactly from the
//! per-element end kernels:
//!
//! with `Fr_j = R(theta_j)^T F` (the load in element j's frame) and
//! `Q_j = tip - p_j`,
//!
//! - `d(F.tip)/dK_j = Fr_j . De_j + (F . J Q_j) grad eta_j`
//! - block `jj`: `Fr_j . D2e_j + (F . J Q_j) D2eta_j - (F . Q_j) grad eta_j grad eta_j^T`
//! - block `jk`, `j < k`: `grad eta_j w_k^T`, `w_k = (J^T Fr_k) . De_k - (F . Q_k) grad eta_k`
//!
//! where `J` rotates by +90 degrees. Scenes without a tip load decouple:
//! each distinct element is a 4x4 solve, done once for equal elements.

use fpc_newton::{
    min_eigenvalue, Energy, Gradient, Hessian, Newton, NewtonOptions, Report, Termination,
};

use crate::actuator::Actuator;
use crate::blocks::{distinct_elements, element_blocks, Partition};
use crate::element::{Coeffs, Element, UpperHessian};
use crate::error::{finite, positive, InputError, SolveError};
use crate::fit::fit_circle;
use crate::kernels::upper_index;

/// Pressure and tip loads of a scene.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Load {
    /// Channel pressure (MPa; 1 kPa = 0.001 MPa).
    pub pressure: f64,
    /// Pressure factor `kappa = 1/(gamma - 1)` (2.5 by default; 1 is plain `P dV` work).
    pub kappa: f64,
    /// Tip force along the finger's X axis (N).
    pub fx: f64,
    /// Tip force along the finger's Z axis (N).
    pub fz: f64,
}

impl Default for Load {
    fn default() -> Load {
        Load {
            pressure: 0.0,
            kappa: 2.5,
            fx: 0.0,
            fz: 0.0,
        }
    }
}

impl Load {
    /// No pressure, no tip load.
    pub fn unloaded() -> Load {
        Load::default()
    }

    /// The same load with a pressure given in kPa.
    pub fn with_pressure_kpa(mut self, kpa: f64) -> Load {
        self.pressure = kpa * 1e-3;
        self
    }

    /// The same load with a tip force (N, finger frame).
    pub fn with_tip_force(mut self, fx: f64, fz: f64) -> Load {
        self.fx = fx;
        self.fz = fz;
        self
    }

    /// True when a tip force acts.
    pub fn has_tip_load(&self) -> bool {
        self.fx != 0.0 || self.fz != 0.0
    }

    /// Checks that every value is finite and kappa positive.
    pub fn validate(&self) -> Result<(), InputError> {
        finite("load.pressure", self.pressure)?;
        positive("load.kappa", self.kappa)?;
        finite("load.fx", self.fx)?;
        finite("load.fz", self.fz)?;
        Ok(())
    }

    fn kp(&self) -> f64 {
        self.kappa * self.pressure
    }
}

/// How a scene is solved.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Strategy {
    /// Decoupled element solves when there is no tip load, the coupled
    /// system otherwise.
    #[default]
    Auto,
    /// Always the coupled 4N system (for checks and benchmarks).
    Coupled,
}

/// Solver settings.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SolveOptions {
    /// Relative residual: `||grad Pi||_inf` over the finger's stiffness scale.
    pub rtol: f64,
    /// Newton iteration limit per solve.
    pub max_iter: usize,
    /// Decoupled or coupled path.
    pub strategy: Strategy,
    /// Sample the mid-plane and fit a circle (off for tip-only output).
    pub shape: bool,
    /// Compute the smallest Hessian eigenvalue (off for tip-only output,
    /// then `Solution::min_hessian_eig` is `None`).
    pub stability: bool,
    /// Mid-plane samples per element when `shape` is on.
    pub samples_per_element: usize,
    /// Fall back to continuation when Newton fails from the guess: load
    /// continuation for tip loads; per element, pressure continuation from
    /// the straight element at zero pressure; and, when no unloaded
    /// equilibrium is found to start a loaded solve from, Newton from the
    /// straight finger.
    pub continuation: bool,
    /// Largest Newton step in the scaled unknowns (dimensionless strains).
    /// The prestressed law's quintic makes the energy unbounded below at
    /// large stretch, so an uncapped step from a poor guess can leave the
    /// physical basin for good; 0.25 never limits a step near equilibrium.
    pub max_step: f64,
}

impl Default for SolveOptions {
    fn default() -> SolveOptions {
        SolveOptions {
            rtol: 1e-11,
            max_iter: 60,
            strategy: Strategy::Auto,
            shape: true,
            stability: true,
            samples_per_element: 16,
            continuation: true,
            max_step: 0.25,
        }
    }
}

impl SolveOptions {
    /// Tip-only output: no shape sampling, no circle fit, no eigenvalue.
    pub fn tip_only(mut self) -> SolveOptions {
        self.shape = false;
        self.stability = false;
        self
    }

    fn validate(&self) -> Result<(), InputError> {
        positive("solve.rtol", self.rtol)?;
        positive("solve.max_step", self.max_step)?;
        if self.max_iter == 0 {
            return Err(InputError::OutOfRange {
                field: "solve.max_iter".into(),
                value: 0.0,
                rule: "must be at least 1".into(),
            });
        }
        if self.shape && self.samples_per_element == 0 {
            return Err(InputError::OutOfRange {
                field: "solve.samples_per_element".into(),
                value: 0.0,
                rule: "must be at least 1 when the shape is sampled".into(),
            });
        }
        Ok(())
    }
}

/// How a solve went.
#[derive(Debug, Clone, PartialEq)]
pub struct SolveReport {
    /// Why it stopped (always converged in a returned solution).
    pub reason: Termination,
    /// Newton iterations (summed over element solves and continuation steps).
    pub iterations: usize,
    /// `||grad Pi||_inf` in scaled units over the stiffness scale.
    pub residual_norm: f64,
    /// Kernel evaluations: energy, gradient and Hessian calls.
    pub evaluations: usize,
    /// True when the coupled system was solved (false: decoupled elements).
    pub coupled: bool,
    /// Continuation steps taken (0: Newton from the guess sufficed).
    pub continuation_steps: usize,
}

/// An equilibrium of one finger.
#[derive(Debug, Clone, PartialEq)]
pub struct Solution {
    /// `[a1, a3, b1, c2]` per element.
    pub coefficients: Vec<Coeffs>,
    /// Tip position (X, Z) in the finger frame (mm).
    pub tip: [f64; 2],
    /// Angle of the tip tangent from the X axis (rad).
    pub end_angle: f64,
    /// Total potential energy `Pi` (N mm).
    pub energy: f64,
    /// Smallest eigenvalue of the scaled Hessian over the stiffness scale
    /// (positive: stable); `None` when not computed (`SolveOptions::stability` off).
    pub min_hessian_eig: Option<f64>,
    /// Mid-plane samples from root to tip (empty for tip-only output).
    pub points: Vec<[f64; 2]>,
    /// Least-squares circle radius of the samples (`None`: nearly straight or not sampled).
    pub radius: Option<f64>,
    /// Solver report.
    pub report: SolveReport,
}

/// A finger: elements with their moments, ready to solve.
#[derive(Debug, Clone)]
pub struct Finger {
    elements: Vec<Element>,
    distinct: Vec<usize>,
    stiffness: f64,
}

#[inline]
fn scales(l: f64) -> Coeffs {
    [1.0, 1.0 / (l * l), 1.0, 1.0 / l]
}

impl Finger {
    /// Builds the elements of `actuator` split by `partition` (ribs optional).
    pub fn new(actuator: &Actuator, partition: &Partition, ribs: bool) -> Finger {
        let blocks = element_blocks(actuator, partition, ribs);
        let distinct = distinct_elements(&blocks);
        let elements: Vec<Element> = blocks.iter().map(Element::from_blocks).collect();
        // stiffness scale: the largest scaled Hessian diagonal of the
        // unstrained strain energy (about E*A*L of the stiffest element)
        let mut stiffness: f64 = 0.0;
        for e in &elements {
            let (_, _, h) = e.hessian(&[0.0; 4], 0.0);
            let s = scales(e.length());
            for i in 0..4 {
                stiffness = stiffness.max((h[upper_index(i, i)] * s[i] * s[i]).abs());
            }
        }
        Finger {
            elements,
            distinct,
            stiffness: stiffness.max(f64::MIN_POSITIVE),
        }
    }

    /// The default actuator at prestrain `eps0`, `n` equal elements, ribs on.
    pub fn paper(eps0: f64, n: usize) -> Result<Finger, InputError> {
        let act = Actuator::paper(eps0)?;
        let part = Partition::equal(act.geometry().lx, n)?;
        Ok(Finger::new(&act, &part, true))
    }

    /// Number of elements.
    pub fn len(&self) -> usize {
        self.elements.len()
    }

    /// True for a finger without elements (never built by the constructors).
    pub fn is_empty(&self) -> bool {
        self.elements.is_empty()
    }

    /// The elements.
    pub fn elements(&self) -> &[Element] {
        &self.elements
    }

    /// Stiffness scale (N mm) that makes residuals relative.
    pub fn stiffness_scale(&self) -> f64 {
        self.stiffness
    }

    /// Total potential energy at raw coefficients.
    pub fn energy(&self, load: &Load, k: &[Coeffs]) -> f64 {
        let mut v: f64 = self
            .elements
            .iter()
            .zip(k)
            .map(|(e, k)| e.energy(k, load.kp()))
            .sum();
        if load.has_tip_load() {
            let (tip, _) = self.tip(k);
            v -= load.fx * tip[0] + load.fz * tip[1];
        }
        v
    }

    /// Tip position and end angle at raw coefficients.
    pub fn tip(&self, k: &[Coeffs]) -> ([f64; 2], f64) {
        let angle = self.elements.iter().zip(k).map(|(e, k)| e.end(k)[2]).sum();
        (self.tip_position(k), angle)
    }

    /// Tip position at raw coefficients, chaining element frames by
    /// rotation (no trigonometric calls).
    pub fn tip_position(&self, k: &[Coeffs]) -> [f64; 2] {
        let mut p = [0.0, 0.0];
        let (mut c, mut s) = (1.0, 0.0);
        for (e, k) in self.elements.iter().zip(k) {
            let [xe, ze, ce, se] = e.frame(k);
            p[0] += c * xe - s * ze;
            p[1] += s * xe + c * ze;
            (c, s) = (c * ce - s * se, s * ce + c * se);
        }
        p
    }

    /// Mid-plane samples from the root (included) to the tip.
    pub fn shape(&self, k: &[Coeffs], per_element: usize) -> Vec<[f64; 2]> {
        let mut pts = vec![[0.0, 0.0]];
        let mut p = [0.0, 0.0];
        let mut theta: f64 = 0.0;
        for (e, k) in self.elements.iter().zip(k) {
            let l = e.length();
            let (s, c) = theta.sin_cos();
            for j in 1..=per_element.max(1) {
                let x = l * j as f64 / per_element.max(1) as f64;
                let (xl, zl) = ((1.0 + k[0]) * x + k[1] * x * x * x, k[3] * x * x);
                pts.push([p[0] + c * xl - s * zl, p[1] + s * xl + c * zl]);
            }
            let [xe, ze, eta] = e.end(k);
            p[0] += c * xe - s * ze;
            p[1] += s * xe + c * ze;
            theta += eta;
        }
        pts
    }

    /// The scene as a Newton problem in scaled unknowns.
    pub fn problem(&self, load: &Load) -> Chain<'_> {
        let mut c = Chain::new(self);
        c.set_load(load);
        c
    }

    /// Total potential energy and its gradient with respect to the raw
    /// coefficients (element by element, `[a1, a3, b1, c2]` each).
    pub fn gradient(&self, load: &Load, k: &[Coeffs]) -> (f64, Vec<f64>) {
        let mut chain = Chain::new(self);
        chain.set_load(load);
        let y = chain.scaled(k);
        let mut g = vec![0.0; y.len()];
        let v = chain.gradient(&y, &mut g);
        for (i, gi) in g.iter_mut().enumerate() {
            *gi /= chain.s[i / 4][i % 4];
        }
        (v, g)
    }

    /// Total potential energy, gradient and full Hessian (column-major,
    /// `4N x 4N`) with respect to the raw coefficients.
    pub fn hessian(&self, load: &Load, k: &[Coeffs]) -> (f64, Vec<f64>, Vec<f64>) {
        let mut chain = Chain::new(self);
        chain.set_load(load);
        let y = chain.scaled(k);
        let n = y.len();
        let mut g = vec![0.0; n];
        let mut h = vec![0.0; n * n];
        let v = chain.hessian(&y, &mut g, &mut h);
        fill_upper(n, &mut h);
        for i in 0..n {
            let si = chain.s[i / 4][i % 4];
            g[i] /= si;
            for j in 0..n {
                h[i + n * j] /= si * chain.s[j / 4][j % 4];
            }
        }
        (v, g, h)
    }

    /// Solves a scene from the straight finger (or, with a tip load, from
    /// the unloaded equilibrium at the same pressure).
    pub fn solve(&self, load: &Load, opts: &SolveOptions) -> Result<Solution, SolveError> {
        Solver::new(self).solve(load, None, opts)
    }

    /// Solves a scene from given coefficients.
    pub fn solve_from(
        &self,
        load: &Load,
        guess: &[Coeffs],
        opts: &SolveOptions,
    ) -> Result<Solution, SolveError> {
        Solver::new(self).solve(load, Some(guess), opts)
    }
}

/// Copies the lower triangle of a column-major `n x n` matrix to its upper triangle.
pub fn fill_upper(n: usize, h: &mut [f64]) {
    for j in 0..n {
        for i in j + 1..n {
            h[j + n * i] = h[i + n * j];
        }
    }
}

/// Checks a starting guess: one coefficient set per element (`n`), every
/// value finite.
fn check_guess(guess: &[Coeffs], n: usize) -> Result<(), InputError> {
    if guess.len() != n {
        return Err(InputError::OutOfRange {
            field: "guess".into(),
            value: guess.len() as f64,
            rule: format!("must hold one coefficient set per element ({n})"),
        });
    }
    match guess.iter().flatten().find(|v| !v.is_finite()) {
        Some(&value) => Err(InputError::NotFinite {
            field: "guess".into(),
            value,
        }),
        None => Ok(()),
    }
}

/// A reusable solver workspace (no allocation per Newton iteration; reuse
/// it across the points of a sweep).
pub struct Solver<'a> {
    finger: &'a Finger,
    chain: Chain<'a>,
    newton: Newton,
    local: Newton,
    y: Vec<f64>,
    /// The start of a coupled solve, kept for a continuation restart.
    start: Vec<f64>,
    /// Pi at the end of the last coupled Newton solve (taken by `finish`).
    final_energy: Option<f64>,
}

impl<'a> Solver<'a> {
    /// A workspace for `finger`.
    pub fn new(finger: &'a Finger) -> Solver<'a> {
        let n = 4 * finger.len();
        Solver {
            finger,
            chain: Chain::new(finger),
            newton: Newton::new(n, NewtonOptions::default()),
            local: Newton::new(4, NewtonOptions::default()),
            y: vec![0.0; n],
            start: vec![0.0; n],
            final_energy: None,
        }
    }

    /// The finger being solved.
    pub fn finger(&self) -> &'a Finger {
        self.finger
    }

    /// Solves a scene; `guess` are raw coefficients per element.
    pub fn solve(
        &mut self,
        load: &Load,
        guess: Option<&[Coeffs]>,
        opts: &SolveOptions,
    ) -> Result<Solution, SolveError> {
        load.validate()?;
        opts.validate()?;
        let f = self.finger;
        if let Some(g) = guess {
            check_guess(g, f.len())?;
        }
        let gtol = opts.rtol * f.stiffness;
        let nopts = NewtonOptions {
            gtol,
            max_iter: opts.max_iter,
            max_step: opts.max_step,
            ..NewtonOptions::default()
        };
        self.newton
            .set_options(nopts)
            .map_err(|e| InputError::OutOfRange {
                field: "solve".into(),
                value: gtol,
                rule: e.to_string(),
            })?;
        self.local
            .set_options(nopts)
            .map_err(|e| InputError::OutOfRange {
                field: "solve".into(),
                value: gtol,
                rule: e.to_string(),
            })?;
        let decoupled = !load.has_tip_load() && opts.strategy == Strategy::Auto;
        let mut report = if decoupled {
            self.solve_decoupled(load, guess, opts.continuation)?
        } else {
            self.solve_coupled(load, guess, opts)?
        };
        report.residual_norm /= f.stiffness;
        self.finish(load, opts, report, decoupled)
    }

    fn load_guess(&mut self, guess: Option<&[Coeffs]>) {
        for (i, e) in self.finger.elements.iter().enumerate() {
            let s = scales(e.length());
            let k = guess.map_or([0.0; 4], |g| g[i]);
            for j in 0..4 {
                self.y[4 * i + j] = k[j] / s[j];
            }
        }
    }

    fn solve_decoupled(
        &mut self,
        load: &Load,
        guess: Option<&[Coeffs]>,
        continuation: bool,
    ) -> Result<SolveReport, SolveError> {
        self.load_guess(guess);
        let f = self.finger;
        let mut rep = SolveReport {
            reason: Termination::Converged,
            iterations: 0,
            residual_norm: 0.0,
            evaluations: 0,
            coupled: false,
            continuation_steps: 0,
        };
        for i in 0..f.len() {
            let d = f.distinct[i];
            if d != i {
                let (a, b) = self.y.split_at_mut(4 * i);
                b[..4].copy_from_slice(&a[4 * d..4 * d + 4]);
                continue;
            }
            let mut p = Single {
                element: &f.elements[i],
                kp: load.kp(),
                s: scales(f.elements[i].length()),
            };
            let warm = guess.is_none() && i > 0;
            if warm {
                // neighbouring elements strain and curve alike: start from
                // the last solved one's raw coefficients (a1, a3, b1, c2 do
                // not depend on the length; the scaled a3 L^2 and c2 L do)
                let sp = scales(f.elements[i - 1].length());
                let (a, b) = self.y.split_at_mut(4 * i);
                for (((yi, yp), sp), si) in
                    b[..4].iter_mut().zip(&a[4 * (i - 1)..]).zip(sp).zip(p.s)
                {
                    *yi = yp * sp / si;
                }
            }
            let y = &mut self.y[4 * i..4 * i + 4];
            let r = solve_element(&mut self.local, &mut p, y, warm, continuation, &mut rep);
            rep.residual_norm = rep.residual_norm.max(r.residual_norm);
            if !r.reason.is_converged() {
                return Err(self.not_converged(&r, Some(i)));
            }
        }
        Ok(rep)
    }

    fn solve_coupled(
        &mut self,
        load: &Load,
        guess: Option<&[Coeffs]>,
        opts: &SolveOptions,
    ) -> Result<SolveReport, SolveError> {
        let mut base = SolveReport {
            reason: Termination::Converged,
            iterations: 0,
            residual_norm: 0.0,
            evaluations: 0,
            coupled: true,
            continuation_steps: 0,
        };
        let start_load = Load {
            fx: 0.0,
            fz: 0.0,
            ..*load
        };
        let mut start_failed = false;
        match guess {
            Some(g) => self.load_guess(Some(g)),
            None => {
                // the unloaded equilibrium at the same pressure
                match self.solve_decoupled(&start_load, None, opts.continuation) {
                    Ok(r) => {
                        base.iterations += r.iterations;
                        base.evaluations += r.evaluations;
                        base.continuation_steps += r.continuation_steps;
                    }
                    Err(SolveError::NotConverged { iterations, .. }) if opts.continuation => {
                        // no unloaded equilibrium to start from (a curl the
                        // elements cannot follow, which the load may undo):
                        // Newton from the straight finger, and no load
                        // continuation (it needs an equilibrium to start)
                        base.iterations += iterations;
                        self.load_guess(None);
                        start_failed = true;
                    }
                    Err(e) => return Err(e),
                }
            }
        }
        self.start.copy_from_slice(&self.y);
        self.chain.set_load(load);
        let r = self.newton.minimize(&mut self.chain, &mut self.y);
        base.iterations += r.iterations;
        base.evaluations += r.energy_evals + r.gradient_evals + r.hessian_evals;
        base.residual_norm = r.residual_norm;
        if r.reason.is_converged() {
            self.final_energy = Some(r.energy);
            return Ok(base);
        }
        if !opts.continuation || !load.has_tip_load() || start_failed {
            return Err(self.not_converged(&r, None));
        }
        // load continuation from the start point: F(t) = t F
        self.y.copy_from_slice(&self.start);
        let chain = &mut self.chain;
        let newton = &mut self.newton;
        let copts = fpc_newton::ContinuationOptions::default();
        let cr = fpc_newton::continuation(0.0, 1.0, &mut self.y, &copts, |t, y| {
            chain.set_load(&Load {
                fx: t * load.fx,
                fz: t * load.fz,
                ..*load
            });
            newton.minimize(chain, y)
        });
        base.iterations += cr.newton_iterations;
        base.continuation_steps += cr.steps;
        base.residual_norm = cr.last.residual_norm;
        if cr.complete && cr.last.reason.is_converged() {
            self.chain.set_load(load);
            self.final_energy = Some(cr.last.energy);
            Ok(base)
        } else {
            Err(self.not_converged(&cr.last, None))
        }
    }

    fn coefficients(&self) -> Vec<Coeffs> {
        self.finger
            .elements
            .iter()
            .enumerate()
            .map(|(i, e)| {
                let s = scales(e.length());
                [
                    self.y[4 * i] * s[0],
                    self.y[4 * i + 1] * s[1],
                    self.y[4 * i + 2] * s[2],
                    self.y[4 * i + 3] * s[3],
                ]
            })
            .collect()
    }

    fn not_converged(&self, r: &Report, element: Option<usize>) -> SolveError {
        SolveError::NotConverged {
            reason: r.reason,
            iterations: r.iterations,
            relative_residual: r.residual_norm / self.finger.stiffness,
            element,
            last: self.coefficients(),
        }
    }

    fn finish(
        &mut self,
        load: &Load,
        opts: &SolveOptions,
        report: SolveReport,
        decoupled: bool,
    ) -> Result<Solution, SolveError> {
        let f = self.finger;
        let k = self.coefficients();
        let (tip, end_angle) = f.tip(&k);
        // a coupled Newton solve already knows Pi at its final point
        let energy = self.final_energy.take().unwrap_or_else(|| {
            f.elements
                .iter()
                .zip(&k)
                .map(|(e, k)| e.energy(k, load.kp()))
                .sum::<f64>()
                - (load.fx * tip[0] + load.fz * tip[1])
        });
        // stability: eigenvalues of the scaled Hessian
        let min_hessian_eig = if !opts.stability {
            None
        } else if decoupled {
            let mut m = f64::INFINITY;
            for (i, e) in f.elements.iter().enumerate() {
                if f.distinct[i] != i {
                    continue;
                }
                let mut p = Single {
                    element: e,
                    kp: load.kp(),
                    s: scales(e.length()),
                };
                let mut g = [0.0; 4];
                let mut h = [0.0; 16];
                p.hessian(&self.y[4 * i..4 * i + 4], &mut g, &mut h);
                // 4x4 on the stack: nalgebra's symmetric eigenvalues, no allocation
                let ev = nalgebra::Matrix4::from_column_slice(&h).symmetric_eigenvalues();
                m = m.min(ev.min());
            }
            Some(m / f.stiffness)
        } else {
            let n = 4 * f.len();
            let mut g = vec![0.0; n];
            let mut h = vec![0.0; n * n];
            self.chain.set_load(load);
            self.chain.hessian(&self.y, &mut g, &mut h);
            fill_upper(n, &mut h);
            Some(min_eigenvalue(n, &h) / f.stiffness)
        }
        .filter(|e| e.is_finite());
        let (points, radius) = if opts.shape {
            let pts = f.shape(&k, opts.samples_per_element);
            let r = fit_circle(&pts).map(|c| c.radius);
            (pts, r)
        } else {
            (Vec::new(), None)
        };
        let values_finite =
            tip.iter().all(|v| v.is_finite()) && energy.is_finite() && end_angle.is_finite();
        if !values_finite {
            return Err(SolveError::NotConverged {
                reason: Termination::NonFinite,
                iterations: report.iterations,
                relative_residual: f64::INFINITY,
                element: None,
                last: k,
            });
        }
        Ok(Solution {
            coefficients: k,
            tip,
            end_angle,
            energy,
            min_hessian_eig,
            points,
            radius,
            report,
        })
    }
}

/// Minimises one element's energy from `y` (the decoupled scenes). When
/// that fails: again from the straight element if `y` was a warm start,
/// then, with `continuation` and a pressure, by pressure continuation from
/// the straight element at zero pressure to the target (warm-starting each
/// step). Adds iterations, evaluations and continuation steps to `rep`;
/// returns the last report, its `iterations` counting every attempt.
fn solve_element(
    newton: &mut Newton,
    p: &mut Single,
    y: &mut [f64],
    warm: bool,
    continuation: bool,
    rep: &mut SolveReport,
) -> Report {
    let before = rep.iterations;
    let tally = |r: &Report, rep: &mut SolveReport| {
        rep.iterations += r.iterations;
        rep.evaluations += r.energy_evals + r.gradient_evals + r.hessian_evals;
    };
    let mut r = newton.minimize(p, y);
    tally(&r, rep);
    if !r.reason.is_converged() && warm {
        y.fill(0.0);
        r = newton.minimize(p, y);
        tally(&r, rep);
    }
    let kp = p.kp;
    if !r.reason.is_converged() && continuation && kp != 0.0 {
        y.fill(0.0);
        p.kp = 0.0;
        r = newton.minimize(p, y);
        tally(&r, rep);
        if r.reason.is_converged() {
            let copts = fpc_newton::ContinuationOptions::default();
            let cr = fpc_newton::continuation(0.0, 1.0, y, &copts, |t, y| {
                p.kp = t * kp;
                let r = newton.minimize(p, y);
                tally(&r, rep);
                r
            });
            rep.continuation_steps += cr.steps;
            r = cr.last;
            if !cr.complete && r.reason.is_converged() {
                r.reason = Termination::MaxIterations;
            }
        }
        p.kp = kp;
    }
    r.iterations = rep.iterations - before;
    r
}

/// One element in scaled unknowns (the decoupled scenes).
struct Single<'a> {
    element: &'a Element,
    kp: f64,
    s: Coeffs,
}

impl Single<'_> {
    fn raw(&self, y: &[f64]) -> Coeffs {
        [
            y[0] * self.s[0],
            y[1] * self.s[1],
            y[2] * self.s[2],
            y[3] * self.s[3],
        ]
    }
}

impl Energy for Single<'_> {
    fn dim(&self) -> usize {
        4
    }
    fn energy(&mut self, y: &[f64]) -> f64 {
        self.element.energy(&self.raw(y), self.kp)
    }
}

impl Gradient for Single<'_> {
    fn gradient(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        let (v, gk) = self.element.gradient(&self.raw(y), self.kp);
        for i in 0..4 {
            g[i] = gk[i] * self.s[i];
        }
        v
    }
}

impl Hessian for Single<'_> {
    fn hessian(&mut self, y: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        let (v, gk, hk) = self.element.hessian(&self.raw(y), self.kp);
        for i in 0..4 {
            g[i] = gk[i] * self.s[i];
            for j in 0..4 {
                h[i + 4 * j] = hk[upper_index(i, j)] * self.s[i] * self.s[j];
            }
        }
        v
    }
}

/// The coupled finger as a Newton problem in scaled unknowns
/// `y = (a1, a3 L^2, b1, c2 L)` per element: all elements plus the tip-load
/// chain, with exact gradient and Hessian (the lower triangle only, which is
/// all Newton reads; [`fill_upper`] completes it). Build it
/// with [`Finger::problem`]; it reuses its buffers, so evaluations do not
/// allocate.
pub struct Chain<'a> {
    finger: &'a Finger,
    kp: f64,
    f: [f64; 2],
    k: Vec<Coeffs>,
    s: Vec<Coeffs>,
    end_g: Vec<[Coeffs; 3]>,
    end_h: Vec<[UpperHessian; 3]>,
    /// (cos, sin) of each element frame's angle theta_i.
    rot: Vec<[f64; 2]>,
    q: Vec<[f64; 2]>,
    u: Vec<Coeffs>,
    w: Vec<Coeffs>,
    blk: Vec<UpperHessian>,
    tip: [f64; 2],
    force_chain: bool,
    /// Condensed Newton system (lower triangle), its right-hand side, and
    /// the shifted b1 pivots.
    red: Vec<f64>,
    rg: Vec<f64>,
    hbb: Vec<f64>,
    cb: Vec<[f64; 3]>,
}

impl<'a> Chain<'a> {
    /// The problem for `finger` with no load (see [`Chain::set_load`]).
    pub fn new(finger: &'a Finger) -> Chain<'a> {
        let n = finger.len();
        Chain {
            finger,
            kp: 0.0,
            f: [0.0, 0.0],
            k: vec![[0.0; 4]; n],
            s: finger.elements.iter().map(|e| scales(e.length())).collect(),
            end_g: vec![[[0.0; 4]; 3]; n],
            end_h: vec![[[0.0; 10]; 3]; n],
            rot: vec![[1.0, 0.0]; n],
            q: vec![[0.0; 2]; n],
            u: vec![[0.0; 4]; n],
            w: vec![[0.0; 4]; n],
            blk: vec![[0.0; 10]; n],
            tip: [0.0, 0.0],
            force_chain: false,
            red: Vec::new(),
            rg: Vec::new(),
            hbb: vec![0.0; n],
            cb: vec![[0.0; 3]; n],
        }
    }

    /// Sets pressure and tip load.
    pub fn set_load(&mut self, load: &Load) {
        self.kp = load.kp();
        self.f = [load.fx, load.fz];
    }

    /// True when the chain geometry is needed (a tip load acts, or a
    /// bordered solve needs the tip and its gradient).
    fn loaded(&self) -> bool {
        self.force_chain || self.f[0] != 0.0 || self.f[1] != 0.0
    }

    /// Scaled gradient of `w . tip` from the geometry of the last
    /// gradient/Hessian evaluation.
    fn tip_gradient_scaled(&self, w: [f64; 2], out: &mut [f64]) {
        for j in 0..self.k.len() {
            let [c, s] = self.rot[j];
            let wr = [c * w[0] + s * w[1], -s * w[0] + c * w[1]];
            let qj = self.q[j];
            let wjq = -w[0] * qj[1] + w[1] * qj[0];
            let eg = &self.end_g[j];
            for a in 0..4 {
                out[4 * j + a] =
                    (wr[0] * eg[0][a] + wr[1] * eg[1][a] + wjq * eg[2][a]) * self.s[j][a];
            }
        }
    }

    /// Scaled unknowns of raw coefficients.
    pub fn scaled(&self, k: &[Coeffs]) -> Vec<f64> {
        k.iter()
            .zip(&self.s)
            .flat_map(|(k, s)| (0..4).map(move |j| k[j] / s[j]))
            .collect()
    }

    fn unscale(&mut self, y: &[f64]) {
        for (i, (k, s)) in self.k.iter_mut().zip(&self.s).enumerate() {
            for j in 0..4 {
                k[j] = y[4 * i + j] * s[j];
            }
        }
    }

    /// Frames (as rotations, from the elements' end tangents) and the
    /// vectors from each element's end to the tip.
    fn chain_geometry(&mut self) {
        let n = self.k.len();
        let (mut c, mut s) = (1.0, 0.0);
        let mut p = [0.0, 0.0];
        let mut ends_p = [0.0, 0.0];
        for i in 0..n {
            self.rot[i] = [c, s];
            let [xe, ze, ce, se] = self.finger.elements[i].frame(&self.k[i]);
            p[0] += c * xe - s * ze;
            p[1] += s * xe + c * ze;
            self.q[i] = p; // p_i for now
            (c, s) = (c * ce - s * se, s * ce + c * se);
            ends_p = p;
        }
        for i in 0..n {
            self.q[i] = [ends_p[0] - self.q[i][0], ends_p[1] - self.q[i][1]];
        }
        self.tip = ends_p;
    }
}

impl Energy for Chain<'_> {
    fn dim(&self) -> usize {
        4 * self.k.len()
    }

    fn energy(&mut self, y: &[f64]) -> f64 {
        self.unscale(y);
        let mut v = 0.0;
        for (e, k) in self.finger.elements.iter().zip(&self.k) {
            v += e.energy(k, self.kp);
        }
        if self.loaded() {
            let tip = self.finger.tip_position(&self.k);
            v -= self.f[0] * tip[0] + self.f[1] * tip[1];
        }
        v
    }
}

impl Gradient for Chain<'_> {
    fn gradient(&mut self, y: &[f64], g: &mut [f64]) -> f64 {
        self.unscale(y);
        let loaded = self.loaded();
        let mut v = 0.0;
        for (i, e) in self.finger.elements.iter().enumerate() {
            let (vi, gi) = e.gradient(&self.k[i], self.kp);
            v += vi;
            g[4 * i..4 * i + 4].copy_from_slice(&gi);
            if loaded {
                let (_, eg) = crate::kernels::end_gradient(&self.k[i], e.length());
                self.end_g[i] = eg;
            }
        }
        if loaded {
            self.chain_geometry();
            let [fx, fz] = self.f;
            let n = self.k.len();
            v -= fx * self.tip[0] + fz * self.tip[1];
            for j in 0..n {
                let [c, s] = self.rot[j];
                let fr = [c * fx + s * fz, -s * fx + c * fz];
                let qj = self.q[j];
                let fjq = -fx * qj[1] + fz * qj[0];
                let eg = &self.end_g[j];
                for a in 0..4 {
                    g[4 * j + a] -= fr[0] * eg[0][a] + fr[1] * eg[1][a] + fjq * eg[2][a];
                }
            }
        }
        for (i, s) in self.s.iter().enumerate() {
            for j in 0..4 {
                g[4 * i + j] *= s[j];
            }
        }
        v
    }
}

impl Hessian for Chain<'_> {
    /// Condenses the transverse strains `b1` out of the Newton system: each
    /// couples only within its own element's block (the chain terms do not
    /// involve it), so eliminating it leaves a `3N x 3N` Cholesky instead of
    /// `4N x 4N`, about 2.4 times less work.
    fn solve_shifted(&mut self, h: &[f64], g: &[f64], tau: f64, p: &mut [f64]) -> Option<bool> {
        let n = self.k.len();
        let (dim, m) = (4 * n, 3 * n);
        if m > fpc_newton::AUTO_DENSE_MAX_DIM {
            return None; // faer's factorisation wins at this size
        }
        const KEEP: [usize; 3] = [0, 1, 3];
        self.red.resize(m * m, 0.0);
        self.rg.resize(m, 0.0);
        // per element: the shifted b1 pivot and the b1 column of its block
        for e in 0..n {
            let b = 4 * e + 2;
            let hbb = h[b + dim * b] + tau;
            if hbb.is_nan() || hbb <= 0.0 {
                return Some(false);
            }
            self.hbb[e] = hbb;
            // rows 4e, 4e+1 sit above b (upper part: read the mirrored lower entry)
            self.cb[e] = [
                h[b + dim * (4 * e)],
                h[b + dim * (4 * e + 1)],
                h[(4 * e + 3) + dim * b],
            ];
        }
        for c in 0..m {
            let (ec, tc) = (c / 3, c % 3);
            let jc = 4 * ec + KEEP[tc];
            let scale = self.cb[ec][tc] / self.hbb[ec];
            self.rg[c] = g[jc] - scale * g[4 * ec + 2];
            let col = &h[dim * jc..dim * (jc + 1)];
            let out = &mut self.red[m * c..m * (c + 1)];
            // the diagonal block: Schur complement of b1
            for (r, o) in out.iter_mut().enumerate().take(3 * ec + 3).skip(c) {
                let tr = r % 3;
                *o = col[4 * ec + KEEP[tr]] - self.cb[ec][tr] * scale;
            }
            out[c] += tau;
            // blocks below: b1 does not couple across elements
            for er in ec + 1..n {
                let src = &col[4 * er..4 * er + 4];
                out[3 * er] = src[0];
                out[3 * er + 1] = src[1];
                out[3 * er + 2] = src[3];
            }
        }
        if fpc_newton::cholesky_in_place(m, &mut self.red).is_err() {
            return Some(false);
        }
        for v in self.rg.iter_mut() {
            *v = -*v;
        }
        fpc_newton::cholesky_solve(m, &self.red, &mut self.rg);
        for e in 0..n {
            let b = 4 * e + 2;
            let mut rhs = -g[b];
            for (t, &kk) in KEEP.iter().enumerate() {
                let j = 4 * e + kk;
                p[j] = self.rg[3 * e + t];
                rhs -= self.cb[e][t] * p[j];
            }
            p[b] = rhs / self.hbb[e];
        }
        Some(true)
    }

    fn hessian(&mut self, y: &[f64], g: &mut [f64], h: &mut [f64]) -> f64 {
        self.unscale(y);
        let n = self.k.len();
        let dim = 4 * n;
        let loaded = self.loaded();
        let mut v = 0.0;
        // pass 1: element energies and, for the chain, end kinematics
        for (i, e) in self.finger.elements.iter().enumerate() {
            let (vi, gi, hi) = e.hessian(&self.k[i], self.kp);
            v += vi;
            g[4 * i..4 * i + 4].copy_from_slice(&gi);
            self.blk[i] = hi;
            if loaded {
                let (_, eg, eh) = e.end_hessian(&self.k[i]);
                self.end_g[i] = eg;
                self.end_h[i] = eh;
            }
        }
        if loaded {
            self.chain_geometry();
            let [fx, fz] = self.f;
            v -= fx * self.tip[0] + fz * self.tip[1];
            for j in 0..n {
                let [cs, sn] = self.rot[j];
                let fr = [cs * fx + sn * fz, -sn * fx + cs * fz];
                let qj = self.q[j];
                let fjq = -fx * qj[1] + fz * qj[0]; // F . J Q_j
                let fq = fx * qj[0] + fz * qj[1]; // F . Q_j
                let eg = self.end_g[j];
                let eh = self.end_h[j];
                let blk = &mut self.blk[j];
                for a in 0..4 {
                    g[4 * j + a] -= fr[0] * eg[0][a] + fr[1] * eg[1][a] + fjq * eg[2][a];
                    for b in a..4 {
                        let ab = upper_index(a, b);
                        blk[ab] -= fr[0] * eh[0][ab] + fr[1] * eh[1][ab] + fjq * eh[2][ab]
                            - fq * eg[2][a] * eg[2][b];
                    }
                }
                // scaled coupling vectors: u_j = grad eta_j, and
                // w_j = (J^T Fr_j) . De_j - (F . Q_j) grad eta_j, J^T Fr = (Fr_z, -Fr_x)
                let sj = self.s[j];
                for a in 0..4 {
                    self.u[j][a] = eg[2][a] * sj[a];
                    self.w[j][a] = (fr[1] * eg[0][a] - fr[0] * eg[1][a] - fq * eg[2][a]) * sj[a];
                }
            }
        }
        // pass 2: write the scaled Hessian
        for j in 0..n {
            let sj = self.s[j];
            let blk = &self.blk[j];
            for b in 0..4 {
                let col = &mut h[dim * (4 * j + b)..dim * (4 * j + b + 1)];
                for a in 0..4 {
                    col[4 * j + a] = blk[upper_index(a, b)] * sj[a] * sj[b];
                }
                // lower triangle only (Newton reads no more): row blocks k > j
                let below = &mut col[4 * (j + 1)..];
                if loaded {
                    // row block k > column block j: -w_k u_j^T
                    let ub = self.u[j][b];
                    for (dst, w) in below.chunks_exact_mut(4).zip(&self.w[j + 1..]) {
                        for a in 0..4 {
                            dst[a] = -w[a] * ub;
                        }
                    }
                } else {
                    below.fill(0.0);
                }
            }
        }
        for (i, s) in self.s.iter().enumerate() {
            for a in 0..4 {
                g[4 * i + a] *= s[a];
            }
        }
        v
    }
}

/// A scene whose tip load depends on one unknown scalar `lambda`,
/// `F = base + lambda * direction`, fixed by one target on the tip position:
/// `weights . tip = target` at equilibrium (docs/model.md section 6: the unknown
/// load joins the Newton system with the target as an extra equation).
#[derive(Debug, Clone, Copy, PartialEq)]
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

    fn validate(&self) -> Result<(), InputError> {
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

struct BorderedChain<'c, 'a> {
    chain: &'c mut Chain<'a>,
    problem: TargetProblem,
    scratch: Vec<f64>,
    /// Stiffness scale over the finger length: weighs a tip error (mm) like
    /// the strain error it implies.
    c_scale: f64,
}

impl fpc_newton::Bordered for BorderedChain<'_, '_> {
    fn dim(&self) -> usize {
        self.chain.dim()
    }

    fn eval(&mut self, y: &[f64], lambda: f64, out: &mut fpc_newton::BorderedEval) -> bool {
        let load = self.problem.load_at(lambda);
        self.chain.set_load(&load);
        self.chain.force_chain = true;
        let v = self.chain.hessian(y, &mut out.g, &mut out.h);
        fill_upper(out.g.len(), &mut out.h);
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

impl Solver<'_> {
    /// Solves a [`TargetProblem`] from `guess` (raw coefficients, ideally a
    /// nearby equilibrium) and a starting `lambda`; returns the equilibrium
    /// and the `lambda` that meets the target. `ctol_mm` bounds the target
    /// residual.
    pub fn solve_target(
        &mut self,
        problem: &TargetProblem,
        guess: &[Coeffs],
        lambda0: f64,
        ctol_mm: f64,
        opts: &SolveOptions,
    ) -> Result<(Solution, f64), SolveError> {
        problem.validate()?;
        opts.validate()?;
        finite("target.lambda0", lambda0)?;
        positive("target.ctol_mm", ctol_mm)?;
        let f = self.finger;
        check_guess(guess, f.len())?;
        self.load_guess(Some(guess));
        let length: f64 = f.elements.iter().map(|e| e.length()).sum();
        let c_scale = f.stiffness / length;
        let nopts = NewtonOptions {
            gtol: opts.rtol * f.stiffness,
            ctol: ctol_mm * c_scale,
            max_iter: opts.max_iter,
            max_step: opts.max_step,
            ..NewtonOptions::default()
        };
        self.newton
            .set_options(nopts)
            .map_err(|e| InputError::OutOfRange {
                field: "solve".into(),
                value: nopts.gtol,
                rule: e.to_string(),
            })?;
        let mut lambda = lambda0;
        let n = self.y.len();
        let mut bc = BorderedChain {
            chain: &mut self.chain,
            problem: *problem,
            scratch: vec![0.0; n],
            c_scale,
        };
        let r = self
            .newton
            .solve_bordered(&mut bc, &mut self.y, &mut lambda);
        if !r.reason.is_converged() || !lambda.is_finite() {
            return Err(self.not_converged(&r, None));
        }
        let report = SolveReport {
            reason: r.reason,
            iterations: r.iterations,
            residual_norm: r.residual_norm / f.stiffness,
            evaluations: r.hessian_evals,
            coupled: true,
            continuation_steps: 0,
        };
        let load = problem.load_at(lambda);
        let sol = self.finish(&load, opts, report, false)?;
        Ok((sol, lambda))
    }
}

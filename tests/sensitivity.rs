//! Exact sensitivities (src/sensitivity.rs, docs/model.md "Sensitivities")
//! against central differences:
//!
//! - the generated moment Jacobians (`*_dmoments`) against central
//!   differences of the generated moments kernels, for every family,
//!   every parameter and both models; and the linearity in the moments
//!   that the sensitivities rest on (the gradient kernel at the moments'
//!   derivative, built with the trait's `add_*_tangents`, is the
//!   derivative of the gradient), also for the load scalar `kp`;
//! - every sensitivity of a finger against central differences of full
//!   re-solves (Richardson-extrapolated), for the tip-loaded standard case,
//!   a pressurised case and a target solve, with every model (the shear
//!   data, `actuator.laminate.shear_correction` and each layer's `g13`,
//!   among the parameters); and the shear correction's derivative against
//!   the shear model's 1 / ks law.
//!
//! Random inputs come from fastrand with fixed seeds. Each test prints its
//! worst agreement per group (`--nocapture`).

use fpc::actuator::ActuatorParam;
use fpc::finger::{Solver, TargetProblem};
use fpc::model::ElementModel;
use fpc::model::{
    ccm, quad, shear, EnergyScalars, GasParams, LinearParams, PrestressedParams, Vector,
};
use fpc::sensitivity::{Param, Sensitivities};
use fpc::studies::{tip_force_for_displacement, Axis};
use fpc::{Actuator, Coefficients, Finger, Load, ModelId, Partition, SolveOptions};

// ---------------------------------------------------------------------------
// Central differences.

/// Richardson-extrapolated central difference of a vector function at `x`
/// with step `h`: `(4 D(h/2) - D(h)) / 3`, error O(h^4).
fn richardson(f: &mut dyn FnMut(f64) -> Vec<f64>, x: f64, h: f64) -> Vec<f64> {
    let d = |f: &mut dyn FnMut(f64) -> Vec<f64>, h: f64| -> Vec<f64> {
        let (a, b) = (f(x + h), f(x - h));
        a.iter().zip(&b).map(|(a, b)| (a - b) / (2.0 * h)).collect()
    };
    let d1 = d(f, h);
    let d2 = d(f, 0.5 * h);
    d1.iter()
        .zip(&d2)
        .map(|(d1, d2)| (4.0 * d2 - d1) / 3.0)
        .collect()
}

/// Two Richardson levels, error O(h^6): for the moments, polynomials of
/// degree up to 11 in the bounds, whose differences cancel digits.
fn richardson2(f: &mut dyn FnMut(f64) -> Vec<f64>, x: f64, h: f64) -> Vec<f64> {
    let r1 = richardson(f, x, h);
    let r2 = richardson(f, x, 0.5 * h);
    r1.iter()
        .zip(&r2)
        .map(|(r1, r2)| (16.0 * r2 - r1) / 15.0)
        .collect()
}

/// `max_i |a_i - b_i| / max_i |b_i|` (0 when both vanish).
fn rel_vec(a: &[f64], b: &[f64]) -> f64 {
    rel_floor(a, b, 0.0)
}

/// `max_i |a_i - b_i| / max(max_i |a_i|, max_i |b_i|, floor)` (0 when all
/// vanish): relative, down to an absolute `floor`.
fn rel_floor(a: &[f64], b: &[f64], floor: f64) -> f64 {
    assert_eq!(a.len(), b.len());
    let scale = b.iter().chain(a).fold(floor, |m, v| m.max(v.abs()));
    if scale == 0.0 {
        return 0.0;
    }
    a.iter()
        .zip(b)
        .fold(0.0f64, |m, (x, y)| m.max((x - y).abs()))
        / scale
}

// ---------------------------------------------------------------------------
// 1. The generated moment Jacobians.

struct Rng(fastrand::Rng);

impl Rng {
    fn new(seed: u64) -> Rng {
        Rng(fastrand::Rng::with_seed(seed))
    }
    fn range(&mut self, lo: f64, hi: f64) -> f64 {
        lo + (hi - lo) * self.0.f64()
    }
}

fn random_linear(r: &mut Rng) -> LinearParams {
    let x0 = r.range(0.0, 6.0);
    let z0 = r.range(-4.0, 3.0);
    LinearParams {
        x0,
        x1: x0 + r.range(1.0, 10.0),
        width: r.range(2.0, 30.0) * if r.0.bool() { 1.0 } else { -1.0 },
        z0,
        z1: z0 + r.range(0.2, 2.0),
        q11: r.range(1.0, 400.0),
        q12: r.range(0.0, 100.0),
        q22: r.range(1.0, 400.0),
        g13: r.range(0.3, 150.0),
        ks: r.range(0.5, 1.2),
    }
}

fn random_prestressed(r: &mut Rng) -> PrestressedParams {
    let l = random_linear(r);
    PrestressedParams {
        x0: l.x0,
        x1: l.x1,
        width: l.width,
        z0: l.z0,
        z1: l.z1,
        eps0: r.range(0.0, 0.5),
        p1: r.range(1.0, 2.0),
        p2: r.range(1.5, 3.0),
        p3: r.range(1.5, 3.0),
        p4: r.range(0.3, 1.0),
        q22: r.range(100.0, 300.0),
        g13: r.range(0.3, 2.0),
        ks: r.range(0.5, 1.2),
    }
}

fn random_gas(r: &mut Rng) -> GasParams {
    let l = random_linear(r);
    GasParams {
        x0: l.x0,
        x1: l.x1,
        width: l.width,
        z0: l.z0,
        z1: l.z1,
    }
}

/// Checks one family's generated `dmoments` against central differences of
/// its `moments`, for every parameter; returns the worst error relative to
/// the derivative's natural scale: the largest slot's derivative plus the
/// largest moment over the parameter's size. (The differences, not the
/// kernels, limit the agreement: the moments hold the bounds to the 11th
/// power and sum terms of both signs, so the differences lose digits to
/// cancellation where a moment hardly depends on the parameter.) A model
/// whose spec takes fewer parameters than the shared struct (`Q < P`: the
/// paper's element without the shear data) has no column for the trailing
/// ones, whose derivatives must then be zero.
fn check_family<const P: usize, const Q: usize, const S: usize, T: Copy>(
    what: &str,
    p: T,
    to: impl Fn(&T) -> [f64; P],
    from: impl Fn([f64; P]) -> T,
    moments: impl Fn(&mut [f64; S], &T),
    dmoments: impl Fn(&T) -> [[f64; S]; Q],
) -> f64 {
    assert!(Q <= P, "{what}: more columns than parameters");
    let v = to(&p);
    let jacobian = dmoments(&p);
    let mut worst: f64 = 0.0;
    for j in 0..P {
        let exact = if j < Q { jacobian[j] } else { [0.0; S] };
        let h = 3e-2 * v[j].abs().max(1.0);
        let mut f = |t: f64| {
            let mut w = v;
            w[j] = t;
            let mut m = [0.0; S];
            moments(&mut m, &from(w));
            m.to_vec()
        };
        let fd = richardson2(&mut f, v[j], h);
        let largest = |v: &[f64]| v.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        let scale = largest(&exact).max(largest(&fd)) + largest(&f(v[j])) / v[j].abs().max(1.0);
        let diff = exact
            .iter()
            .zip(&fd)
            .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
        let e = diff / scale;
        assert!(e <= 1e-9, "{what}: parameter {j}: {e:e}\n{exact:?}\n{fd:?}");
        worst = worst.max(e);
    }
    worst
}

macro_rules! moment_jacobians {
    ($model:ident, $seed:expr) => {{
        use $model as m;
        let mut r = Rng::new($seed);
        let mut worst = [0.0f64; 3];
        for _ in 0..20 {
            worst[0] = worst[0].max(check_family(
                concat!(stringify!($model), " linear"),
                random_linear(&mut r),
                LinearParams::to_values,
                LinearParams::from_values,
                m::linear_moments,
                m::linear_dmoments,
            ));
            worst[1] = worst[1].max(check_family(
                concat!(stringify!($model), " prestressed"),
                random_prestressed(&mut r),
                PrestressedParams::to_values,
                PrestressedParams::from_values,
                m::prestressed_moments,
                m::prestressed_dmoments,
            ));
            worst[2] = worst[2].max(check_family(
                concat!(stringify!($model), " gas"),
                random_gas(&mut r),
                GasParams::to_values,
                GasParams::from_values,
                m::gas_moments,
                m::gas_dmoments,
            ));
        }
        println!(
            "{}: moment Jacobians vs central differences, worst relative error: linear {:.1e}, prestressed {:.1e}, gas {:.1e}",
            stringify!($model),
            worst[0],
            worst[1],
            worst[2]
        );
    }};
}

#[test]
fn moment_jacobians_match_central_differences_of_the_moments() {
    moment_jacobians!(ccm, 11);
    moment_jacobians!(quad, 12);
    moment_jacobians!(shear, 13);
}

/// Random unknowns of the size of a solved element (raw).
fn random_k<M: ElementModel>(r: &mut Rng) -> M::Coeffs {
    let s = M::unscale(13.75);
    M::Coeffs::from_fn(|i| r.range(-0.05, 0.05) * s[i])
}

/// The sensitivities' premise: the energy is linear in the moments, so the
/// gradient kernel at the moments' derivative (built with the trait's
/// `add_*_tangent`) is the derivative of the element gradient with respect
/// to a box parameter; and `scalars_tangent` is its derivative in `kp`.
fn linearity_in_moments<M: ElementModel>(seed: u64) -> f64 {
    let mut r = Rng::new(seed);
    let mut worst: f64 = 0.0;
    for _ in 0..10 {
        let k = random_k::<M>(&mut r);
        let s = EnergyScalars {
            kp: r.range(0.0, 0.3),
        };
        let lin = random_linear(&mut r);
        let pre = random_prestressed(&mut r);
        let gas = random_gas(&mut r);
        let build = |lin: &LinearParams, pre: &PrestressedParams, gas: &GasParams| {
            let mut m = M::zero_moments();
            M::add_linear(&mut m, lin);
            M::add_prestressed(&mut m, pre);
            M::add_gas(&mut m, gas);
            m
        };
        let value_and_gradient = |m: &M::Moments, s: &EnergyScalars| {
            let (v, g) = M::gradient(m, &k, s);
            let mut out = vec![v];
            out.extend_from_slice(g.as_ref());
            out
        };
        // one parameter of each family: z1 of the linear box, eps0 of the
        // prestressed one, x1 of the gas box; and the shear data, g13 of
        // the linear box and ks of the prestressed one (zero derivatives
        // for a model without shear)
        for case in 0..5 {
            let mut dm = M::zero_moments();
            let x = match case {
                0 => {
                    let mut d = LinearParams::from_values([0.0; 10]);
                    d.z1 = 1.0;
                    M::add_linear_tangents(std::slice::from_mut(&mut dm), &lin, &[d]);
                    lin.z1
                }
                1 => {
                    let mut d = PrestressedParams::from_values([0.0; 13]);
                    d.eps0 = 1.0;
                    M::add_prestressed_tangents(std::slice::from_mut(&mut dm), &pre, &[d]);
                    pre.eps0
                }
                3 => {
                    let mut d = LinearParams::from_values([0.0; 10]);
                    d.g13 = 1.0;
                    M::add_linear_tangents(std::slice::from_mut(&mut dm), &lin, &[d]);
                    lin.g13
                }
                4 => {
                    let mut d = PrestressedParams::from_values([0.0; 13]);
                    d.ks = 1.0;
                    M::add_prestressed_tangents(std::slice::from_mut(&mut dm), &pre, &[d]);
                    pre.ks
                }
                _ => {
                    let mut d = GasParams::from_values([0.0; 5]);
                    d.x1 = 1.0;
                    M::add_gas_tangents(std::slice::from_mut(&mut dm), &gas, &[d]);
                    gas.x1
                }
            };
            let exact = value_and_gradient(&dm, &s);
            let mut f = |t: f64| {
                let (mut l, mut p, mut g) = (lin, pre, gas);
                match case {
                    0 => l.z1 = t,
                    1 => p.eps0 = t,
                    3 => l.g13 = t,
                    4 => p.ks = t,
                    _ => g.x1 = t,
                }
                value_and_gradient(&build(&l, &p, &g), &s)
            };
            let fd = richardson(&mut f, x, 1e-3 * x.abs().max(0.1));
            let e = rel_vec(&exact, &fd);
            assert!(e <= 1e-8, "{} case {case}: {e:e}", M::NAME);
            worst = worst.max(e);
        }
        // the load scalar
        let m = build(&lin, &pre, &gas);
        let (v, g) = M::scalars_tangent(&m, &k, &s, &EnergyScalars { kp: 1.0 });
        let mut exact = vec![v];
        exact.extend_from_slice(g.as_ref());
        let mut f = |t: f64| value_and_gradient(&m, &EnergyScalars { kp: t });
        let fd = richardson(&mut f, s.kp, 1e-3);
        let e = rel_vec(&exact, &fd);
        assert!(e <= 1e-8, "{} kp: {e:e}", M::NAME);
        worst = worst.max(e);
    }
    worst
}

#[test]
fn the_gradient_is_linear_in_the_moments() {
    let a = linearity_in_moments::<ccm::Ccm>(21);
    let b = linearity_in_moments::<quad::Quad>(22);
    let c = linearity_in_moments::<shear::Shear>(23);
    println!(
        "gradient at d(moments) vs central differences: ccm {a:.1e}, quad {b:.1e}, shear {c:.1e}"
    );
}

// ---------------------------------------------------------------------------
// 2. Sensitivities of solved fingers against re-solves.

/// The solver settings of the re-solves (tighter than the default).
fn opts() -> SolveOptions {
    SolveOptions {
        rtol: 1e-13,
        ..SolveOptions::default().tip_only()
    }
}

/// The outputs a sensitivity differentiates, for comparison: tip X, tip Z,
/// end angle, energy, then lambda (target solves) and the coefficients.
fn outputs(
    tip: [f64; 2],
    angle: f64,
    energy: f64,
    lambda: Option<f64>,
    k: &Coefficients,
) -> Vec<f64> {
    let mut v = vec![tip[0], tip[1], angle, energy];
    v.extend(lambda);
    v.extend_from_slice(k.as_slice());
    v
}

/// One scene: a finger, a load or a target problem, and its solution.
struct Case {
    name: &'static str,
    model: ModelId,
    actuator: Actuator,
    partition: Partition,
    load: Load,
    target: Option<(TargetProblem, f64)>,
    guess: Coefficients,
    sens: Sensitivities,
}

const CTOL_MM: f64 = 1e-11;

impl Case {
    fn finger(&self, act: &Actuator) -> Finger {
        Finger::with_model(self.model, act, &self.partition, true)
    }

    /// Re-solves with a changed actuator, load or target problem.
    fn solve(&self, act: &Actuator, load: &Load, problem: Option<&TargetProblem>) -> Vec<f64> {
        let finger = self.finger(act);
        match (problem, &self.target) {
            (Some(p), Some((_, lambda))) => {
                let (sol, l) = Solver::new(&finger)
                    .solve_target(p, &self.guess, *lambda, CTOL_MM, &opts())
                    .unwrap_or_else(|e| panic!("{}: target re-solve: {e}", self.name));
                outputs(
                    sol.tip,
                    sol.end_angle,
                    sol.energy,
                    Some(l),
                    &sol.coefficients,
                )
            }
            _ => {
                let sol = finger
                    .solve_from(load, &self.guess, &opts())
                    .unwrap_or_else(|e| panic!("{}: re-solve: {e}", self.name));
                // polished: a solve that stopped just under the tolerance
                // after two Newton steps is off by up to 1e-10 rad, which
                // the differences divide by their step (one more step, where
                // the rounding floor allows it)
                let polish = SolveOptions {
                    rtol: 1e-15,
                    ..opts()
                };
                let sol = finger
                    .solve_from(load, &sol.coefficients, &polish)
                    .unwrap_or(sol);
                outputs(sol.tip, sol.end_angle, sol.energy, None, &sol.coefficients)
            }
        }
    }

    /// The step of the central differences in `param`: relative to the
    /// value, absolute where the value is 0.
    fn step(param: Param, value: f64) -> f64 {
        match param {
            Param::Pressure => 1e-2 * value.abs().max(1.0),
            Param::Fx | Param::Fz => 1e-2 * value.abs().max(0.1),
            Param::Target => 1e-2,
            // the shear data move a pressurised finger's tip by about 1e-6
            // of it and its energy by 1e-11 (no shear force): a longer
            // step keeps the re-solves' rounding out of the differences,
            // and the outputs, rational in ks G13 like C / (ks G13), keep
            // Richardson's error at (h / value)^4 / 4 = 4e-8 of the
            // derivative
            Param::Actuator(ActuatorParam::ShearCorrection | ActuatorParam::ShearModulus(_)) => {
                2e-2 * value.abs()
            }
            _ => 1e-3 * value.abs().max(1e-2),
        }
    }

    /// The central difference of every output in `param`.
    fn central_difference(&self, param: Param, value: f64) -> Vec<f64> {
        let h = Case::step(param, value);
        let problem = self.target.as_ref().map(|t| t.0);
        let mut f = |v: f64| match param {
            Param::Actuator(a) => {
                let act = a
                    .with_value(&self.actuator, v)
                    .unwrap_or_else(|e| panic!("{}: {e}", self.name));
                self.solve(&act, &self.load, problem.as_ref())
            }
            Param::Target => {
                let mut p = problem.expect("a target case");
                p.target = v;
                self.solve(&self.actuator, &self.load, Some(&p))
            }
            _ => {
                let l = match &problem {
                    Some(p) => param.load_with(&p.base, v),
                    None => param.load_with(&self.load, v),
                }
                .expect("a load parameter");
                let p = problem.map(|p| TargetProblem { base: l, ..p });
                self.solve(&self.actuator, &l, p.as_ref())
            }
        };
        richardson(&mut f, value, h)
    }

    /// The shear model's data: ks and each layer's G13.
    fn shear_data(param: Param) -> bool {
        matches!(
            param,
            Param::Actuator(ActuatorParam::ShearCorrection | ActuatorParam::ShearModulus(_))
        )
    }

    /// Every row against central differences; returns the worst relative
    /// agreement per output group (tip, angle, energy, lambda, K) per row.
    ///
    /// Relative to the larger of the two derivatives, down to a floor for
    /// derivatives that vanish (d K / d base.fz of a target solve along Z,
    /// whose load factor takes the change back): the output's own size
    /// output's own size over the parameter's scale (its value, or 100
    /// steps where the value is 0), 1e-7 of the output per unit of it.
    fn check(&self) -> Vec<(Param, [f64; 5])> {
        let mut out = Vec::new();
        let s = &self.sens;
        let base = outputs(s.tip, s.end_angle, s.energy, s.lambda, &self.guess);
        let size = |r: std::ops::Range<usize>| base[r].iter().fold(0.0f64, |m, v| m.max(v.abs()));
        for row in &self.sens.rows {
            let fd = self.central_difference(row.param, row.value);
            let exact = outputs(
                row.tip,
                row.end_angle,
                row.energy,
                row.lambda,
                &row.coefficients,
            );
            let scale = row
                .value
                .abs()
                .max(100.0 * Case::step(row.param, row.value));
            let t = usize::from(row.lambda.is_some());
            // the shear data's derivatives under pressure alone lie below
            // that floor (the energy's at 1e-11 of it per unit): there the
            // differences' own rounding decides, a re-solve's outputs
            // rounded to about 1e-15 of their size, divided by the step
            // and tripled by Richardson's combination, 1e-14 size / h,
            // which is 1e-8 size / h at the tolerance
            let rounding = if Case::shear_data(row.param) {
                1e-8 / Case::step(row.param, row.value)
            } else {
                0.0
            };
            let cmp = |r: std::ops::Range<usize>| {
                let floor = (1e-7 / scale).max(rounding) * size(r.clone());
                rel_floor(&exact[r.clone()], &fd[r.clone()], floor)
            };
            let err = [
                cmp(0..2),
                cmp(2..3),
                cmp(3..4),
                if t == 1 { cmp(4..5) } else { 0.0 },
                cmp(4 + t..exact.len()),
            ];
            out.push((row.param, err));
        }
        out
    }
}

/// A case solved on eight equal elements with ribs: `actuator` at `load`.
fn solved(name: &'static str, model: ModelId, actuator: Actuator, load: Load) -> Case {
    let partition = Partition::equal(110.0, 8).unwrap();
    let finger = Finger::with_model(model, &actuator, &partition, true);
    let sol = finger.solve(&load, &opts()).unwrap();
    // polished like the re-solves: where a derivative is small against
    // its unknowns (the shear strain of a finger under pressure alone
    // nearly vanishes), the equilibrium's own error shows in it
    let polish = SolveOptions {
        rtol: 1e-15,
        ..opts()
    };
    let sol = finger
        .solve_from(&load, &sol.coefficients, &polish)
        .unwrap_or(sol);
    let sens = finger
        .sensitivities(&actuator, &sol, &load, &Param::all(&actuator))
        .unwrap();
    Case {
        name,
        model,
        actuator,
        partition,
        load,
        target: None,
        guess: sol.coefficients,
        sens,
    }
}

/// The standard tip-loaded case: eps0 0.25, Fx 0.939782 N, Fz 0.521707 N, N = 8.
fn tip_loaded(model: ModelId) -> Case {
    let load = Load::unloaded().with_tip_force(0.939782, 0.521707);
    solved("tip-loaded", model, Actuator::paper(0.25).unwrap(), load)
}

/// The standard tip-loaded case in plane strain across the width, under
/// pressure too (the held unknowns must not move with any parameter).
fn tip_loaded_plane_strain(model: ModelId) -> Case {
    let actuator = Actuator::new(fpc::ActuatorParams {
        plane_strain: true,
        ..fpc::ActuatorParams::default()
    })
    .unwrap();
    let load = Load::unloaded()
        .with_pressure_kpa(30.0)
        .with_tip_force(0.939782, 0.521707);
    solved("tip-loaded, plane strain", model, actuator, load)
}

/// The standard tip-loaded case under pressure with ribs on the
/// constraining layer (docs/model.md section 4.10): they stand on H/2, so
/// they move with `actuator.geometry.h`, and they are of the layer's
/// material, so they move with its constants.
fn tip_loaded_cl_ribs(model: ModelId) -> Case {
    let rib = |x0: f64, x1: f64, width: f64, height: f64| fpc::actuator::ClRib {
        x0,
        x1,
        width,
        height,
    };
    let actuator = Actuator::new(fpc::ActuatorParams {
        cl_ribs: vec![rib(20.0, 35.0, 30.0, 0.6), rib(60.0, 61.5, 12.0, 1.0)],
        ..fpc::ActuatorParams::default()
    })
    .unwrap();
    let load = Load::unloaded()
        .with_pressure_kpa(30.0)
        .with_tip_force(0.939782, 0.521707);
    solved("tip-loaded, CL ribs", model, actuator, load)
}

/// A pressurised finger without tip load (the decoupled solve): 50 kPa.
fn pressurised(model: ModelId) -> Case {
    let load = Load::unloaded().with_pressure_kpa(50.0);
    solved("pressurised", model, Actuator::paper(0.25).unwrap(), load)
}

/// Study 8's target solve: the eps0 = 0.15 sample at 27.6 kPa, the force
/// along +Z that moves the tip 10 mm along +Z.
fn target(model: ModelId) -> Case {
    let actuator = Actuator::paper(0.15).unwrap();
    let partition = Partition::equal(110.0, 8).unwrap();
    let finger = Finger::with_model(model, &actuator, &partition, true);
    let d = tip_force_for_displacement(&finger, 27.6, Axis::Z, 10.0).unwrap();
    let base = Load::unloaded().with_pressure_kpa(27.6);
    let problem = TargetProblem {
        base,
        direction: [0.0, 1.0],
        weights: [0.0, 1.0],
        target: d.start_tip[1] + 10.0,
    };
    // tighten the solution to the re-solves' tolerance
    let (sol, lambda) = Solver::new(&finger)
        .solve_target(
            &problem,
            &d.solution.coefficients,
            d.force,
            CTOL_MM,
            &opts(),
        )
        .unwrap();
    let mut params = Param::all(&actuator);
    params.push(Param::Target);
    let sens = finger
        .target_sensitivities(&actuator, &sol, &problem, lambda, &params)
        .unwrap();
    Case {
        name: "target",
        model,
        actuator,
        partition,
        load: problem.load_at(lambda),
        target: Some((problem, lambda)),
        guess: sol.coefficients,
        sens,
    }
}

/// The group a parameter belongs to in the printed summary.
fn group(p: Param) -> &'static str {
    match p {
        Param::Actuator(a) => match a {
            ActuatorParam::Eps0 => "eps0",
            ActuatorParam::PemcE2 | ActuatorParam::Elastic(..) => "moduli",
            ActuatorParam::PsiP1
            | ActuatorParam::PsiP2
            | ActuatorParam::PsiP3
            | ActuatorParam::PsiP4 => "psi law",
            ActuatorParam::H
            | ActuatorParam::H1
            | ActuatorParam::H2
            | ActuatorParam::H3
            | ActuatorParam::ChannelH3a
            | ActuatorParam::ChannelH3b => "thicknesses",
            ActuatorParam::Ly | ActuatorParam::ChannelCy | ActuatorParam::RibsW2 => "widths",
            ActuatorParam::ShearCorrection | ActuatorParam::ShearModulus(_) => "shear",
            ActuatorParam::ClRibWidth(_) | ActuatorParam::ClRibHeight(_) => "CL ribs",
        },
        Param::Pressure | Param::Kappa => "pressure, kappa",
        Param::Fx | Param::Fz => "tip forces",
        Param::Target => "target",
    }
}

/// Largest relative disagreement accepted.
const TOL: f64 = 1e-6;

fn check_case(make: fn(ModelId) -> Case) {
    for &model in ModelId::ALL {
        let case = make(model);
        let rows = case.check();
        let mut groups: Vec<(&str, [f64; 5])> = Vec::new();
        for (p, err) in &rows {
            let g = group(*p);
            match groups.iter_mut().find(|(n, _)| *n == g) {
                Some((_, w)) => {
                    for (w, e) in w.iter_mut().zip(err) {
                        *w = w.max(*e);
                    }
                }
                None => groups.push((g, *err)),
            }
        }
        println!(
            "{} ({model}): worst relative agreement with central differences of re-solves",
            case.name
        );
        println!(
            "  {:<16} {:>9} {:>9} {:>9} {:>9} {:>9}",
            "group", "tip", "angle", "energy", "lambda", "K"
        );
        for (g, w) in &groups {
            println!(
                "  {g:<16} {:>9.1e} {:>9.1e} {:>9.1e} {:>9.1e} {:>9.1e}",
                w[0], w[1], w[2], w[3], w[4]
            );
        }
        for (p, err) in &rows {
            let worst = err.iter().fold(0.0f64, |m, e| m.max(*e));
            assert!(
                worst <= TOL,
                "{} ({model}): {p}: relative disagreement {err:?}",
                case.name
            );
        }
    }
}

#[test]
fn tip_loaded_sensitivities_match_re_solves() {
    check_case(tip_loaded);
}

#[test]
fn plane_strain_sensitivities_match_re_solves() {
    check_case(tip_loaded_plane_strain);
}

#[test]
fn cl_rib_sensitivities_match_re_solves() {
    check_case(tip_loaded_cl_ribs);
}

#[test]
fn pressurised_sensitivities_match_re_solves() {
    check_case(pressurised);
}

#[test]
fn target_sensitivities_match_re_solves() {
    check_case(target);
}

/// The shear data move the shear model's tip, and nothing else's. The
/// shear model's tip departs from the CCM's by a shear deflection that
/// falls like 1 / ks (docs/model.md section 4.8), so `ks d(tip)/d ks` is
/// minus the tips' difference, up to the next term (the deflection over
/// the tip's, a few 1e-3).
#[test]
fn the_shear_data_move_only_the_shear_model() {
    use fpc::actuator::ShearLayer;
    let params: Vec<Param> = [ActuatorParam::ShearCorrection]
        .into_iter()
        .chain(
            ShearLayer::ALL
                .iter()
                .map(|&l| ActuatorParam::ShearModulus(l)),
        )
        .map(Param::Actuator)
        .collect();
    let act = Actuator::paper(0.25).unwrap();
    let part = Partition::equal(110.0, 8).unwrap();
    let load = Load::unloaded().with_tip_force(0.939782, 0.521707);
    let solved = |model: ModelId| {
        let finger = Finger::with_model(model, &act, &part, true);
        let sol = finger.solve(&load, &opts()).unwrap();
        let sens = finger.sensitivities(&act, &sol, &load, &params).unwrap();
        (sol.tip, sens)
    };
    let (ccm_tip, ccm) = solved(ModelId::Ccm);
    for row in &ccm.rows {
        assert_eq!(row.tip, [0.0, 0.0], "ccm: {}", row.param);
        assert_eq!(row.energy, 0.0, "ccm: {}", row.param);
    }
    let (tip, shear) = solved(ModelId::Shear);
    let ks = shear.rows[0].value;
    for c in 0..2 {
        let want = -(tip[c] - ccm_tip[c]);
        let got = ks * shear.rows[0].tip[c];
        println!("tip {c}: ks d(tip)/d ks = {got:.6e} mm, CCM tip - shear tip = {want:.6e} mm");
        assert!((got - want).abs() <= 0.02 * want.abs(), "{got} vs {want}");
    }
    // every layer's G13 stiffens the section: the tip moves back toward
    // the CCM's, the film's most
    let d = |r: &fpc::sensitivity::Sensitivity| {
        r.value * (r.tip[0] * (tip[0] - ccm_tip[0]) + r.tip[1] * (tip[1] - ccm_tip[1]))
    };
    let film = d(&shear.rows[1]);
    for r in &shear.rows[1..] {
        println!(
            "{}: G d(tip)/dG along the shear deflection {:.3e}",
            r.param,
            d(r)
        );
        assert!(d(r) < 0.0 && d(r) >= film, "{}", r.param);
    }
    // the energy holds ks and each G13 only through their products, so
    // sum_l G_l d/dG_l = ks d/dks (two paths through the tangents)
    for c in 0..2 {
        let sum: f64 = shear.rows[1..].iter().map(|r| r.value * r.tip[c]).sum();
        let ks_d = ks * shear.rows[0].tip[c];
        assert!((sum - ks_d).abs() <= 1e-9 * ks_d.abs(), "{sum} vs {ks_d}");
    }
}

// ---------------------------------------------------------------------------
// 3. The API's checks.

#[test]
fn parameters_have_their_scene_names() {
    let act = Actuator::default();
    for p in Param::all(&act) {
        assert_eq!(Param::from_name(&p.name()), Some(p));
        let v = p.value(&act, &Load::unloaded(), None);
        assert!(v.is_some_and(f64::is_finite), "{p}");
    }
    assert_eq!(
        Param::Actuator(ActuatorParam::Eps0).name(),
        "actuator.pemc.eps0"
    );
    assert_eq!(Param::Pressure.name(), "load.pressure_kpa");
    // the default CL is isotropic: e and nu, not e1
    let names: Vec<String> = Param::all(&act).iter().map(|p| p.name()).collect();
    let has = |n: &str| names.iter().any(|m| m == n);
    assert!(has("actuator.cl.e") && has("actuator.emc.e1"));
    assert!(!has("actuator.cl.e1") && !has("actuator.emc.e"));
    // a rib on the constraining layer is named by its list entry
    let p = Param::Actuator(ActuatorParam::ClRibHeight(1));
    assert_eq!(p.name(), "actuator.cl_ribs.list[1].height");
    assert_eq!(Param::from_name("actuator.cl_ribs.list[1].height"), Some(p));
    assert_eq!(Param::from_name("actuator.cl_ribs.list[1].x0"), None);
    assert_eq!(p.value(&act, &Load::unloaded(), None), None);
}

#[test]
fn a_wrong_actuator_or_state_is_rejected() {
    let act = Actuator::paper(0.25).unwrap();
    let finger = Finger::paper(0.25, 8).unwrap();
    let load = Load::unloaded().with_tip_force(0.5, 0.2);
    let sol = finger.solve(&load, &SolveOptions::default()).unwrap();
    let p = [Param::Actuator(ActuatorParam::Eps0)];
    assert!(finger.sensitivities(&act, &sol, &load, &p).is_ok());
    // another actuator
    let other = Actuator::paper(0.3).unwrap();
    let e = finger.sensitivities(&other, &sol, &load, &p).unwrap_err();
    assert!(e.to_string().starts_with("actuator:"), "{e}");
    // not an equilibrium of this load
    let e = finger
        .sensitivities(&act, &sol, &Load::unloaded(), &p)
        .unwrap_err();
    assert!(e.to_string().starts_with("solution:"), "{e}");
    // the target is a parameter of target solves only
    let e = finger
        .sensitivities(&act, &sol, &load, &[Param::Target])
        .unwrap_err();
    assert!(e.to_string().starts_with("target.value:"), "{e}");
    // an orthotropic constant of an isotropic layer
    let e = finger
        .sensitivities(
            &act,
            &sol,
            &load,
            &[Param::Actuator(ActuatorParam::Elastic(
                fpc::actuator::Lamina::Cl,
                fpc::actuator::Elastic::E1,
            ))],
        )
        .unwrap_err();
    assert!(e.to_string().starts_with("actuator.cl.e1:"), "{e}");
}

//! Equilibria: residuals and definite Hessians, the assembled derivatives against finite differences, and an independent gradient-only minimiser.

use argmin::core::{CostFunction, Executor};
use argmin::solver::{linesearch::MoreThuenteLineSearch, quasinewton::LBFGS};

use super::*;

// -------------------------------------------------------- 1. residual, PD

#[test]
fn equilibria_have_tiny_residuals_and_positive_definite_hessians() {
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let s = flat_scales(&finger_scales(&f));
        let n = s.len();
        // the solver's scaled units are the paper's natural scales
        let own = f.unknown_scales();
        assert_eq!(own.len(), n);
        for (i, (a, b)) in own.iter().zip(&s).enumerate() {
            assert!(
                (a - b).abs() <= 1e-15 * b.abs(),
                "eps0 {eps0}: unknown_scales[{i}] = {a:e}, natural scale {b:e}"
            );
        }
        let stiff = f.stiffness_scale();
        for (name, load) in scenes() {
            let sol = solve(&f, &load);
            let what = format!("eps0 {eps0}, {name}");
            assert_eq!(sol.report.reason, Termination::Converged, "{what}");
            assert!(
                sol.report.residual_norm <= 1e-10,
                "{what}: reported residual {:e}",
                sol.report.residual_norm
            );
            assert_eq!(sol.report.coupled, load.has_tip_load(), "{what}");

            // the raw gradient, recomputed: scaled by s it is the residual
            let (v, g) = f.gradient(&load, &sol.coefficients).unwrap();
            let gs: Vec<f64> = g.iter().zip(&s).map(|(g, s)| g * s).collect();
            let r = norm_inf(&gs) / stiff;
            assert!(r <= 1e-10, "{what}: recomputed scaled residual {r:e}");
            // the value returned with the gradient is the reported energy
            assert!(
                (v - sol.energy).abs() <= 1e-12 * (1.0 + sol.energy.abs()),
                "{what}: energy {v} vs {}",
                sol.energy
            );

            // positive definiteness by an independent Cholesky of the raw Hessian
            let (_, _, h) = f.hessian(&load, &sol.coefficients).unwrap();
            assert!(cholesky(n, &h).is_some(), "{what}: raw Hessian not PD");
            // and the reported smallest eigenvalue by another eigen-solver
            let hs = scaled_hessian(&f, &load, &sol.coefficients);
            let sym: Vec<f64> = (0..n * n)
                .map(|idx| 0.5 * (hs[idx] + hs[(idx % n) * n + idx / n]))
                .collect();
            let lam = nalgebra_min_eig(n, &sym) / stiff;
            let reported = sol
                .negative_eigenvalues
                .expect("stability is on by default");
            assert_eq!(reported, 0, "{what}");
            assert!(lam > 0.0, "{what}: min eig {lam:e} (nalgebra)");
            assert_eq!(sol.stable, Some(true));
        }
    }
}

// ------------------------------------------------- 2. assembled derivatives

#[test]
fn assembled_gradient_and_hessian_match_finite_differences() {
    let mut rng = Lcg::new(0x5eed_f1a9);
    // Steps in scaled units, i.e. times each unknown's natural scale (1 for
    // a1, b1; 1/L^2 for a3; 1/L for c2). The Hessian's differences of the
    // gradient are round-off limited at 1e-6 (worst block error 4e-7), so
    // they use 1e-5 (worst 1e-7, truncation still negligible).
    let h = 1e-6;
    let hh = 1e-5;
    let mut worst_g: f64 = 0.0;
    let mut worst_h: f64 = 0.0;
    for n_el in [1usize, 3, 6] {
        for trial in 0..3 {
            let eps0 = EPS0S[trial % 3];
            let f = Finger::paper(eps0, n_el).unwrap();
            let sc = finger_scales(&f);
            let s = flat_scales(&sc);
            let n = 4 * n_el;
            let k = random_coeffs(&mut rng, &f);
            let y = to_scaled(&sc, &k);
            let loaded = Load::unloaded()
                .with_pressure_kpa(rng.range(0.0, 400.0))
                .with_tip_force(rng.range(-2.0, 2.0), rng.range(-2.0, 2.0));
            let unloaded = Load {
                fx: 0.0,
                fz: 0.0,
                ..loaded
            };
            for load in [loaded, unloaded] {
                let what = format!("N {n_el}, trial {trial}, {load:?}");
                let energy = |y: &[f64]| f.energy(&load, &to_raw(&sc, y)).unwrap();
                let grad = |y: &[f64]| -> Vec<f64> {
                    let (_, g) = f.gradient(&load, &to_raw(&sc, y)).unwrap();
                    g.iter().zip(&s).map(|(g, s)| g * s).collect()
                };

                // gradient against central differences of the energy
                let gy = grad(&y);
                let gscale = norm_inf(&gy);
                for j in 0..n {
                    let mut yp = y.clone();
                    let mut ym = y.clone();
                    yp[j] += h;
                    ym[j] -= h;
                    let fd = (energy(&yp) - energy(&ym)) / (2.0 * h);
                    let err = (fd - gy[j]).abs() / gscale;
                    worst_g = worst_g.max(err);
                    assert!(
                        err <= 1e-6,
                        "{what}: dPi/dy[{j}] = {} vs FD {fd} (rel {err:e})",
                        gy[j]
                    );
                }

                // Hessian against central differences of the gradient
                let (_, _, hr) = f.hessian(&load, &k).unwrap();
                for i in 0..n {
                    for j in 0..n {
                        assert_eq!(
                            hr[i + n * j].to_bits(),
                            hr[j + n * i].to_bits(),
                            "{what}: Hessian not exactly symmetric at ({i}, {j})"
                        );
                    }
                }
                let hy: Vec<f64> = (0..n * n)
                    .map(|idx| hr[idx] * s[idx % n] * s[idx / n])
                    .collect();
                let hscale = norm_inf(&hy);
                let mut fdh = vec![0.0; n * n];
                for j in 0..n {
                    let mut yp = y.clone();
                    let mut ym = y.clone();
                    yp[j] += hh;
                    ym[j] -= hh;
                    let (gp, gm) = (grad(&yp), grad(&ym));
                    for i in 0..n {
                        fdh[i + n * j] = (gp[i] - gm[i]) / (2.0 * hh);
                    }
                }
                for bi in 0..n_el {
                    for bj in 0..n_el {
                        let idx = |a: usize, b: usize| (4 * bi + a) + n * (4 * bj + b);
                        let mut bscale: f64 = 0.0;
                        let mut err: f64 = 0.0;
                        for a in 0..4 {
                            for b in 0..4 {
                                bscale = bscale.max(hy[idx(a, b)].abs());
                                err = err.max((hy[idx(a, b)] - fdh[idx(a, b)]).abs());
                            }
                        }
                        if bi != bj {
                            if load.has_tip_load() {
                                // the chain couples every pair of elements
                                assert!(
                                    bscale > 1e-6 * hscale,
                                    "{what}: block ({bi}, {bj}) vanishes ({bscale:e})"
                                );
                            } else {
                                assert_eq!(bscale, 0.0, "{what}: block ({bi}, {bj})");
                                assert_eq!(err, 0.0, "{what}: FD block ({bi}, {bj})");
                                continue;
                            }
                        }
                        let rel = err / bscale;
                        worst_h = worst_h.max(rel);
                        assert!(
                            rel <= 1e-6,
                            "{what}: block ({bi}, {bj}) differs from FD by {err:e} (scale {bscale:e})"
                        );
                    }
                }
            }
        }
    }
    eprintln!("worst relative FD error: gradient {worst_g:.2e}, Hessian block {worst_h:.2e}");
}

// ------------------------------------------------ 3. independent minimiser

/// The finger's energy in scaled unknowns over its stiffness scale (a
/// gradient of order one, whose tolerance is the solver's relative one),
/// through the public raw-coefficient API only (no Hessian: L-BFGS never
/// sees one).
struct ScaledFinger<'a> {
    finger: &'a Finger,
    load: Load,
    s: Vec<Coeffs>,
}

impl CostFunction for ScaledFinger<'_> {
    type Param = Vec<f64>;
    type Output = f64;
    fn cost(&self, y: &Vec<f64>) -> Result<f64, argmin::core::Error> {
        let e = self.finger.energy(&self.load, &to_raw(&self.s, y))?;
        Ok(e / self.finger.stiffness_scale())
    }
}

impl argmin::core::Gradient for ScaledFinger<'_> {
    type Param = Vec<f64>;
    type Gradient = Vec<f64>;
    fn gradient(&self, y: &Vec<f64>) -> Result<Vec<f64>, argmin::core::Error> {
        let (_, gk) = self.finger.gradient(&self.load, &to_raw(&self.s, y))?;
        Ok(gk
            .iter()
            .enumerate()
            .map(|(i, g)| g * self.s[i / 4][i % 4] / self.finger.stiffness_scale())
            .collect())
    }
}

#[test]
fn lbfgs_from_the_straight_finger_reaches_newtons_equilibrium() {
    for (n_el, load) in [
        (8, Load::unloaded()),
        (8, Load::unloaded().with_tip_force(FX, FZ)),
        (4, pressure(100.0).with_tip_force(FX, FZ)),
    ] {
        let f = Finger::paper(0.25, n_el).unwrap();
        let newton = solve(&f, &load);
        let s = finger_scales(&f);
        let p = ScaledFinger {
            finger: &f,
            load,
            s: s.clone(),
        };
        // steps bounded away from the energy's far, unphysical reaches
        let search = MoreThuenteLineSearch::new()
            .with_bounds(f64::EPSILON.sqrt(), 1e2)
            .unwrap();
        let solver = LBFGS::new(search, 10)
            .with_tolerance_grad(1e-11)
            .and_then(|s| s.with_tolerance_cost(0.0))
            .unwrap();
        let result = Executor::new(p, solver)
            .configure(|s| s.param(vec![0.0; 4 * n_el]).max_iters(5000))
            .run()
            .unwrap();
        let what = format!("N {n_el}, {load:?}");
        let state = result.state;
        // converged (the last point), or stopped where its line search
        // meets round-off (the best point)
        let (y, cost) = match state.param {
            Some(y) => (y, state.cost),
            None => (state.best_param.unwrap(), state.best_cost),
        };
        let energy = cost * f.stiffness_scale();
        let k = to_raw(&s, &y);
        let (_, g) = f.gradient(&load, &k).unwrap();
        let gy: Vec<f64> = (0..g.len()).map(|i| g[i] * s[i / 4][i % 4]).collect();
        let g_rel = norm_inf(&gy) / f.stiffness_scale();
        assert!(g_rel <= 1e-10, "{what}: |g| / stiffness {g_rel:e}");
        let (tip, angle) = f.tip(&k).unwrap();
        let dtip = dist(tip, newton.tip);
        let yn = to_scaled(&s, &newton.coefficients);
        let dy = norm_inf(&y.iter().zip(&yn).map(|(a, b)| a - b).collect::<Vec<f64>>());
        eprintln!(
            "{what}: L-BFGS {} iterations, |g| / stiffness {g_rel:.1e}, |tip - newton| = {dtip:.2e} mm, max |dy| = {dy:.2e}",
            state.iter
        );
        assert!(
            dtip <= 1e-6,
            "{what}: tip {tip:?} vs Newton {:?}",
            newton.tip
        );
        assert!(dy <= 1e-7, "{what}: scaled coefficients differ by {dy:e}");
        assert!((angle - newton.end_angle).abs() <= 1e-8, "{what}");
        assert!(
            (energy - newton.energy).abs() <= 1e-12 * newton.energy.abs().max(1.0),
            "{what}: energy {energy} vs {}",
            newton.energy
        );
    }
}

/// The report's step counts say where every iteration went: on seeded
/// random fingers (eps0 0.1-0.5, 0-350 kPa, tip loads up to 1.5 N, N of
/// 1 to 16) the phases add up to the total, a decoupled solve has no
/// coupled steps, continuation iterations come with continuation steps,
/// and the globalisation's counts are among the iterations.
#[test]
fn step_counts_add_up_to_the_iterations() {
    let mut rng = Lcg::new(23);
    let (mut coupled, mut element, mut globalised) = (0, 0, 0);
    for case in 0..60 {
        let eps0 = rng.range(0.1, 0.5);
        let n = [1usize, 2, 4, 8, 16][case % 5];
        let loaded = case % 4 != 0;
        let load = Load {
            pressure: rng.range(0.0, 0.35),
            fx: if loaded { rng.range(-1.5, 1.5) } else { 0.0 },
            fz: if loaded { rng.range(-1.5, 1.5) } else { 0.0 },
            ..Load::default()
        };
        let f = Finger::paper(eps0, n).unwrap();
        let Ok(sol) = f.solve(&load, &SolveOptions::default().tip_only()) else {
            continue;
        };
        let (r, s) = (&sol.report, &sol.report.steps);
        assert_eq!(
            s.element + s.coupled + s.continuation,
            r.iterations,
            "case {case}: {s} against {} iterations",
            r.iterations
        );
        if !r.coupled {
            assert_eq!(s.coupled + s.continuation, 0, "case {case}: {s}");
        }
        if s.continuation > 0 {
            assert!(r.continuation_steps > 0, "case {case}: {s}");
        }
        for k in [s.chord, s.shifted, s.damped, s.grown] {
            assert!(k <= r.iterations, "case {case}: {s}");
        }
        coupled += usize::from(r.coupled && s.coupled > 0);
        element += usize::from(s.element > 0);
        globalised += s.chord + s.shifted + s.damped;
    }
    // the draw reaches every phase
    assert!(
        coupled > 20 && element > 20,
        "{coupled} coupled, {element} with element steps"
    );
    assert!(globalised > 0);
}

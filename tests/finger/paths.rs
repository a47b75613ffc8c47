//! Agreement between solution paths: decoupled and coupled, equal elements, and solvers reusing buffers.

use super::*;

// ------------------------------------------------- 6. decoupled vs coupled

#[test]
fn decoupled_and_coupled_paths_agree_without_tip_load() {
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let sc = finger_scales(&f);
        let zero = f.straight();
        // Both paths stop once the residual is below rtol (relative), which
        // pins the scaled coefficients only to about rtol / min_hessian_eig
        // (2.4e-9 and 0.67 um at the tip for eps0 0.4, 386 kPa at the
        // default 1e-11, where the decoupled residual is 9.7e-12). Agreement to
        // 1e-9 therefore needs a tighter rtol; 1e-14 is still far above the
        // round-off floor of the residual (~1e-17).
        let tight = SolveOptions {
            rtol: 1e-14,
            ..SolveOptions::default()
        };
        for load in [Load::unloaded(), pressure(100.0), pressure(386.0)] {
            let auto = f.solve_from(&load, &zero, &tight).unwrap();
            let coupled = f
                .solve_from(
                    &load,
                    &zero,
                    &SolveOptions {
                        strategy: Strategy::Coupled,
                        ..tight
                    },
                )
                .unwrap();
            let what = format!("eps0 {eps0}, {load:?}");
            assert!(!auto.report.coupled, "{what}");
            assert!(coupled.report.coupled, "{what}");
            let ya = to_scaled(&sc, &auto.coefficients);
            let yc = to_scaled(&sc, &coupled.coefficients);
            let dy = ya
                .iter()
                .zip(&yc)
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(dy <= 1e-9, "{what}: scaled coefficients differ by {dy:e}");
            let dt = dist(auto.tip, coupled.tip);
            assert!(dt <= 1e-9, "{what}: tips differ by {dt:e} mm");
            assert!((auto.end_angle - coupled.end_angle).abs() <= 1e-9, "{what}");
            let de = (auto.energy - coupled.energy).abs();
            assert!(de <= 1e-12 * auto.energy.abs().max(1.0), "{what}: {de:e}");
            assert_eq!(
                auto.negative_eigenvalues, coupled.negative_eigenvalues,
                "{what}: inertia"
            );
        }
    }
}

// ---------------------------------------------------------- 7. equal elements

/// Element `i`'s potential at `load`, and every integral family alone,
/// each with gradient and Hessian, at the element unknowns `k`.
fn element_outputs(f: &Finger, i: usize, load: &Load, k: &[f64]) -> Vec<Vec<f64>> {
    let families = (0..Ccm::FAMILIES.len()).map(Some);
    std::iter::once(None)
        .chain(families)
        .map(|fam| {
            let (v, g, h) = f
                .element_hessian(i, fam, load, k)
                .expect("element and family in range");
            let mut out = vec![v];
            out.extend(g);
            out.extend(h);
            out
        })
        .collect()
}

#[test]
fn equal_elements_without_ribs_have_equal_solutions() {
    let act = Actuator::paper(0.25).unwrap();
    let mut rng = Lcg::new(0x0e9a_1e1e);
    // N = 8: the last element holds the channel's end; N = 22: elements of
    // 5 mm, the last one is the solid wall past the channel.
    for n_el in [8usize, 22] {
        let f = Finger::new(&act, &Partition::equal(110.0, n_el).unwrap(), false);
        let lengths = f.element_lengths();
        // Equal elements have the same energy function: every family's
        // value, gradient and Hessian agree bit for bit at random states
        // (the blocks themselves are compared in src/actuator/blocks.rs's tests).
        let load = pressure(100.0);
        let states = random_coeffs(&mut rng, &f);
        for probe in states.iter().chain(std::iter::once(&[0.0; 4][..])) {
            let first = element_outputs(&f, 0, &load, probe);
            for i in 1..n_el - 1 {
                assert_eq!(lengths[i], lengths[0], "N {n_el}: length of element {i}");
                assert_eq!(
                    element_outputs(&f, i, &load, probe),
                    first,
                    "N {n_el}: element {i} differs from element 0 at {probe:?}"
                );
            }
            assert_ne!(
                element_outputs(&f, n_el - 1, &load, probe),
                first,
                "N {n_el}: the last element is special"
            );
        }
        for load in [Load::unloaded(), pressure(100.0)] {
            // the coupled path solves every element itself (no sharing)
            let coupled = f
                .solve(
                    &load,
                    &SolveOptions {
                        strategy: Strategy::Coupled,
                        ..SolveOptions::default()
                    },
                )
                .unwrap();
            let auto = solve(&f, &load);
            let sc = scales(lengths[0]);
            let k0 = coupled.coefficients.element(0);
            for i in 1..n_el - 1 {
                let ki = coupled.coefficients.element(i);
                for j in 0..4 {
                    let d = (ki[j] - k0[j]).abs() / sc[j];
                    assert!(d <= 1e-12, "N {n_el}, element {i}, unknown {j}: {d:e}");
                }
                assert_eq!(auto.coefficients.element(i), auto.coefficients.element(0));
            }
            let kl = coupled.coefficients.element(n_el - 1);
            assert!(
                (kl[3] - k0[3]).abs() / sc[3] > 1e-6,
                "N {n_el}: the last element should bend differently"
            );
        }
    }
}

/// A solver hands its buffers to the next solver of the same finger
/// (`Finger::solve` builds one per call): what a solve leaves in them must
/// not change the next answer. The same scene after others (a decoupled
/// one, a coupled one from elsewhere) gives bit-identical coefficients and
/// the same report, and so does a copy of the finger. The cold solve after
/// another tip load at the same pressure takes the unloaded start kept
/// from it; after one at another pressure it solves its own; each is
/// compared with a finger built afresh, which keeps nothing (a copy shares
/// its original's workspace).
#[test]
fn reused_solver_buffers_do_not_change_answers() {
    let f = Finger::paper(0.25, 8).unwrap();
    let opts = SolveOptions::default();
    let tip = Load::unloaded().with_tip_force(FX, FZ);
    let first = f.solve(&tip, &opts).unwrap();
    let _ = f.solve(&pressure(200.0), &opts).unwrap();
    let _ = f
        .solve(&Load::unloaded().with_tip_force(-2.0, 3.0), &opts)
        .unwrap();
    // (the last two take the kept unloaded start, and the element pass of
    // its first Hessian kept by the first of them)
    let again = f.solve(&tip, &opts).unwrap();
    assert_eq!(first.coefficients, again.coefficients);
    assert_eq!(first.tip, again.tip);
    assert_eq!(first.report, again.report);
    let copy = f.clone();
    let on_copy = copy.solve(&tip, &opts).unwrap();
    assert_eq!(first.coefficients, on_copy.coefficients);
    // at 120 kPa, after a tip load at 0 kPa, then after another at 120 kPa
    let at = |fx: f64| pressure(120.0).with_tip_force(fx, 0.3);
    let fresh = Finger::paper(0.25, 8)
        .unwrap()
        .solve(&at(0.5), &opts)
        .unwrap();
    let after_other_pressure = f.solve(&at(0.5), &opts).unwrap();
    let _ = f.solve(&at(-0.4), &opts).unwrap();
    let after_same_pressure = f.solve(&at(0.5), &opts).unwrap();
    for s in [&after_other_pressure, &after_same_pressure] {
        assert_eq!(fresh.coefficients, s.coefficients);
        assert_eq!(fresh.energy.to_bits(), s.energy.to_bits());
        assert_eq!(fresh.report, s.report);
    }
}

/// A solve from the rest state (`Finger::solve_from_rest`) is the cold
/// solve given its start. On random fingers and loads (issue 23's draw:
/// eps0 0.1-0.5, 0-350 kPa, tip loads up to 1.5 N per axis, N = 1 to 16,
/// seeded) it converges wherever the cold solve does, in the cold solve's
/// coupled steps (within one: the given start is the cold solve's own up
/// to rounding), to an equilibrium of the ordinary unknowns (the
/// potential's gradient in raw unknowns, without the change of variables,
/// vanishes to the tolerance) at the cold solve's tip; and on the standard
/// tip-loaded finger it factorises fewer Hessians than the same start
/// taken as a guess near the answer (`Finger::solve_from`).
#[test]
fn a_rest_start_is_taken_as_the_cold_solve_takes_its_own() {
    let opts = SolveOptions::default();
    let mut rng = Lcg::new(41);
    let mut solved = 0;
    for case in 0..32 {
        let n = [1, 4, 8, 16][case % 4];
        let eps0 = rng.range(0.1, 0.5);
        let kpa = rng.range(0.0, 350.0);
        let load = pressure(kpa).with_tip_force(rng.range(-1.5, 1.5), rng.range(-1.5, 1.5));
        let f = Finger::paper(eps0, n).unwrap();
        let what = format!("case {case}: N = {n}, eps0 {eps0}, {load:?}");
        let Ok(rest) = f.solve(&pressure(kpa), &opts) else {
            continue;
        };
        let cold = f.solve(&load, &opts);
        let from_rest = f.solve_from_rest(&load, &rest.coefficients, &opts);
        let (cold, from_rest) = match (cold, from_rest) {
            (Ok(c), Ok(r)) => (c, r),
            (Err(_), Err(_)) => continue,
            (c, r) => panic!("{what}: cold {:?}, from rest {:?}", c.err(), r.err()),
        };
        solved += 1;
        let (a, b) = (cold.report.steps, from_rest.report.steps);
        assert!(
            a.coupled.abs_diff(b.coupled) <= 1 && a.continuation == b.continuation,
            "{what}: cold {a}, from rest {b}"
        );
        let residual = scaled_residual(&f, &load, &from_rest.coefficients);
        assert!(
            residual <= 1e-9 * f.stiffness_scale(),
            "{what}: scaled residual {residual:e} against stiffness {}",
            f.stiffness_scale()
        );
        let apart = dist(cold.tip, from_rest.tip);
        assert!(apart <= 1e-6, "{what}: tips {apart:e} mm apart");
    }
    assert!(solved >= 24, "only {solved} of 32 cases solved");
    let f = Finger::paper(0.25, 8).unwrap();
    let rest = f.solve(&Load::unloaded(), &opts).unwrap();
    let load = Load::unloaded().with_tip_force(FX, FZ);
    let from_rest = f.solve_from_rest(&load, &rest.coefficients, &opts).unwrap();
    let near = f.solve_from(&load, &rest.coefficients, &opts).unwrap();
    assert!(dist(from_rest.tip, near.tip) <= 1e-6);
    // accepted steps that are not chord steps each factorise a Hessian
    let factorised = |s: &Solution| s.report.steps.coupled - s.report.steps.chord;
    assert!(
        factorised(&from_rest) < factorised(&near),
        "from rest {}, as a near guess {}",
        from_rest.report.steps,
        near.report.steps
    );
}

/// A looser tolerance costs no more steps from the rest state. The
/// straightened cold solve's chord steps go on to 1 % of the tolerance;
/// after a landing whose Hessian is at hand they start only where two
/// more at the last rate reach that depth. Before that rule the tip-loaded
/// finger on the material partition (27 elements) took six coupled steps
/// at a relative residual of 1e-9, the tolerance of a refinement's first
/// level, four of them chord steps at a rate of about 1e-2, against four
/// at 1e-11; N = 8 took five at 1e-8 against four.
#[test]
fn a_looser_tolerance_takes_no_more_steps_from_rest() {
    let act = Actuator::paper(0.25).unwrap();
    let material = Partition::material(&act, true, act.geometry().lx / 8.0).unwrap();
    assert_eq!(material.len(), 27);
    let load = Load::unloaded().with_tip_force(FX, FZ);
    for f in [
        Finger::new(&act, &material, true),
        Finger::paper(0.25, 8).unwrap(),
    ] {
        let opts = |rtol: f64| SolveOptions {
            rtol,
            ..SolveOptions::default().tip_only()
        };
        let rest = f.solve(&Load::unloaded(), &opts(1e-11)).unwrap();
        let steps = |rtol: f64| {
            let s = f
                .solve_from_rest(&load, &rest.coefficients, &opts(rtol))
                .unwrap();
            assert!(
                s.report.residual_norm <= rtol,
                "N = {}: {}",
                f.len(),
                s.report.steps
            );
            s.report.steps
        };
        let tight = steps(1e-11);
        for rtol in [1e-8, 1e-9, 1e-10] {
            let loose = steps(rtol);
            assert!(
                loose.coupled <= tight.coupled && loose.chord <= tight.chord,
                "N = {}, rtol {rtol:e}: {loose} against {tight} at 1e-11",
                f.len()
            );
        }
    }
}

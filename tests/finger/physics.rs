//! Physical trends and the variational inequality: curl with prestrain, flattening under pressure, the tip under a tip force, energy below perturbed states.

use super::*;

// ---------------------------------------------------------------- 4. physics

#[test]
fn unloaded_finger_curls_towards_minus_z_tighter_with_prestrain() {
    let mut radii = Vec::new();
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let sol = solve(&f, &Load::unloaded());
        assert!(sol.tip[1] < 0.0, "eps0 {eps0}: tip {:?}", sol.tip);
        assert!(sol.end_angle < 0.0, "eps0 {eps0}: {}", sol.end_angle);
        // every element bends the same way
        assert!(sol.coefficients.iter().all(|k| k[3] < 0.0), "eps0 {eps0}");
        let r = sol.radius.expect("a curled finger has a circle fit");
        // independent estimate: deformed arc length over total turning
        let arc: f64 = sol.points.windows(2).map(|w| dist(w[0], w[1])).sum();
        let r_mean = arc / sol.end_angle.abs();
        eprintln!(
            "eps0 {eps0}: tip {:?}, end angle {:.4}, circle fit {r:.3} mm, arc/turning {r_mean:.3} mm",
            sol.tip, sol.end_angle
        );
        assert!(
            (r - r_mean).abs() <= 0.05 * r,
            "eps0 {eps0}: circle fit {r} vs arc/turning {r_mean}"
        );
        radii.push((r, sol.end_angle));
    }
    for w in radii.windows(2) {
        assert!(w[0].0 > w[1].0, "radius must shrink with eps0: {radii:?}");
        assert!(w[0].1 > w[1].1, "turning must grow with eps0: {radii:?}");
    }
}

/// Turning angle (rad) where the tip height of a circular arc of fixed length
/// is extremal: theta sin(theta) = 1 - cos(theta), about 2.331. Tip Z falls
/// while a finger curled past it flattens, and rises below it.
const ARC_Z_EXTREMUM: f64 = 2.3311;

#[test]
fn pressure_flattens_the_finger_monotonically() {
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let sweep: Vec<(f64, Solution, f64)> = (0..=7)
            .map(|i| {
                let kpa = 50.0 * i as f64;
                let sol = solve(&f, &pressure(kpa));
                let v = gas_volume(&f, &sol.coefficients);
                (kpa, sol, v)
            })
            .collect();
        eprintln!("eps0 {eps0}: P (kPa), tip, end angle, radius, gas volume");
        for (kpa, s, v) in &sweep {
            eprintln!(
                "  {kpa:5.0}  ({:8.3}, {:8.3})  {:8.4}  {:>10.3}  {v:.3}",
                s.tip[0],
                s.tip[1],
                s.end_angle,
                s.radius.unwrap_or(f64::INFINITY)
            );
        }
        for w in sweep.windows(2) {
            let ((p0, a, v0), (p1, b, v1)) = (&w[0], &w[1]);
            let what = format!("eps0 {eps0}, {p0} -> {p1} kPa");
            // variational facts: dPi*/dP = -kappa V < 0 and V(P) non-decreasing
            assert!(v1 > v0, "{what}: gas volume {v0} -> {v1}");
            assert!(b.energy < a.energy, "{what}: energy");
            // the finger unbends
            assert!(b.end_angle > a.end_angle, "{what}: end angle");
            if b.end_angle < 0.0 {
                let (ra, rb) = (a.radius.unwrap(), b.radius.unwrap_or(f64::INFINITY));
                assert!(rb > ra, "{what}: radius {ra} -> {rb} while still curled");
            }
            // tip height: rises unless the finger is curled past the arc extremum
            let (ta, tb) = (a.end_angle.abs(), b.end_angle.abs());
            if ta < ARC_Z_EXTREMUM - 0.1 && tb < ARC_Z_EXTREMUM - 0.1 {
                assert!(b.tip[1] > a.tip[1], "{what}: tip Z must rise");
            }
            if ta > ARC_Z_EXTREMUM + 0.1 && tb > ARC_Z_EXTREMUM + 0.1 {
                assert!(b.tip[1] < a.tip[1], "{what}: tip Z must fall (curled past)");
            }
        }
    }
}

#[test]
fn tip_force_along_plus_z_raises_the_tip() {
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let free = solve(&f, &Load::unloaded());
        let mut prev = free.clone();
        for fz in [0.5, 1.0, 1.5, 2.0] {
            let load = Load::unloaded().with_tip_force(0.0, fz);
            let sol = solve(&f, &load);
            let what = format!("eps0 {eps0}, Fz {fz}");
            assert!(sol.tip[1] > prev.tip[1], "{what}: tip Z not monotonic");
            // work inequality: K_F minimises Pi_F and K_0 minimises Pi_0, so
            // 0 <= Pi_0(K_F) - Pi_0(K_0) <= F . (tip_F - tip_0)
            let stored = f.energy(&Load::unloaded(), &sol.coefficients).unwrap() - free.energy;
            let work = fz * (sol.tip[1] - free.tip[1]);
            assert!(stored >= 0.0, "{what}: {stored}");
            assert!(stored <= work, "{what}: stored {stored} > work {work}");
            // where the tip is the outermost point (curl under 90 degrees) the
            // moment of a +Z tip force opens every section: the end angle rises
            let tip_outermost = prev.points.iter().all(|p| p[0] <= prev.tip[0] + 1e-9);
            if tip_outermost {
                assert!(sol.end_angle > prev.end_angle, "{what}: end angle");
            }
            eprintln!(
                "{what}: tip ({:.3}, {:.3}), end angle {:.4}{}",
                sol.tip[0],
                sol.tip[1],
                sol.end_angle,
                if tip_outermost {
                    ""
                } else {
                    " (curled past 90 deg)"
                }
            );
            prev = sol;
        }
    }
    // the general tip load of the brief obeys the same inequality
    for eps0 in EPS0S {
        let f = Finger::paper(eps0, 8).unwrap();
        let free = solve(&f, &Load::unloaded());
        let sol = solve(&f, &Load::unloaded().with_tip_force(FX, FZ));
        let stored = f.energy(&Load::unloaded(), &sol.coefficients).unwrap() - free.energy;
        let work = FX * (sol.tip[0] - free.tip[0]) + FZ * (sol.tip[1] - free.tip[1]);
        assert!(
            0.0 <= stored && stored <= work,
            "eps0 {eps0}: {stored} {work}"
        );
    }
}

#[test]
fn equilibrium_energy_is_below_perturbed_states() {
    let mut rng = Lcg::new(0xbeef_0042);
    let f = Finger::paper(0.25, 8).unwrap();
    let sc = finger_scales(&f);
    let n = 4 * f.len();
    for (name, load) in scenes() {
        let sol = solve(&f, &load);
        assert_eq!(sol.negative_eigenvalues, Some(0), "{name}");
        let y0 = to_scaled(&sc, &sol.coefficients);
        let hs = scaled_hessian(&f, &load, &sol.coefficients);
        for _ in 0..20 {
            let d: Vec<f64> = (0..n).map(|_| rng.range(-1e-3, 1e-3)).collect();
            let y: Vec<f64> = y0.iter().zip(&d).map(|(a, b)| a + b).collect();
            let de = f.energy(&load, &to_raw(&sc, &y)).unwrap() - sol.energy;
            assert!(de > 0.0, "{name}: perturbation lowers the energy by {de:e}");
            // and the rise is the quadratic form of the Hessian (third order ~ |d|)
            let q: f64 = 0.5
                * (0..n)
                    .map(|j| (0..n).map(|i| d[i] * hs[i + n * j]).sum::<f64>() * d[j])
                    .sum::<f64>();
            assert!(
                (de - q).abs() <= 0.02 * q,
                "{name}: energy rise {de:e} vs 1/2 d^T H d = {q:e}"
            );
        }
    }
}

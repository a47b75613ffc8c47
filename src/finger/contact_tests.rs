//! The self-contact check's clearance proof (src/validity/clearance.rs)
//! on solved fingers: its bounds against dense samples of the mid-plane,
//! and its verdict against the search it skips.

use super::{CoreVisitor, Finger, FingerCore, Load, SolveOptions};
use crate::element;
use crate::model::ElementModel;
use crate::validity::{contact_turning, proof_and_search, proof_pieces, scan_matches_elements};
use crate::{Actuator, ActuatorParams, ModelId, Partition};

/// Solved states of random fingers (three models, 1-128 elements,
/// prestrains 0.1-0.5, pressures to 300 kPa, tip loads to 1.5 N): the
/// finger, its state, its thickness, and whether it turns past
/// [`contact_turning`].
fn random_states(count: usize) -> Vec<(Finger, Vec<f64>, f64, bool)> {
    let mut rng = fastrand::Rng::with_seed(7);
    let mut out = Vec::new();
    for case in 0..count {
        let model = [ModelId::Ccm, ModelId::Quad, ModelId::Shear][case % 3];
        let n = [1, 2, 4, 8, 16, 64, 128][rng.usize(0..7)];
        let mut params = ActuatorParams::default();
        params.pemc.eps0 = 0.1 + 0.4 * rng.f64();
        let act = Actuator::new(params).unwrap();
        let part = Partition::equal(act.geometry().lx, n).unwrap();
        let finger = Finger::with_model(model, &act, &part, true);
        let load = Load::unloaded()
            .with_pressure_kpa(300.0 * rng.f64())
            .with_tip_force(3.0 * rng.f64() - 1.5, 3.0 * rng.f64() - 1.5);
        if let Ok(sol) = finger.solve(&load, &SolveOptions::default().tip_only()) {
            let turned = sol.end_angle.abs() > contact_turning();
            out.push((
                finger,
                sol.coefficients.as_slice().to_vec(),
                act.geometry().h,
                turned,
            ));
        }
    }
    out
}

/// The proof's bounds hold: every piece's box holds its mid-plane and its
/// cone the tangents (dense samples, in the finger's frame), and no
/// segment of the search is longer than the bound on it.
#[test]
fn the_clearance_bounds_hold_the_sampled_midplane() {
    struct Bounds<'a>(&'a [f64], f64);
    impl CoreVisitor for Bounds<'_> {
        type Output = usize;
        fn visit<M: ElementModel>(self, core: &FingerCore<M>) -> usize {
            let (k, h) = (self.0, self.1);
            let els = &core.elements;
            let Some((pieces, chord, longest)) = proof_pieces(els, k, h) else {
                return 0;
            };
            assert!(
                longest <= chord * (1.0 + 1e-12),
                "segment {longest} > bound {chord}"
            );
            let cross = |a: [f64; 2], b: [f64; 2]| a[0] * b[1] - a[1] * b[0];
            let frames = element::walk::frames(els, k);
            let mut next = 0;
            // the pieces follow one another along the whole finger
            let mut at = (0, 0.0);
            for &(lo, hi, [cw, ccw], from, to) in &pieces {
                next += 1;
                assert_eq!(from, at, "piece {next} starts where the last ended");
                at = if to.1 >= els[to.0].length() * (1.0 - 1e-12) {
                    (to.0 + 1, 0.0)
                } else {
                    to
                };
                for i in from.0..=to.0 {
                    let (e, (p, [c, s])) = (&els[i], frames[i]);
                    let ki = element::coeffs::<M>(k, i);
                    let x0 = if i == from.0 { from.1 } else { 0.0 };
                    let x1 = if i == to.0 { to.1 } else { e.length() };
                    for t in 0..=50 {
                        let x = x0 + (x1 - x0) * t as f64 / 50.0;
                        let [xl, zl] = M::midplane(&ki, x);
                        let g = [p[0] + c * xl - s * zl, p[1] + s * xl + c * zl];
                        for a in 0..2 {
                            let tol = 1e-9 * (1.0 + g[a].abs());
                            assert!(g[a] >= lo[a] - tol && g[a] <= hi[a] + tol);
                        }
                        let [dx, dz] = M::tangent(&ki, x);
                        let v = [c * dx - s * dz, s * dx + c * dz];
                        let tol = 1e-9 * dx.hypot(dz);
                        assert!(cross(cw, v) >= -tol * cw[0].hypot(cw[1]));
                        assert!(cross(v, ccw) >= -tol * ccw[0].hypot(ccw[1]));
                    }
                }
            }
            assert_eq!(at, (els.len(), 0.0), "the pieces cover the finger");
            1
        }
    }

    let states = random_states(90);
    let bounded: usize = states
        .iter()
        .map(|(f, k, h, _)| f.visit_core(Bounds(k, *h)))
        .sum();
    assert!(
        bounded * 10 >= states.len() * 8,
        "{bounded} of {}",
        states.len()
    );
}

/// Wherever the clearance proof skips the search, the search (run anyway)
/// finds nothing, at the laminate's thickness and at thicknesses up to 60
/// times it in steps of 15 % (which bring parts of a curl into contact);
/// and at a thickness just over each contact found, where the contact sits
/// at the edge of the search's test, the proof does not skip it. The proof
/// must also settle most curled states at the real thickness, or it saves
/// nothing.
#[test]
fn the_clearance_proof_never_hides_a_finding() {
    struct Compare<'a>(&'a [f64], f64);
    impl CoreVisitor for Compare<'_> {
        type Output = (bool, Option<f64>);
        fn visit<M: ElementModel>(self, core: &FingerCore<M>) -> (bool, Option<f64>) {
            let (k, h) = (self.0, self.1);
            let stretch: Vec<f64> = (0..core.elements.len())
                .map(|i| {
                    let ki = element::coeffs::<M>(k, i);
                    let l = core.elements[i].length();
                    (0..=8)
                        .map(|j| {
                            let [dx, dz] = M::tangent(&ki, l * j as f64 / 8.0);
                            dx.hypot(dz)
                        })
                        .fold(0.0, f64::max)
                })
                .collect();
            proof_and_search(&core.elements, k, &stretch, h)
        }
    }

    let (mut curled, mut cleared_at_h, mut found_any, mut checked, mut at_edge) = (0, 0, 0, 0, 0);
    for (case, (finger, k, h, turned)) in random_states(240).iter().enumerate() {
        let (model, n, h, k) = (finger.model(), finger.len(), *h, k.as_slice());
        for scale in (0..30).map(|i| 1.15f64.powi(i)) {
            let (cleared, found) = finger.visit_core(Compare(k, h * scale));
            checked += 1;
            let what = format!("case {case} ({model:?}, N = {n}, H x {scale:.3})");
            assert!(
                !(cleared && found.is_some()),
                "{what}: cleared, yet the search finds contact"
            );
            if let Some(d) = found {
                // at a thickness just over the closest approach (the
                // mid-plane sampled afresh for it), a contact at the edge
                // of the search's test
                found_any += 1;
                let edge = d * (1.0 + 1e-3);
                let (cleared, again) = finger.visit_core(Compare(k, edge));
                if again.is_some() {
                    at_edge += 1;
                    assert!(!cleared, "{what}: cleared at H = {edge}, closest {d}");
                }
            }
            if scale == 1.0 && *turned {
                curled += 1;
                cleared_at_h += usize::from(cleared);
            }
        }
    }
    assert!(
        checked > 1000 && found_any > 20 && at_edge > 20,
        "{checked} checked, {found_any} with contact, {at_edge} at the edge"
    );
    assert!(
        cleared_at_h * 4 >= curled * 3 && curled > 30,
        "the proof settled {cleared_at_h} of {curled} curled states"
    );
    eprintln!("{checked} checked, {found_any} with contact, {at_edge} at the edge, {cleared_at_h} of {curled} curled settled");
}

/// The validity check scans up to eight elements side by side in vector
/// lanes: every element's extremes are those of a scalar loop over it
/// alone, bit for bit, on solved states of random fingers (1-128 elements,
/// so full and partial groups of lanes) and on those states disturbed
/// (tangents that turn backwards, strains past the limits), at 1-9 check
/// points per element.
#[test]
fn the_lane_scan_is_each_element_s_own() {
    struct Scan<'a>(&'a [f64], usize);
    impl CoreVisitor for Scan<'_> {
        type Output = bool;
        fn visit<M: ElementModel>(self, core: &FingerCore<M>) -> bool {
            let lam = core.laminate();
            let z = [lam.pemc_z.0, lam.pemc_z.1];
            scan_matches_elements(&core.elements, self.0, self.1, z, lam.eps0)
        }
    }
    let mut rng = fastrand::Rng::with_seed(19);
    for (case, (finger, k, _, _)) in random_states(60).into_iter().enumerate() {
        let shaken: Vec<f64> = k
            .iter()
            .map(|v| v * (1.0 + 4.0 * (rng.f64() - 0.5)))
            .collect();
        for state in [&k, &shaken] {
            let samples = 1 + case % 9;
            assert!(finger.visit_core(Scan(state, samples)), "case {case}");
        }
    }
}

/// The end angle a solution reports (from the validity check after a
/// solve, and from `element::walk::tip_and_end_angle` after a tip-only level: one
/// `atan2` of the chained rotation, on the branch of the approximate
/// turns) is the sum of the elements' end slopes within rounding, on
/// random solved fingers of all three models, some curled past half a
/// turn; and the tip both report is the chain walk's, bit for bit.
#[test]
fn the_end_angle_is_the_sum_of_the_element_slopes() {
    struct Angles<'a>(&'a [f64]);
    impl CoreVisitor for Angles<'_> {
        type Output = [f64; 3];
        fn visit<M: ElementModel>(self, core: &FingerCore<M>) -> [f64; 3] {
            let (els, k) = (&core.elements, self.0);
            let sum = (0..els.len())
                .map(|i| els[i].end(&element::coeffs::<M>(k, i))[2])
                .sum();
            let (_, tip, checked) = crate::validity::check(els, &core.laminate(), k, 4);
            let (walked_tip, walked) = element::walk::tip_and_end_angle(els, k);
            // the tip, bit for bit that of the chain's walk
            let at = element::walk::walk(els, |i| element::coeffs::<M>(k, i), |_, _, _, _| {});
            assert_eq!(tip.map(f64::to_bits), at.map(f64::to_bits));
            assert_eq!(walked_tip.map(f64::to_bits), at.map(f64::to_bits));
            [sum, walked, checked]
        }
    }
    let mut past_half = 0;
    for (case, (finger, k, _, _)) in random_states(120).iter().enumerate() {
        let [sum, walked, checked] = finger.visit_core(Angles(k));
        for got in [walked, checked] {
            let off = (got - sum).abs();
            assert!(
                off <= 1e-13 * sum.abs().max(1.0),
                "case {case}: {got} vs {sum}"
            );
        }
        past_half += usize::from(sum.abs() > std::f64::consts::PI);
    }
    assert!(past_half >= 5, "{past_half}");
}

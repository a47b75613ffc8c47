//! The element potentials, gradients and Hessians in lanes (src/lanes.rs, `ElementLanes` in
//! src/element.rs) and the end kinematics' derivatives in lanes against
//! the scalar kernels, bit for bit, on the elements of real fingers.

use super::FingerCore;
use crate::element::packed::{ElementLanes, HessianGroups};
use crate::element::{self, Element};
use crate::lanes::{Lanes, Width};
use crate::model::{ElementModel, EnergyScalars, Vector};
use crate::{Actuator, ActuatorParams, Partition};
use proptest::prelude::*;
use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};

/// The elements of the default actuator on `n` equal elements, in
/// plane stress or plane strain.
fn elements<M: ElementModel>(n: usize, plane_strain: bool) -> Vec<Element<M>> {
    let act = Actuator::new(ActuatorParams {
        plane_strain,
        ..ActuatorParams::default()
    })
    .unwrap();
    let part = Partition::equal(act.geometry().lx, n).unwrap();
    FingerCore::<M>::new(&act, &part, true).elements
}

/// Every width this processor runs gives every element's potential,
/// gradient and Hessian bit for bit as the scalar kernels do, at
/// random unknowns and pressures, for every model, in plane stress and
/// plane strain, with the last batch partly filled (the Hessians in
/// groups, whose lanes past the last element repeat it); and so do the
/// end kinematics' derivatives on eight lanes and on one.
fn lanes_are_the_scalar_kernels<M: ElementModel>() {
    let mut runner = TestRunner::new_with_rng(
        Config {
            cases: 40,
            ..Config::default()
        },
        TestRng::deterministic_rng(RngAlgorithm::ChaCha),
    );
    let n = M::Coeffs::LEN;
    let strategy = (
        1usize..=19,
        any::<bool>(),
        prop::collection::vec(-0.3f64..0.3, n * 19),
        0.0f64..3.0,
    );
    runner
        .run(&strategy, |(ne, plane_strain, raw, kp)| {
            let els = elements::<M>(ne, plane_strain);
            let k: Vec<M::Coeffs> = (0..ne)
                .map(|i| M::Coeffs::from_fn(|j| raw[n * i + j]))
                .collect();
            let s = EnergyScalars { kp };
            let (nh, w) = (M::Upper::LEN, fpc_newton::GROUP);
            for width in Width::ALL.into_iter().filter(|w| w.is_supported()) {
                let lanes = ElementLanes::new(&els, width);
                prop_assert_eq!(lanes.width(), width);
                let mut ev = vec![0.0; ne];
                let mut eg = vec![(0.0, M::Coeffs::zero()); ne];
                // (filled with NaN: every lane must be written)
                let mut hg = HessianGroups::new::<M>(ne);
                for x in
                    hg.v.iter_mut()
                        .chain(hg.g.iter_mut())
                        .chain(hg.h.iter_mut())
                {
                    *x = Lanes([f64::NAN; 8]);
                }
                lanes.eval::<element::packed::Value>(&els, &k, &s, &mut ev);
                lanes.eval::<element::packed::Gradient>(&els, &k, &s, &mut eg);
                lanes.hessian_groups(&els, &k, &s, &mut hg);
                let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                for (i, (e, k)) in els.iter().zip(&k).enumerate() {
                    let at = format!("{} element {i}", width.name());
                    prop_assert_eq!(ev[i].to_bits(), e.energy(k, &s).to_bits(), "{}", at);
                    let (v, g) = e.gradient(k, &s);
                    prop_assert_eq!(eg[i].0.to_bits(), v.to_bits(), "{}", at);
                    prop_assert_eq!(bits(eg[i].1.as_ref()), bits(g.as_ref()), "{}", at);
                    let (v, g, h) = e.hessian(k, &s);
                    // element i and, past the last element, the lanes
                    // that repeat it
                    let lanes = if i + 1 == ne {
                        i % w..w
                    } else {
                        i % w..i % w + 1
                    };
                    let j = i / w;
                    for l in lanes {
                        let lane = |x: &[Lanes<8>]| x.iter().map(|x| x.0[l]).collect::<Vec<_>>();
                        prop_assert_eq!(hg.v[j].0[l].to_bits(), v.to_bits(), "{}", at);
                        let gl = lane(&hg.g[j * n..(j + 1) * n]);
                        prop_assert_eq!(bits(&gl), bits(g.as_ref()), "{}", at);
                        let hl = lane(&hg.h[j * nh..(j + 1) * nh]);
                        prop_assert_eq!(bits(&hl), bits(h.as_ref()), "{}", at);
                    }
                }
            }
            // the end kinematics' derivatives, eight elements at a time
            // (the last group's lanes repeating its last) and one by one
            let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
            for c in (0..ne).step_by(8) {
                let at = |l: usize| (c + l).min(ne - 1);
                let kl: Vec<Lanes<8>> = (0..n)
                    .map(|a| Lanes(std::array::from_fn(|l| k[at(l)][a])))
                    .collect();
                let length = Lanes(std::array::from_fn(|l| els[at(l)].length()));
                let (mut g8, mut h8) =
                    (vec![Lanes([0.0; 8]); 3 * n], vec![Lanes([0.0; 8]); 3 * nh]);
                M::end_derivatives_lanes(&kl, length, &mut g8, &mut h8);
                for l in 0..8 {
                    let e = &els[at(l)];
                    let (dg, dh) = e.end_derivatives(&k[at(l)]);
                    let (mut g1, mut h1) = (vec![0.0; 3 * n], vec![0.0; 3 * nh]);
                    M::end_derivatives_lanes(k[at(l)].as_ref(), e.length(), &mut g1, &mut h1);
                    let want_g: Vec<u64> = dg.iter().flat_map(|d| bits(d.as_ref())).collect();
                    let want_h: Vec<u64> = dh.iter().flat_map(|d| bits(d.as_ref())).collect();
                    let lane8 =
                        |x: &[Lanes<8>]| x.iter().map(|x| x.0[l].to_bits()).collect::<Vec<_>>();
                    prop_assert_eq!(&lane8(&g8), &want_g, "element {}", at(l));
                    prop_assert_eq!(&lane8(&h8), &want_h, "element {}", at(l));
                    prop_assert_eq!(&bits(&g1), &want_g, "element {}", at(l));
                    prop_assert_eq!(&bits(&h1), &want_h, "element {}", at(l));
                }
            }
            Ok(())
        })
        .unwrap();
}

#[test]
fn lanes_are_the_scalar_kernels_for_every_model() {
    lanes_are_the_scalar_kernels::<crate::model::ccm::Ccm>();
    lanes_are_the_scalar_kernels::<crate::model::quad::Quad>();
    lanes_are_the_scalar_kernels::<crate::model::shear::Shear>();
}

/// A width the processor lacks falls back to the widest it has below.
#[test]
fn an_unsupported_width_falls_back() {
    let els = elements::<crate::model::ccm::Ccm>(5, false);
    let w = ElementLanes::new(&els, Width::EightAvx512).width();
    assert!(w.is_supported());
    assert_eq!(w == Width::EightAvx512, Width::EightAvx512.is_supported());
    assert_eq!(ElementLanes::new(&els, Width::One).width(), Width::One);
}

/// Whole solves (unloaded, pressurised, tip-loaded cold and warm, three
/// models) are the same at every width.
#[test]
fn solves_are_the_same_at_every_width() {
    use crate::{Finger, Load, ModelId, SolveOptions};
    let act = Actuator::paper(0.3).unwrap();
    let opts = SolveOptions::default();
    for model in [ModelId::Ccm, ModelId::Quad, ModelId::Shear] {
        let part = Partition::equal(act.geometry().lx, 11).unwrap();
        let base = Finger::with_model(model, &act, &part, true);
        let solve = |f: &Finger| {
            let p = Load::unloaded().with_pressure_kpa(120.0);
            let un = f.solve(&p, &opts).unwrap();
            let cold = f
                .solve_from(&p.with_tip_force(0.6, 0.4), &un.coefficients, &opts)
                .unwrap();
            let warm = f
                .solve_from(&p.with_tip_force(0.5, 0.45), &cold.coefficients, &opts)
                .unwrap();
            (un, cold, warm)
        };
        let scalar = solve(&base.with_lane_width(Width::One));
        assert_eq!(base.with_lane_width(Width::One).lane_width(), Width::One);
        for width in Width::ALL.into_iter().filter(|w| w.is_supported()) {
            let f = base.with_lane_width(width);
            assert_eq!(f.lane_width(), width);
            assert!(solve(&f) == scalar, "{model:?} at {}", width.name());
        }
    }
}

//! The element potentials, gradients and Hessians in lanes (src/lanes.rs, `ElementLanes` in
//! src/element.rs) against the scalar kernels, bit for bit, on the
//! elements of real fingers.

use super::FingerCore;
use crate::element::{self, Element, ElementLanes};
use crate::lanes::Width;
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
/// plane strain, with the last batch partly filled.
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
            let zero = (0.0, M::Coeffs::zero(), M::Upper::zero());
            for width in Width::ALL.into_iter().filter(|w| w.is_supported()) {
                let lanes = ElementLanes::new(&els, width);
                prop_assert_eq!(lanes.width(), width);
                let mut ev = vec![0.0; ne];
                let mut eg = vec![(0.0, M::Coeffs::zero()); ne];
                let mut eh = vec![zero; ne];
                lanes.eval::<element::Value>(&els, &k, &s, &mut ev);
                lanes.eval::<element::Gradient>(&els, &k, &s, &mut eg);
                lanes.eval::<element::Hessian>(&els, &k, &s, &mut eh);
                let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
                for (i, (e, k)) in els.iter().zip(&k).enumerate() {
                    let at = format!("{} element {i}", width.name());
                    prop_assert_eq!(ev[i].to_bits(), e.energy(k, &s).to_bits(), "{}", at);
                    let (v, g) = e.gradient(k, &s);
                    prop_assert_eq!(eg[i].0.to_bits(), v.to_bits(), "{}", at);
                    prop_assert_eq!(bits(eg[i].1.as_ref()), bits(g.as_ref()), "{}", at);
                    let (v, g, h) = e.hessian(k, &s);
                    prop_assert_eq!(eh[i].0.to_bits(), v.to_bits(), "{}", at);
                    prop_assert_eq!(bits(eh[i].1.as_ref()), bits(g.as_ref()), "{}", at);
                    prop_assert_eq!(bits(eh[i].2.as_ref()), bits(h.as_ref()), "{}", at);
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

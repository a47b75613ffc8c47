//! The integration blocks of each element, rebuilt from the actuator's
//! public description for the benchmarks (the library's own block
//! construction, `element_blocks`, is crate-private): the linear laminae
//! over each element whole, the channel clipped to it (a negative-width
//! fluidic box and a gas box), the ribs clipped to it (fluidic boxes and
//! negative-width gas boxes), and the prestressed layer, in the library's
//! order (docs/model.md sections 4.3 and 4.4).
//!
//! [`check_against_finger`] compares the rebuilt elements with the
//! finger's own through the public `Finger::element_hessian`, so a bench
//! that times them provably times the library's elements.

#![allow(dead_code)] // each bench uses part of this

use fpc::actuator::Rib;
use fpc::model::ElementModel;
use fpc::model::{EnergyScalars, GasParams, LinearParams, PrestressedParams, Vector};
use fpc::{Actuator, Finger, Load, Partition};

/// Clipped boxes shorter than this fraction of the element are dropped
/// (the library's rule).
const MIN_BLOCK_FRACTION: f64 = 1e-12;

/// One element's boxes, by family.
#[derive(Debug, Clone)]
pub struct Blocks {
    pub length: f64,
    pub linear: Vec<LinearParams>,
    pub prestressed: Vec<PrestressedParams>,
    pub gas: Vec<GasParams>,
}

/// [gx0, gx1] clipped to the element [start, start + len], in local
/// coordinates; exactly 0 or `len` where the box covers an end.
fn clip(gx0: f64, gx1: f64, start: f64, len: f64) -> Option<(f64, f64)> {
    let end = start + len;
    let x0 = if gx0 <= start { 0.0 } else { gx0 - start };
    let x1 = if gx1 >= end { len } else { gx1 - start };
    (x1 - x0 > MIN_BLOCK_FRACTION * len).then_some((x0, x1))
}

/// The blocks of every element of `part`, root to tip.
pub fn element_blocks(act: &Actuator, part: &Partition, ribs: bool) -> Vec<Blocks> {
    let layers = act.linear_layers();
    let fq = act.fluidic_q();
    let (pz0, pz1) = act.pemc_z();
    let (cz0, cz1) = act.channel_z();
    let channel = act.channel();
    let pemc = act.pemc();
    let rib_list: &[Rib] = if ribs { act.ribs() } else { &[] };
    let width = act.geometry().ly;
    let ks = act.shear_correction();
    let fluidic_g13 = act.g13(fpc::actuator::ShearLayer::Fluidic);
    let fluidic = |x0: f64, x1: f64, width: f64| LinearParams {
        x0,
        x1,
        z0: cz0,
        z1: cz1,
        width,
        q11: fq.q11,
        q12: fq.q12,
        q22: fq.q22,
        g13: fluidic_g13,
        ks,
    };
    let gas = |x0: f64, x1: f64, width: f64| GasParams {
        x0,
        x1,
        z0: cz0,
        z1: cz1,
        width,
    };
    part.lengths()
        .iter()
        .zip(part.starts())
        .map(|(&len, &start)| {
            let mut b = Blocks {
                length: len,
                linear: layers
                    .iter()
                    .map(|l| LinearParams {
                        x0: 0.0,
                        x1: len,
                        z0: l.z0,
                        z1: l.z1,
                        width,
                        q11: l.q.q11,
                        q12: l.q.q12,
                        q22: l.q.q22,
                        g13: l.g13,
                        ks,
                    })
                    .collect(),
                prestressed: vec![PrestressedParams {
                    x0: 0.0,
                    x1: len,
                    z0: pz0,
                    z1: pz1,
                    width,
                    eps0: pemc.eps0,
                    p1: pemc.law.p1,
                    p2: pemc.law.p2,
                    p3: pemc.law.p3,
                    p4: pemc.law.p4,
                    q22: pemc.q22(),
                    g13: act.g13(fpc::actuator::ShearLayer::Pemc),
                    ks,
                }],
                gas: Vec::new(),
            };
            if let Some((x0, x1)) = clip(0.0, channel.cx, start, len) {
                b.linear.push(fluidic(x0, x1, -channel.cy));
                b.gas.push(gas(x0, x1, channel.cy));
            }
            for rib in rib_list {
                if let Some((x0, x1)) = clip(rib.x0, rib.x1, start, len) {
                    b.linear.push(fluidic(x0, x1, rib.width));
                    b.gas.push(gas(x0, x1, -rib.width));
                }
            }
            b
        })
        .collect()
}

/// The element's blocks folded into model `M`'s moments.
pub fn moments<M: ElementModel>(b: &Blocks) -> M::Moments {
    let mut m = M::zero_moments();
    for p in &b.linear {
        M::add_linear(&mut m, p);
    }
    for p in &b.prestressed {
        M::add_prestressed(&mut m, p);
    }
    for p in &b.gas {
        M::add_gas(&mut m, p);
    }
    m
}

/// Panics unless the rebuilt elements have the finger's lengths and, at
/// `k` and the load's pressure, the finger's element potential, gradient
/// and Hessian (to 1e-12 of each array's largest entry).
pub fn check_against_finger<M: ElementModel>(
    blocks: &[Blocks],
    finger: &Finger,
    load: &Load,
    k: &M::Coeffs,
) {
    assert_eq!(finger.model().name(), M::NAME);
    assert_eq!(blocks.len(), finger.len());
    let s = EnergyScalars {
        kp: load.kappa * load.pressure,
    };
    for (i, b) in blocks.iter().enumerate() {
        assert_eq!(b.length, finger.element_lengths()[i], "element {i}: length");
        let (v, g, h) = M::hessian(&moments::<M>(b), k, &s);
        let (fv, fg, fh) = finger
            .element_hessian(i, None, load, k.as_ref())
            .expect("element in range");
        for (what, got, want) in [
            ("value", &[v][..], &[fv][..]),
            ("gradient", g.as_ref(), &fg[..]),
            ("Hessian", h.as_ref(), &fh[..]),
        ] {
            let scale = want.iter().fold(0.0f64, |m, w| m.max(w.abs()));
            for (a, b) in got.iter().zip(want) {
                assert!(
                    (a - b).abs() <= 1e-12 * scale,
                    "element {i}: the rebuilt blocks' {what} {a:e} differs from the finger's {b:e}"
                );
            }
        }
    }
    // one unknown vector per element
    assert_eq!(M::Coeffs::LEN, finger.unknowns_per_element());
}

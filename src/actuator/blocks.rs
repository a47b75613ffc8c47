//! The actuator cut into integration blocks, element by element
//! (docs/model.md section 4.4), and the partition on its material changes.
//!
//! An element's strain energy and gas volume are sums of integrals over
//! boxes: x over a sub-interval [x0, x1] of the element (local
//! coordinate, 0 <= x0 < x1 <= L_i), z over [z0, z1], and a width in y
//! that is a plain factor because nothing depends on y. A box with a
//! NEGATIVE width is subtracted: that is how the channel (a void in the
//! fluidic layer) and the ribs (solid inside the gas volume) enter.

use crate::element::ElementBlocks;
use crate::error::{positive, require, InputError};
use crate::field::Field;
use crate::model::{GasParams, LinearParams, PrestressedParams};
use crate::partition::{Partition, MIN_ELEMENT_FRACTION};

use super::laminate::{Actuator, Rib};
use super::material::PlaneStress;
use crate::field::ShearLayer;

/// Clipped blocks shorter than this fraction of the element are dropped.
const MIN_BLOCK_FRACTION: f64 = 1e-12;

impl Partition {
    /// Element boundaries on every material change: the ends of the ribs
    /// and of the channel (when ribs are off, the channel's end only), the
    /// ends of the ribs on the constraining layer (always: they are not
    /// switched by `ribs`), and
    /// every piece split into equal parts no longer than `max_length`.
    /// Boundaries closer than [`MIN_ELEMENT_FRACTION`] `lx` to another are
    /// merged. This is the starting partition of the automatic choice
    /// ([`crate::Plan::Auto`]); with element ends on material changes the
    /// CCM converges at second order in the element length, with a small
    /// first-order term under a tip load (src/plan/refine.rs).
    pub fn material(
        actuator: &Actuator,
        ribs: bool,
        max_length: f64,
    ) -> Result<Partition, InputError> {
        let lx = actuator.geometry().lx;
        positive(Field::PartitionMaxLength, max_length)?;
        let min = MIN_ELEMENT_FRACTION * lx;
        let mut cuts: Vec<f64> = vec![0.0, lx, actuator.channel().cx];
        if ribs {
            for r in actuator.ribs() {
                cuts.push(r.x0);
                cuts.push(r.x1);
            }
        }
        for r in actuator.cl_ribs() {
            cuts.push(r.x0);
            cuts.push(r.x1);
        }
        cuts.retain(|x| x.is_finite() && (0.0..=lx).contains(x));
        cuts.sort_by(f64::total_cmp);
        let mut merged: Vec<f64> = Vec::with_capacity(cuts.len());
        for x in cuts {
            match merged.last() {
                Some(&last) if x - last < min => {
                    // keep the finger's end exact
                    if x == lx {
                        *merged.last_mut().unwrap_or(&mut 0.0) = lx;
                    }
                }
                _ => merged.push(x),
            }
        }
        if merged.len() < 2 || merged[0] != 0.0 {
            merged.insert(0, 0.0);
        }
        let mut lengths = Vec::new();
        for w in merged.windows(2) {
            let piece = w[1] - w[0];
            let parts = (piece / max_length).ceil().max(1.0) as usize;
            lengths.extend(std::iter::repeat_n(piece / parts as f64, parts));
        }
        let max = (1.0 / MIN_ELEMENT_FRACTION).round() as usize;
        require(
            lengths.len() <= max,
            Field::PartitionMaxLength,
            max_length,
            || {
                format!(
                    "gives {} elements (pieces of at most {max_length} mm between the \
                     material boundaries), more than {max}",
                    lengths.len()
                )
            },
        )?;
        Partition::custom(lengths, lx)
    }
}

/// Clips the global range [gx0, gx1] to the element [start, start + len]
/// in local coordinates, or None if less than a negligible part remains.
/// Where a box covers an end of the element the local bound is exactly 0
/// or `len`, so elements with the same content give bit-identical blocks.
pub(super) fn clip(gx0: f64, gx1: f64, start: f64, len: f64) -> Option<(f64, f64)> {
    let end = start + len;
    let x0 = if gx0 <= start { 0.0 } else { gx0 - start };
    let x1 = if gx1 >= end { len } else { gx1 - start };
    (x1 - x0 > MIN_BLOCK_FRACTION * len).then_some((x0, x1))
}

/// The integration blocks of every element of `part`, root to tip.
///
/// `part` should be built for `act.geometry().lx`; the laminae cover each
/// element whole, and the channel and ribs are clipped to it. `ribs`
/// switches the channel's rib terms (in both energy and gas volume) on or
/// off; the ribs on the constraining layer ([`Actuator::cl_ribs`], none
/// by default) are data of the actuator and always enter, as boxes of the
/// constraining layer's material over z in [H/2, H/2 + height], after
/// every other linear block (so an actuator without them gives the same
/// blocks as before they existed).
///
/// The library builds every finger's elements from these; they are public
/// for code that evaluates the laminate's integrals on its own (the
/// benchmarks of independent derivative strategies, for one).
pub fn element_blocks(act: &Actuator, part: &Partition, ribs: bool) -> Vec<ElementBlocks> {
    let layers = act.linear_layers();
    let fluidic_q = act.fluidic_q();
    let (pz0, pz1) = act.pemc_z();
    let (cz0, cz1) = act.channel_z();
    let channel = act.channel();
    let pemc = act.pemc();
    let rib_list: &[Rib] = if ribs { act.ribs() } else { &[] };
    let width = act.geometry().ly;
    let ks = act.shear_correction();
    let fluidic_g13 = act.g13(ShearLayer::Fluidic);
    let [cl_layer, ..] = layers;
    let top = act.geometry().h / 2.0;

    // a linear box over x in [x0, x1], z in [z0, z1] of a material
    let linear_box =
        |(x0, x1): (f64, f64), (z0, z1): (f64, f64), width: f64, q: PlaneStress, g13| {
            let PlaneStress { q11, q12, q22 } = q;
            LinearParams {
                x0,
                x1,
                z0,
                z1,
                width,
                q11,
                q12,
                q22,
                g13,
                ks,
            }
        };
    part.lengths()
        .iter()
        .zip(part.starts())
        .map(|(&len, &start)| {
            let mut linear: Vec<LinearParams> = layers
                .iter()
                .map(|l| linear_box((0.0, len), (l.z0, l.z1), width, l.q, l.g13))
                .collect();
            let mut gas = Vec::new();
            // the channel takes the fluidic material out over its width cy
            // (a box of width -cy) and holds gas there; each rib in it puts
            // the material back over its own width and displaces the gas
            let channel_part = clip(0.0, channel.cx, start, len).map(|x| (x, -channel.cy));
            let rib_parts = rib_list
                .iter()
                .filter_map(|rib| clip(rib.x0, rib.x1, start, len).map(|x| (x, rib.width)));
            for ((x0, x1), w) in channel_part.into_iter().chain(rib_parts) {
                linear.push(linear_box((x0, x1), (cz0, cz1), w, fluidic_q, fluidic_g13));
                gas.push(GasParams {
                    x0,
                    x1,
                    z0: cz0,
                    z1: cz1,
                    width: -w,
                });
            }
            for rib in act.cl_ribs() {
                if let Some(x) = clip(rib.x0, rib.x1, start, len) {
                    let z = (top, top + rib.height);
                    linear.push(linear_box(x, z, rib.width, cl_layer.q, cl_layer.g13));
                }
            }
            let law = pemc.law;
            let prestressed = vec![PrestressedParams {
                x0: 0.0,
                x1: len,
                z0: pz0,
                z1: pz1,
                width,
                eps0: pemc.eps0,
                p1: law.p1,
                p2: law.p2,
                p3: law.p3,
                p4: law.p4,
                q22: pemc.q22(),
                g13: act.g13(ShearLayer::Pemc),
                ks,
            }];
            ElementBlocks {
                length: len,
                plane_strain: act.plane_strain(),
                linear,
                prestressed,
                gas,
            }
        })
        .collect()
}

/// The blocks of the default actuator against values computed by hand
/// (moved here from tests/actuator_validation.rs: the block construction
/// is crate-private).
#[cfg(test)]
mod tests {
    use super::*;
    use crate::actuator::PlaneStress;
    use crate::element::distinct_elements;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol * (1.0 + a.abs().max(b.abs()))
    }

    fn volume(x0: f64, x1: f64, z0: f64, z1: f64, w: f64) -> f64 {
        (x1 - x0) * (z1 - z0) * w
    }

    fn q_of(k: &LinearParams) -> PlaneStress {
        PlaneStress {
            q11: k.q11,
            q12: k.q12,
            q22: k.q22,
        }
    }

    fn assert_inside(blocks: &[ElementBlocks]) {
        for b in blocks {
            let l = b.length;
            let boxes = b
                .linear
                .iter()
                .map(|k| (k.x0, k.x1))
                .chain(b.prestressed.iter().map(|k| (k.x0, k.x1)))
                .chain(b.gas.iter().map(|k| (k.x0, k.x1)));
            for (x0, x1) in boxes {
                assert!(
                    0.0 <= x0 && x0 < x1 && x1 <= l,
                    "[{x0}, {x1}] outside [0, {l}]"
                );
            }
        }
    }

    #[test]
    fn block_volumes_add_up() {
        let act = Actuator::default();
        let height = 0.8 + 1.2;
        // D5 by hand: longitudinal 2 x 105, 13 transverse 2 x 12.
        let rib_area = 2.0 * 105.0 + 13.0 * 2.0 * 12.0;
        let rib_area_list: f64 = act.ribs().iter().map(|r| (r.x1 - r.x0) * r.width).sum();
        assert!(close(rib_area, rib_area_list, 1e-14));
        let channel_vol = 26.0 * 105.0 * height;
        let fl_vol = 31.75 * 110.0 * (1.8 + 2.2);
        let fl_q = act.fluidic_q();

        for n in [1, 3, 8] {
            let part = Partition::equal(110.0, n).unwrap();
            for ribs in [true, false] {
                let blocks = element_blocks(&act, &part, ribs);
                assert_eq!(blocks.len(), n);
                assert_inside(&blocks);
                let rib_vol = if ribs { rib_area * height } else { 0.0 };

                let gas: f64 = blocks
                    .iter()
                    .flat_map(|b| &b.gas)
                    .map(|g| volume(g.x0, g.x1, g.z0, g.z1, g.width))
                    .sum();
                assert!(close(gas, channel_vol - rib_vol, 1e-12), "n = {n}: {gas}");

                let fl: f64 = blocks
                    .iter()
                    .flat_map(|b| &b.linear)
                    .filter(|k| q_of(k) == fl_q)
                    .map(|k| volume(k.x0, k.x1, k.z0, k.z1, k.width))
                    .sum();
                assert!(
                    close(fl, fl_vol - channel_vol + rib_vol, 1e-12),
                    "n = {n}: {fl}"
                );

                // The other laminae cover the whole finger.
                for (q, thick) in [
                    (act.linear_layers()[0].q, 0.4),
                    (act.linear_layers()[1].q, 1.9),
                ] {
                    let v: f64 = blocks
                        .iter()
                        .flat_map(|b| &b.linear)
                        .filter(|k| q_of(k) == q)
                        .map(|k| volume(k.x0, k.x1, k.z0, k.z1, k.width))
                        .sum();
                    assert!(close(v, 31.75 * 110.0 * thick, 1e-12));
                }
                let pv: f64 = blocks
                    .iter()
                    .flat_map(|b| &b.prestressed)
                    .map(|k| volume(k.x0, k.x1, k.z0, k.z1, k.width))
                    .sum();
                assert!(close(pv, 31.75 * 110.0 * 1.9, 1e-12));
                for b in &blocks {
                    for k in &b.prestressed {
                        assert_eq!(
                            (k.eps0, [k.p1, k.p2, k.p3, k.p4], k.q22),
                            (0.25, [1.598, 2.306, 2.29, 0.698], 250.0)
                        );
                    }
                }
            }
        }
    }

    #[test]
    fn voids_have_negative_width() {
        let act = Actuator::default();
        let part = Partition::equal(110.0, 1).unwrap();
        let b = &element_blocks(&act, &part, true)[0];
        // Three laminae, the channel, 14 ribs.
        assert_eq!(b.linear.len(), 3 + 1 + 14);
        assert_eq!(b.linear[3].width, -26.0);
        assert!(b.linear[4..].iter().all(|k| k.width > 0.0));
        assert_eq!(b.gas.len(), 1 + 14);
        assert_eq!(b.gas[0].width, 26.0);
        assert!(b.gas[1..].iter().all(|g| g.width < 0.0));
        assert_eq!((b.gas[0].z0, b.gas[0].z1), (-1.2, 0.8));
    }

    #[test]
    fn element_past_the_channel_has_no_gas() {
        let act = Actuator::default();
        let part = Partition::custom(vec![105.0, 5.0], 110.0).unwrap();
        let blocks = element_blocks(&act, &part, true);
        assert!(blocks[1].gas.is_empty());
        assert_eq!(blocks[1].linear.len(), 3);
        assert_eq!(blocks[0].gas.len(), 15);
    }

    #[test]
    fn equal_elements_are_found() {
        let act = Actuator::default();
        // Without ribs, elements 1..7 of 8 are whole channel; the last holds
        // the channel's end.
        let part = Partition::equal(110.0, 8).unwrap();
        let blocks = element_blocks(&act, &part, false);
        assert_eq!(distinct_elements(&blocks), [0, 0, 0, 0, 0, 0, 0, 7]);

        // With ribs, elements [8k - 4, 8k + 4] each hold one centred
        // transverse rib and are identical.
        let mut lengths = vec![4.0];
        lengths.extend([8.0; 12]);
        lengths.push(10.0);
        let part = Partition::custom(lengths, 110.0).unwrap();
        let blocks = element_blocks(&act, &part, true);
        let mut want = vec![0];
        want.extend([1; 12]);
        want.push(13);
        assert_eq!(distinct_elements(&blocks), want);

        // The general property on an irregular case.
        let part = Partition::equal(110.0, 8).unwrap();
        let blocks = element_blocks(&act, &part, true);
        let map = distinct_elements(&blocks);
        for (i, &j) in map.iter().enumerate() {
            assert!(j <= i && map[j] == j && blocks[j] == blocks[i]);
            for k in 0..j {
                assert_ne!(blocks[k], blocks[i]);
            }
        }
    }

    #[test]
    fn equal_elements_without_ribs_have_equal_blocks() {
        // tests/finger/paths.rs checks the same fingers through the public API
        // (equal element energies, equal solutions); here the blocks
        // themselves: N = 8, the last element holds the channel's end;
        // N = 22, 5 mm elements, the last one is the solid wall.
        let act = Actuator::paper(0.25).unwrap();
        for n in [8usize, 22] {
            let blocks = element_blocks(&act, &Partition::equal(110.0, n).unwrap(), false);
            for (i, b) in blocks.iter().enumerate().take(n - 1) {
                assert_eq!(b, &blocks[0], "N {n}: element {i} differs from element 0");
            }
            assert_ne!(
                blocks[n - 1],
                blocks[0],
                "N {n}: the last element is special"
            );
        }
    }
}

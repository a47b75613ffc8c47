//! The element partition and each element's integration blocks
//! (docs/model.md sections 4.3 and 4.4).
//!
//! An element's strain energy and gas volume are sums of integrals over
//! boxes: x over a sub-interval [x0, x1] of the element (local
//! coordinate, 0 <= x0 < x1 <= L_i), z over [z0, z1], and a width in y
//! that is a plain factor because nothing depends on y. A box with a
//! NEGATIVE width is subtracted: that is how the channel (a void in the
//! fluidic layer) and the ribs (solid inside the gas volume) enter.

use crate::actuator::{Actuator, Material, PlaneStress, Rib, RibLayout};
use crate::error::{finite, positive, require, InputError};
use crate::model::{GasParams, LinearParams, PrestressedParams, PsiParams};
use crate::sensitivity::{ActuatorParam, Elastic, Lamina};

/// Shortest element allowed, as a fraction of the finger's length.
pub const MIN_ELEMENT_FRACTION: f64 = 1e-3;

/// Relative tolerance on the sum of custom element lengths.
pub const LENGTH_SUM_TOLERANCE: f64 = 1e-9;

/// Clipped blocks shorter than this fraction of the element are dropped.
const MIN_BLOCK_FRACTION: f64 = 1e-12;

/// How the finger's length is split into elements.
#[derive(Debug, Clone, PartialEq)]
pub struct Partition {
    lengths: Vec<f64>,
    starts: Vec<f64>,
}

impl Partition {
    /// `n` equal elements of length `lx / n`; `n` at most
    /// 1 / [`MIN_ELEMENT_FRACTION`].
    pub fn equal(lx: f64, n: usize) -> Result<Partition, InputError> {
        positive("partition.lx", lx)?;
        let max = (1.0 / MIN_ELEMENT_FRACTION).round();
        require(
            n >= 1 && n as f64 <= max,
            "partition.n",
            n as f64,
            format!(
                "must lie in [1, {max}] (each element at least {MIN_ELEMENT_FRACTION} lx long)"
            ),
        )?;
        Ok(Partition::from_lengths(vec![lx / n as f64; n]))
    }

    /// Elements of the given lengths, in order from the root. Each must be
    /// finite and at least [`MIN_ELEMENT_FRACTION`] `lx` long, and they must
    /// add up to `lx` within [`LENGTH_SUM_TOLERANCE`] `lx`.
    pub fn custom(lengths: Vec<f64>, lx: f64) -> Result<Partition, InputError> {
        positive("partition.lx", lx)?;
        if lengths.is_empty() {
            return Err(InputError::Inconsistent {
                field: "partition.lengths".into(),
                rule: "needs at least one element".into(),
            });
        }
        let min = MIN_ELEMENT_FRACTION * lx;
        for (i, &l) in lengths.iter().enumerate() {
            let field = format!("partition.lengths[{i}]");
            positive(&field, l)?;
            require(
                l >= min,
                &field,
                l,
                format!("must be at least {MIN_ELEMENT_FRACTION} lx = {min}"),
            )?;
        }
        let sum: f64 = lengths.iter().sum();
        finite("partition.lengths (sum)", sum)?;
        if (sum - lx).abs() > LENGTH_SUM_TOLERANCE * lx {
            return Err(InputError::Inconsistent {
                field: "partition.lengths".into(),
                rule: format!("the lengths add up to {sum}, not to lx = {lx}"),
            });
        }
        Ok(Partition::from_lengths(lengths))
    }

    /// Element boundaries on every material change: the ends of the ribs
    /// and of the channel (when ribs are off, the channel's end only), and
    /// every piece split into equal parts no longer than `max_length`.
    /// Boundaries closer than [`MIN_ELEMENT_FRACTION`] `lx` to another are
    /// merged. This is the starting partition of the automatic choice
    /// ([`crate::solve_auto`]); with element ends on material changes the
    /// CCM converges at second order in the element length, with a small
    /// first-order term under a tip load (src/refine.rs).
    pub fn material(
        actuator: &Actuator,
        ribs: bool,
        max_length: f64,
    ) -> Result<Partition, InputError> {
        let lx = actuator.geometry().lx;
        positive("partition.max_length", max_length)?;
        let min = MIN_ELEMENT_FRACTION * lx;
        let mut cuts: Vec<f64> = vec![0.0, lx, actuator.channel().cx];
        if ribs {
            for r in actuator.ribs() {
                cuts.push(r.x0);
                cuts.push(r.x1);
            }
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
            "partition.max_length",
            max_length,
            format!("gives {} elements, more than {max}", lengths.len()),
        )?;
        Partition::custom(lengths, lx)
    }

    /// Every element halved (twice the elements, nested in this partition).
    pub fn halved(&self) -> Partition {
        self.split(&vec![true; self.len()])
    }

    /// Splits the elements whose index `split` marks into two halves.
    pub fn split(&self, split: &[bool]) -> Partition {
        let mut lengths = Vec::with_capacity(self.len() + split.len());
        for (i, &l) in self.lengths.iter().enumerate() {
            if split.get(i).copied().unwrap_or(false) {
                lengths.push(0.5 * l);
                lengths.push(0.5 * l);
            } else {
                lengths.push(l);
            }
        }
        Partition::from_lengths(lengths)
    }

    fn from_lengths(lengths: Vec<f64>) -> Partition {
        let mut starts = Vec::with_capacity(lengths.len());
        let mut s = 0.0;
        for &l in &lengths {
            starts.push(s);
            s += l;
        }
        Partition { lengths, starts }
    }

    /// Undeformed element lengths L_i, root to tip.
    pub fn lengths(&self) -> &[f64] {
        &self.lengths
    }

    /// X_ref of each element's root: S_i = L_1 + ... + L_{i-1}.
    pub fn starts(&self) -> &[f64] {
        &self.starts
    }

    /// Number of elements N.
    pub fn len(&self) -> usize {
        self.lengths.len()
    }

    /// Always false: a partition has at least one element.
    pub fn is_empty(&self) -> bool {
        self.lengths.is_empty()
    }
}

/// The blocks of one element, each in the parameter struct of the model's
/// integral family it feeds (a negative width subtracts a box: the channel
/// from the fluidic layer, a rib from the gas volume). Two elements with
/// equal `ElementBlocks` (compared exactly) have the same energy function.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ElementBlocks {
    /// Undeformed length L_i.
    pub length: f64,
    /// CL, regular EMC, whole fluidic layer, then the channel (negative
    /// width), then the ribs (fluidic material) if enabled.
    pub linear: Vec<LinearParams>,
    /// The prestressed layer.
    pub prestressed: Vec<PrestressedParams>,
    /// The channel (positive width), then the ribs (negative width) if
    /// enabled. Empty where the element has no channel.
    pub gas: Vec<GasParams>,
}

/// Clips the global range [gx0, gx1] to the element [start, start + len]
/// in local coordinates, or None if less than a negligible part remains.
/// Where a box covers an end of the element the local bound is exactly 0
/// or `len`, so elements with the same content give bit-identical blocks.
fn clip(gx0: f64, gx1: f64, start: f64, len: f64) -> Option<(f64, f64)> {
    let end = start + len;
    let x0 = if gx0 <= start { 0.0 } else { gx0 - start };
    let x1 = if gx1 >= end { len } else { gx1 - start };
    (x1 - x0 > MIN_BLOCK_FRACTION * len).then_some((x0, x1))
}

/// The integration blocks of every element of `part`, root to tip.
///
/// `part` should be built for `act.geometry().lx`; the laminae cover each
/// element whole, and the channel and ribs are clipped to it. `ribs`
/// switches the rib terms (in both energy and gas volume) on or off.
pub(crate) fn element_blocks(act: &Actuator, part: &Partition, ribs: bool) -> Vec<ElementBlocks> {
    let layers = act.linear_layers();
    let fluidic_q = act.fluidic_q();
    let (pz0, pz1) = act.pemc_z();
    let (cz0, cz1) = act.channel_z();
    let channel = act.channel();
    let pemc = act.pemc();
    let rib_list: &[Rib] = if ribs { act.ribs() } else { &[] };
    let width = act.geometry().ly;

    part.lengths()
        .iter()
        .zip(part.starts())
        .map(|(&len, &start)| {
            let mut linear: Vec<LinearParams> = layers
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
                })
                .collect();
            let mut gas = Vec::new();
            if let Some((x0, x1)) = clip(0.0, channel.cx, start, len) {
                linear.push(LinearParams {
                    x0,
                    x1,
                    z0: cz0,
                    z1: cz1,
                    width: -channel.cy,
                    q11: fluidic_q.q11,
                    q12: fluidic_q.q12,
                    q22: fluidic_q.q22,
                });
                gas.push(GasParams {
                    x0,
                    x1,
                    z0: cz0,
                    z1: cz1,
                    width: channel.cy,
                });
            }
            for rib in rib_list {
                if let Some((x0, x1)) = clip(rib.x0, rib.x1, start, len) {
                    linear.push(LinearParams {
                        x0,
                        x1,
                        z0: cz0,
                        z1: cz1,
                        width: rib.width,
                        q11: fluidic_q.q11,
                        q12: fluidic_q.q12,
                        q22: fluidic_q.q22,
                    });
                    gas.push(GasParams {
                        x0,
                        x1,
                        z0: cz0,
                        z1: cz1,
                        width: -rib.width,
                    });
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
            }];
            ElementBlocks {
                length: len,
                linear,
                prestressed,
                gas,
            }
        })
        .collect()
}

/// The change of every actuator quantity the blocks read, per unit change
/// of one design parameter: a tangent of the actuator (docs/model.md,
/// "Sensitivities"). [`element_block_tangents`] turns it into the tangent
/// of every block's parameters.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ActuatorTangent {
    /// Total thickness H.
    pub h: f64,
    /// Interfaces h1, h2, h3.
    pub h1: f64,
    pub h2: f64,
    pub h3: f64,
    /// Width of the laminae.
    pub ly: f64,
    /// Channel width and heights.
    pub cy: f64,
    pub h3a: f64,
    pub h3b: f64,
    /// Reduced stiffnesses of the constraining layer, the regular EMC and
    /// the fluidic layer (also the ribs' material).
    pub cl: PlaneStress,
    pub emc: PlaneStress,
    pub fluidic: PlaneStress,
    /// The prestressed layer: prestrain, E2 (its Q22) and its law.
    pub eps0: f64,
    pub e2: f64,
    pub law: PsiParams,
    /// The total width of each rib of [`Actuator::ribs`], in that order.
    pub rib_widths: Vec<f64>,
}

const NO_Q: PlaneStress = PlaneStress {
    q11: 0.0,
    q12: 0.0,
    q22: 0.0,
};

impl ActuatorTangent {
    /// No change (the tangent of a parameter the blocks do not read).
    pub fn zero(act: &Actuator) -> ActuatorTangent {
        ActuatorTangent {
            h: 0.0,
            h1: 0.0,
            h2: 0.0,
            h3: 0.0,
            ly: 0.0,
            cy: 0.0,
            h3a: 0.0,
            h3b: 0.0,
            cl: NO_Q,
            emc: NO_Q,
            fluidic: NO_Q,
            eps0: 0.0,
            e2: 0.0,
            law: PsiParams {
                p1: 0.0,
                p2: 0.0,
                p3: 0.0,
                p4: 0.0,
            },
            rib_widths: vec![0.0; act.ribs().len()],
        }
    }

    /// The tangent of one actuator parameter of `act`: the unit change of
    /// the parameter, carried to every quantity the blocks read (the
    /// plane-stress Q's of (M3) for an elastic constant, the ribs' widths
    /// `2 w2` for `actuator.ribs.w2`). Fails for an elastic constant the
    /// layer's material does not have (`e1` of an isotropic layer) and for
    /// `w2` without the paper's rib layout.
    pub fn of(act: &Actuator, param: ActuatorParam) -> Result<ActuatorTangent, InputError> {
        let mut t = ActuatorTangent::zero(act);
        match param {
            ActuatorParam::Eps0 => t.eps0 = 1.0,
            ActuatorParam::PemcE2 => t.e2 = 1.0,
            ActuatorParam::PsiP1 => t.law.p1 = 1.0,
            ActuatorParam::PsiP2 => t.law.p2 = 1.0,
            ActuatorParam::PsiP3 => t.law.p3 = 1.0,
            ActuatorParam::PsiP4 => t.law.p4 = 1.0,
            ActuatorParam::H => t.h = 1.0,
            ActuatorParam::H1 => t.h1 = 1.0,
            ActuatorParam::H2 => t.h2 = 1.0,
            ActuatorParam::H3 => t.h3 = 1.0,
            ActuatorParam::Ly => t.ly = 1.0,
            ActuatorParam::ChannelCy => t.cy = 1.0,
            ActuatorParam::ChannelH3a => t.h3a = 1.0,
            ActuatorParam::ChannelH3b => t.h3b = 1.0,
            ActuatorParam::Elastic(layer, key) => {
                let p = act.params();
                let material = match layer {
                    Lamina::Cl => &p.cl,
                    Lamina::Emc => &p.emc,
                    Lamina::Fluidic => &p.fluidic,
                };
                let dq = plane_stress_tangent(material, key).ok_or_else(|| {
                    InputError::Inconsistent {
                        field: ActuatorParam::Elastic(layer, key).name().into(),
                        rule: format!(
                            "the {} layer's material has no such constant ({})",
                            layer.name(),
                            match material {
                                Material::Isotropic(_) => "isotropic: e, nu",
                                Material::Orthotropic(_) => "orthotropic: e1, e2, nu12",
                            }
                        ),
                    }
                })?;
                match layer {
                    Lamina::Cl => t.cl = dq,
                    Lamina::Emc => t.emc = dq,
                    Lamina::Fluidic => t.fluidic = dq,
                }
            }
            ActuatorParam::RibsW2 => {
                if !matches!(act.params().ribs, RibLayout::Paper { .. }) {
                    return Err(InputError::Inconsistent {
                        field: param.name().into(),
                        rule: "needs the paper's rib layout (`kind = \"paper\"`)".into(),
                    });
                }
                // the longitudinal rib first (width t), then the transverse
                // ribs (2 w2 each)
                for (i, w) in t.rib_widths.iter_mut().enumerate() {
                    *w = if i == 0 { 0.0 } else { 2.0 };
                }
            }
        }
        Ok(t)
    }
}

/// The derivative of a material's plane-stress Q's (M3) with respect to
/// one of its elastic constants, or `None` if it has no such constant.
///
/// Orthotropic, `D = 1 - nu12^2 E2 / E1`: `Q11 = E1 / D`,
/// `Q12 = nu12 E2 / D`, `Q22 = E2 / D`, so `dQ = dN / D - N dD / D^2` with
/// `dD = -(2 nu12 dnu12 E2 / E1 + nu12^2 dE2 / E1 - nu12^2 E2 dE1 / E1^2)`.
/// Isotropic: the same with `E1 = E2 = E` (so `dE1 = dE2 = dE`, and
/// `dD = 0` along `E`).
pub(crate) fn plane_stress_tangent(material: &Material, key: Elastic) -> Option<PlaneStress> {
    let (e1, e2, nu, de1, de2, dnu) = match (material, key) {
        (Material::Isotropic(m), Elastic::E) => (m.e, m.e, m.nu, 1.0, 1.0, 0.0),
        (Material::Isotropic(m), Elastic::Nu) => (m.e, m.e, m.nu, 0.0, 0.0, 1.0),
        (Material::Orthotropic(m), Elastic::E1) => (m.e1, m.e2, m.nu12, 1.0, 0.0, 0.0),
        (Material::Orthotropic(m), Elastic::E2) => (m.e1, m.e2, m.nu12, 0.0, 1.0, 0.0),
        (Material::Orthotropic(m), Elastic::Nu12) => (m.e1, m.e2, m.nu12, 0.0, 0.0, 1.0),
        _ => return None,
    };
    let d = 1.0 - nu * nu * e2 / e1;
    let dd = -(2.0 * nu * dnu * e2 / e1 + nu * nu * de2 / e1 - nu * nu * e2 * de1 / (e1 * e1));
    let quotient = |n: f64, dn: f64| dn / d - n * dd / (d * d);
    Some(PlaneStress {
        q11: quotient(e1, de1),
        q12: quotient(nu * e2, dnu * e2 + nu * de2),
        q22: quotient(e2, de2),
    })
}

/// The tangent of every block of [`element_blocks`] along `t`: the same
/// elements, the same blocks in the same order, each parameter replaced by
/// its derivative. The geometry is piecewise linear in the actuator's
/// dimensions (a lamina's z range is an interface or `H/2`, the channel's
/// `[-h3b, h3a]`, the widths `ly`, `-cy` and `cy`, a rib's width); no
/// parameter of [`ActuatorTangent`] moves an x bound, so the clipping to
/// the elements has no derivative.
#[cfg_attr(not(test), allow(dead_code))] // the sensitivities fill element by element
pub(crate) fn element_block_tangents(
    act: &Actuator,
    part: &Partition,
    ribs: bool,
    t: &ActuatorTangent,
) -> Vec<ElementBlocks> {
    part.lengths()
        .iter()
        .zip(part.starts())
        .map(|(&len, &start)| {
            let mut out = ElementBlocks {
                length: 0.0,
                linear: Vec::new(),
                prestressed: Vec::new(),
                gas: Vec::new(),
            };
            element_block_tangent_into(act, ribs, t, start, len, &mut out);
            out
        })
        .collect()
}

/// The tangent of the blocks of the element `[start, start + len]` (see
/// [`element_block_tangents`]), into `out` (its vectors reused; `length`
/// is 0: no parameter moves it).
pub(crate) fn element_block_tangent_into(
    act: &Actuator,
    ribs: bool,
    t: &ActuatorTangent,
    start: f64,
    len: f64,
    out: &mut ElementBlocks,
) {
    let channel = act.channel();
    let rib_list: &[Rib] = if ribs { act.ribs() } else { &[] };
    // (z0, z1, q) of CL, EMC and the whole fluidic layer (Actuator::linear_layers)
    let layers = [
        (t.h1, 0.5 * t.h, t.cl),
        (t.h2, t.h1, t.emc),
        (-t.h3, t.h2, t.fluidic),
    ];
    let (cz0, cz1) = (-t.h3b, t.h3a);
    let linear_box = |z0: f64, z1: f64, width: f64, q: PlaneStress| LinearParams {
        x0: 0.0,
        x1: 0.0,
        z0,
        z1,
        width,
        q11: q.q11,
        q12: q.q12,
        q22: q.q22,
    };
    let gas_box = |width: f64| GasParams {
        x0: 0.0,
        x1: 0.0,
        z0: cz0,
        z1: cz1,
        width,
    };
    out.length = 0.0;
    out.linear.clear();
    out.prestressed.clear();
    out.gas.clear();
    out.linear.extend(
        layers
            .iter()
            .map(|&(z0, z1, q)| linear_box(z0, z1, t.ly, q)),
    );
    if clip(0.0, channel.cx, start, len).is_some() {
        out.linear.push(linear_box(cz0, cz1, -t.cy, t.fluidic));
        out.gas.push(gas_box(t.cy));
    }
    for (rib, &dw) in rib_list.iter().zip(&t.rib_widths) {
        if clip(rib.x0, rib.x1, start, len).is_some() {
            out.linear.push(linear_box(cz0, cz1, dw, t.fluidic));
            out.gas.push(gas_box(-dw));
        }
    }
    out.prestressed.push(PrestressedParams {
        x0: 0.0,
        x1: 0.0,
        z0: -0.5 * t.h,
        z1: -t.h3,
        width: t.ly,
        eps0: t.eps0,
        p1: t.law.p1,
        p2: t.law.p2,
        p3: t.law.p3,
        p4: t.law.p4,
        q22: t.e2,
    });
}

/// For each element, the index of the first element with identical
/// blocks (itself if none before it matches). Elements that map to the
/// same index have the same energy and, without tip loads, the same
/// equilibrium, so they can be solved once.
pub(crate) fn distinct_elements(blocks: &[ElementBlocks]) -> Vec<usize> {
    let mut first = Vec::with_capacity(blocks.len());
    for (i, b) in blocks.iter().enumerate() {
        let j = (0..i)
            .find(|&j| first[j] == j && blocks[j] == *b)
            .unwrap_or(i);
        first.push(j);
    }
    first
}

/// The blocks of the default actuator against values computed by hand
/// (moved here from tests/actuator_validation.rs: the block construction
/// is crate-private).
#[cfg(test)]
mod tests {
    use super::*;
    use crate::actuator::PlaneStress;

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

    /// Every block parameter's derivative (`element_block_tangents`)
    /// against central differences of the block construction, for every
    /// actuator parameter, on the default actuator and on one with
    /// orthotropic layers and Poisson coupling (so every Q depends on every
    /// constant).
    #[test]
    fn block_tangents_match_central_differences() {
        use crate::actuator::{ActuatorParams, Orthotropic};
        use crate::sensitivity::ActuatorParam;
        let params = ActuatorParams {
            cl: Orthotropic {
                e1: 305.0,
                e2: 200.0,
                nu12: 0.3,
            }
            .into(),
            emc: Orthotropic {
                e1: 1.5,
                e2: 250.0,
                nu12: 0.05,
            }
            .into(),
            ..ActuatorParams::default()
        };
        let coupled = Actuator::new(params).unwrap();
        let values = |b: &ElementBlocks| -> Vec<f64> {
            let mut v = Vec::new();
            for k in &b.linear {
                v.extend(k.to_values());
            }
            for k in &b.prestressed {
                v.extend(k.to_values());
            }
            for k in &b.gas {
                v.extend(k.to_values());
            }
            v
        };
        let mut worst: f64 = 0.0;
        let mut checked = 0;
        for act in [Actuator::default(), coupled] {
            for n in [1, 3, 8] {
                let part = Partition::equal(110.0, n).unwrap();
                for ribs in [true, false] {
                    for param in ActuatorParam::for_actuator(&act) {
                        let v = param.value(&act).unwrap();
                        let t = ActuatorTangent::of(&act, param).unwrap();
                        let exact = element_block_tangents(&act, &part, ribs, &t);
                        // Richardson-extrapolated central differences (the
                        // Q's are rational in the constants)
                        let h = 1e-3 * v.abs().max(1e-2);
                        let blocks_at = |x: f64| {
                            element_blocks(&param.with_value(&act, x).unwrap(), &part, ribs)
                        };
                        let diff = |h: f64| -> Vec<Vec<f64>> {
                            let (a, b) = (blocks_at(v + h), blocks_at(v - h));
                            a.iter()
                                .zip(&b)
                                .map(|(a, b)| {
                                    assert_eq!(a.linear.len(), b.linear.len());
                                    assert_eq!(a.gas.len(), b.gas.len());
                                    values(a)
                                        .iter()
                                        .zip(values(b))
                                        .map(|(x, y)| (x - y) / (2.0 * h))
                                        .collect()
                                })
                                .collect()
                        };
                        let (d1, d2) = (diff(h), diff(0.5 * h));
                        assert_eq!(exact.len(), n);
                        for (i, e) in exact.iter().enumerate() {
                            let ev = values(e);
                            assert_eq!(ev.len(), d1[i].len(), "{}: element {i}", param.name());
                            for (j, x) in ev.iter().enumerate() {
                                let fd = (4.0 * d2[i][j] - d1[i][j]) / 3.0;
                                let err = (x - fd).abs() / x.abs().max(fd.abs()).max(1.0);
                                assert!(
                                    err <= 1e-8,
                                    "{} (N {n}, ribs {ribs}): element {i}, entry {j}: {x} vs {fd}",
                                    param.name()
                                );
                                worst = worst.max(err);
                            }
                        }
                        checked += 1;
                    }
                }
            }
        }
        assert!(checked > 100);
        println!("block tangents vs central differences: worst {worst:.1e} over {checked} cases");
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

//! The tangent of the actuator along one of its parameters
//! ([`ActuatorParam`]), and of its integration blocks: the right-hand sides
//! of the design sensitivities (docs/model.md, "Sensitivities").

use crate::element::ElementBlocks;
use crate::error::InputError;
use crate::model::{GasParams, LinearParams, PrestressedParams, PsiParams};
use crate::partition::Partition;

use super::blocks::clip;
use super::laminate::{Actuator, Rib, RibLayout};
use super::material::{Material, PlaneStress};
use super::param::ActuatorParam;
use crate::field::{Elastic, Lamina, ShearLayer};

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
    /// The width and height of each rib of [`Actuator::cl_ribs`].
    pub cl_rib_widths: Vec<f64>,
    pub cl_rib_heights: Vec<f64>,
    /// The transverse shear moduli G13, in [`ShearLayer::ALL`]'s order
    /// (a default one moves with the constants it comes from), and the
    /// shear correction factor.
    pub g13: [f64; 4],
    pub ks: f64,
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
            cl_rib_widths: vec![0.0; act.cl_ribs().len()],
            cl_rib_heights: vec![0.0; act.cl_ribs().len()],
            g13: [0.0; 4],
            ks: 0.0,
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
            ActuatorParam::PsiP1 => {
                t.law.p1 = 1.0;
                // the prestressed layer's default G13 is p1 / 2
                if act.params().shear.g13[ShearLayer::Pemc as usize].is_none() {
                    t.g13[ShearLayer::Pemc as usize] = 0.5;
                }
            }
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
                        field: crate::Field::Material(layer, key),
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
                let shear_layer = match layer {
                    Lamina::Cl => {
                        t.cl = dq;
                        ShearLayer::Cl
                    }
                    Lamina::Emc => {
                        t.emc = dq;
                        ShearLayer::Emc
                    }
                    Lamina::Fluidic => {
                        t.fluidic = dq;
                        ShearLayer::Fluidic
                    }
                };
                if p.shear.g13[shear_layer as usize].is_none() {
                    t.g13[shear_layer as usize] = default_g13_tangent(material, key);
                }
            }
            ActuatorParam::RibsW2 => {
                if !matches!(act.params().ribs, RibLayout::Paper { .. }) {
                    return Err(InputError::Inconsistent {
                        field: param.field(),
                        rule: "needs the paper's rib layout (`kind = \"paper\"`)".into(),
                    });
                }
                // the longitudinal rib first (width t), then the transverse
                // ribs (2 w2 each)
                for (i, w) in t.rib_widths.iter_mut().enumerate() {
                    *w = if i == 0 { 0.0 } else { 2.0 };
                }
            }
            ActuatorParam::ShearCorrection => t.ks = 1.0,
            // the layer's G13 as given (the blocks of the ribs and the
            // channel's void read the fluidic layer's)
            ActuatorParam::ShearModulus(l) => t.g13[l as usize] = 1.0,
            ActuatorParam::ClRibWidth(i) | ActuatorParam::ClRibHeight(i) => {
                let slot = match param {
                    ActuatorParam::ClRibWidth(_) => t.cl_rib_widths.get_mut(i),
                    _ => t.cl_rib_heights.get_mut(i),
                };
                *slot.ok_or_else(|| InputError::Inconsistent {
                    field: param.field(),
                    rule: format!(
                        "the actuator has {} ribs on its constraining layer",
                        act.cl_ribs().len()
                    ),
                })? = 1.0;
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

/// The derivative of a material's default G13 ([`Material::default_g13`],
/// `E / (2 (1 + nu))`) with respect to one of its elastic constants (0 for
/// a constant it does not read).
fn default_g13_tangent(material: &Material, key: Elastic) -> f64 {
    match (material, key) {
        (Material::Isotropic(m), Elastic::E) => 0.5 / (1.0 + m.nu),
        (Material::Isotropic(m), Elastic::Nu) => -0.5 * m.e / ((1.0 + m.nu) * (1.0 + m.nu)),
        (Material::Orthotropic(m), Elastic::E1) => 0.5 / (1.0 + m.nu12),
        (Material::Orthotropic(m), Elastic::Nu12) => {
            -0.5 * m.e1 / ((1.0 + m.nu12) * (1.0 + m.nu12))
        }
        _ => 0.0,
    }
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
                plane_strain: act.plane_strain(),
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
    let [g_cl, g_emc, g_fluidic, g_pemc] = t.g13;
    let layers = [
        (t.h1, 0.5 * t.h, t.cl, g_cl),
        (t.h2, t.h1, t.emc, g_emc),
        (-t.h3, t.h2, t.fluidic, g_fluidic),
    ];
    let (cz0, cz1) = (-t.h3b, t.h3a);
    let linear_box = |z0: f64, z1: f64, width: f64, q: PlaneStress, g13: f64| LinearParams {
        x0: 0.0,
        x1: 0.0,
        z0,
        z1,
        width,
        q11: q.q11,
        q12: q.q12,
        q22: q.q22,
        g13,
        ks: t.ks,
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
            .map(|&(z0, z1, q, g13)| linear_box(z0, z1, t.ly, q, g13)),
    );
    if clip(0.0, channel.cx, start, len).is_some() {
        out.linear
            .push(linear_box(cz0, cz1, -t.cy, t.fluidic, g_fluidic));
        out.gas.push(gas_box(t.cy));
    }
    for (rib, &dw) in rib_list.iter().zip(&t.rib_widths) {
        if clip(rib.x0, rib.x1, start, len).is_some() {
            out.linear
                .push(linear_box(cz0, cz1, dw, t.fluidic, g_fluidic));
            out.gas.push(gas_box(-dw));
        }
    }
    // the ribs on the constraining layer: z in [H/2, H/2 + height], of
    // the layer's material
    for ((rib, &dw), &dheight) in act
        .cl_ribs()
        .iter()
        .zip(&t.cl_rib_widths)
        .zip(&t.cl_rib_heights)
    {
        if clip(rib.x0, rib.x1, start, len).is_some() {
            let top = 0.5 * t.h;
            out.linear
                .push(linear_box(top, top + dheight, dw, t.cl, g_cl));
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
        g13: g_pemc,
        ks: t.ks,
    });
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::actuator::blocks::element_blocks;

    /// Every block parameter's derivative (`element_block_tangents`)
    /// against central differences of the block construction, for every
    /// actuator parameter, on the default actuator, on one with
    /// orthotropic layers and Poisson coupling (so every Q depends on every
    /// constant) and on one with given shear moduli (the blocks' default
    /// G13's move with the constants they come from, given ones do not).
    #[test]
    fn block_tangents_match_central_differences() {
        use crate::actuator::{ActuatorParams, Orthotropic};
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
        // shear moduli given for two layers (they do not move with the
        // constants), the defaults of the others (they do)
        let mut params = ActuatorParams::default();
        params.shear.g13 = [Some(100.0), None, None, Some(0.6)];
        params.shear.correction = 0.9;
        let given_shear = Actuator::new(params).unwrap();
        // ribs on the constraining layer (their widths and heights are
        // parameters), one clipped by the partitions' element ends
        let cl_ribs = Actuator::new(ActuatorParams {
            cl_ribs: vec![
                crate::actuator::ClRib {
                    x0: 20.0,
                    x1: 35.0,
                    width: 30.0,
                    height: 0.6,
                },
                crate::actuator::ClRib {
                    x0: 50.0,
                    x1: 61.5,
                    width: 12.0,
                    height: 1.0,
                },
            ],
            ..ActuatorParams::default()
        })
        .unwrap();
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
        for act in [Actuator::default(), coupled, given_shear, cl_ribs] {
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
}

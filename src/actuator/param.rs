//! The actuator's parameters by their scene keys: the ones its integration
//! blocks depend on smoothly ([`ActuatorParam`]), with the laminae and the
//! elastic constants they name ([`Lamina`], [`Elastic`]). The design
//! sensitivities differentiate along them.

use crate::error::InputError;
use crate::field::{
    ChannelKey, ClRibKey, Elastic, Field, GeometryKey, Lamina, LaminateKey, PaperRibKey, PemcKey,
    ShearLayer,
};

use super::laminate::{Actuator, ActuatorParams, RibLayout};
use super::material::Material;

impl Elastic {
    /// The constant's value in `material`, if it has it.
    pub fn value(self, material: &Material) -> Option<f64> {
        match (material, self) {
            (Material::Isotropic(m), Elastic::E) => Some(m.e),
            (Material::Isotropic(m), Elastic::Nu) => Some(m.nu),
            (Material::Orthotropic(m), Elastic::E1) => Some(m.e1),
            (Material::Orthotropic(m), Elastic::E2) => Some(m.e2),
            (Material::Orthotropic(m), Elastic::Nu12) => Some(m.nu12),
            _ => None,
        }
    }

    fn slot(self, material: &mut Material) -> Option<&mut f64> {
        match (material, self) {
            (Material::Isotropic(m), Elastic::E) => Some(&mut m.e),
            (Material::Isotropic(m), Elastic::Nu) => Some(&mut m.nu),
            (Material::Orthotropic(m), Elastic::E1) => Some(&mut m.e1),
            (Material::Orthotropic(m), Elastic::E2) => Some(&mut m.e2),
            (Material::Orthotropic(m), Elastic::Nu12) => Some(&mut m.nu12),
            _ => None,
        }
    }
}

/// An actuator parameter the blocks depend on smoothly, named by its scene
/// key ([`ActuatorParam::name`]). Not covered: the lengths `lx` and `cx`,
/// the rib layout's `w1` and `t`, and any rib's `x0` and `x1`, which move
/// element boundaries or the clipping of a rib (and at the paper's layout
/// the last rib ends exactly at the channel's end, where the blocks are
/// not differentiable).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum ActuatorParam {
    /// `actuator.pemc.eps0`, the prestrain.
    Eps0,
    /// `actuator.pemc.e2` (MPa), the prestressed layer's Y modulus (its Q22).
    PemcE2,
    /// `actuator.pemc.p1` (MPa), the psi law's coefficients.
    PsiP1,
    /// `actuator.pemc.p2` (MPa).
    PsiP2,
    /// `actuator.pemc.p3` (MPa).
    PsiP3,
    /// `actuator.pemc.p4` (MPa).
    PsiP4,
    /// `actuator.geometry.h` (mm), the total thickness H.
    H,
    /// `actuator.geometry.h1` (mm): the CL / EMC interface.
    H1,
    /// `actuator.geometry.h2` (mm): the EMC / fluidic interface.
    H2,
    /// `actuator.geometry.h3` (mm): the fluidic / PEMC interface is at -h3.
    H3,
    /// `actuator.geometry.ly` (mm), the width.
    Ly,
    /// `actuator.channel.cy` (mm), the channel's width.
    ChannelCy,
    /// `actuator.channel.h3a` (mm): the channel's top at z = h3a.
    ChannelH3a,
    /// `actuator.channel.h3b` (mm): the channel's bottom at z = -h3b.
    ChannelH3b,
    /// `actuator.<layer>.<constant>`: an elastic constant of a linear lamina.
    Elastic(Lamina, Elastic),
    /// `actuator.ribs.w2` (mm): the transverse ribs' half width (paper layout).
    RibsW2,
    /// `actuator.laminate.shear_correction`: the shear correction factor
    /// ks. Only shear-deformable models read it (docs/model.md section
    /// 4.8); the others have zero sensitivity to it.
    ShearCorrection,
    /// `actuator.<layer>.g13` (MPa): a layer's transverse shear modulus,
    /// given or defaulted ([`Actuator::g13`]); read only by
    /// shear-deformable models, like [`ActuatorParam::ShearCorrection`].
    ShearModulus(ShearLayer),
    /// `actuator.cl_ribs.list[i].width` (mm): the total width of rib `i`
    /// on the constraining layer (docs/model.md section 4.10).
    ClRibWidth(usize),
    /// `actuator.cl_ribs.list[i].height` (mm): its height above H/2.
    ClRibHeight(usize),
}

impl ActuatorParam {
    /// Every actuator parameter that is not indexed by a rib (elastic
    /// constants of both kinds); [`ActuatorParam::for_actuator`] adds the
    /// ribs' on the constraining layer.
    pub fn all() -> Vec<ActuatorParam> {
        let mut v = vec![
            ActuatorParam::Eps0,
            ActuatorParam::PemcE2,
            ActuatorParam::PsiP1,
            ActuatorParam::PsiP2,
            ActuatorParam::PsiP3,
            ActuatorParam::PsiP4,
            ActuatorParam::H,
            ActuatorParam::H1,
            ActuatorParam::H2,
            ActuatorParam::H3,
            ActuatorParam::Ly,
            ActuatorParam::ChannelCy,
            ActuatorParam::ChannelH3a,
            ActuatorParam::ChannelH3b,
        ];
        for &l in Lamina::ALL {
            for &k in Elastic::ALL {
                v.push(ActuatorParam::Elastic(l, k));
            }
        }
        v.push(ActuatorParam::RibsW2);
        v.push(ActuatorParam::ShearCorrection);
        for &l in ShearLayer::ALL {
            v.push(ActuatorParam::ShearModulus(l));
        }
        v
    }

    /// The parameters `actuator` has (its materials' constants, `w2` only
    /// with the paper's rib layout; the shear data always, whatever model
    /// the finger uses; the width and height of each rib on the
    /// constraining layer, rib by rib).
    pub fn for_actuator(actuator: &Actuator) -> Vec<ActuatorParam> {
        let mut v: Vec<ActuatorParam> = ActuatorParam::all()
            .into_iter()
            .filter(|p| p.value(actuator).is_some())
            .collect();
        for i in 0..actuator.cl_ribs().len() {
            v.extend([ActuatorParam::ClRibWidth(i), ActuatorParam::ClRibHeight(i)]);
        }
        v
    }

    /// The parameter of a scene key ([`ActuatorParam::name`]), a rib's
    /// (`actuator.cl_ribs.list[2].width`) for any index.
    pub fn from_name(name: &str) -> Option<ActuatorParam> {
        if let Some(rest) = name.strip_prefix("actuator.cl_ribs.list[") {
            let (index, key) = rest.split_once("].")?;
            let i: usize = index.parse().ok()?;
            return match key {
                "width" => Some(ActuatorParam::ClRibWidth(i)),
                "height" => Some(ActuatorParam::ClRibHeight(i)),
                _ => None,
            };
        }
        ActuatorParam::all().into_iter().find(|p| p.name() == name)
    }

    /// The scene key (`actuator.pemc.eps0`, `actuator.pemc.p1`,
    /// `actuator.cl.e`, ...): the library's field, the psi law's
    /// coefficients without `law`.
    pub fn name(self) -> String {
        match self.field() {
            Field::Pemc(k) => format!("actuator.pemc.{k}"),
            Field::ClRib(i, k) => format!("actuator.cl_ribs.list[{i}].{k}"),
            f => f.to_string(),
        }
    }

    /// The field the library names it by (`actuator.pemc.law.p1` for
    /// [`ActuatorParam::PsiP1`]).
    pub fn field(self) -> Field {
        match self {
            ActuatorParam::Eps0 => Field::Pemc(PemcKey::Eps0),
            ActuatorParam::PemcE2 => Field::Pemc(PemcKey::E2),
            ActuatorParam::PsiP1 => Field::Pemc(PemcKey::P1),
            ActuatorParam::PsiP2 => Field::Pemc(PemcKey::P2),
            ActuatorParam::PsiP3 => Field::Pemc(PemcKey::P3),
            ActuatorParam::PsiP4 => Field::Pemc(PemcKey::P4),
            ActuatorParam::H => Field::Geometry(GeometryKey::H),
            ActuatorParam::H1 => Field::Geometry(GeometryKey::H1),
            ActuatorParam::H2 => Field::Geometry(GeometryKey::H2),
            ActuatorParam::H3 => Field::Geometry(GeometryKey::H3),
            ActuatorParam::Ly => Field::Geometry(GeometryKey::Ly),
            ActuatorParam::ChannelCy => Field::Channel(ChannelKey::Cy),
            ActuatorParam::ChannelH3a => Field::Channel(ChannelKey::H3a),
            ActuatorParam::ChannelH3b => Field::Channel(ChannelKey::H3b),
            ActuatorParam::Elastic(l, k) => Field::Material(l, k),
            ActuatorParam::RibsW2 => Field::PaperRib(PaperRibKey::W2),
            ActuatorParam::ShearCorrection => Field::Laminate(LaminateKey::ShearCorrection),
            ActuatorParam::ShearModulus(l) => Field::ShearModulus(l),
            ActuatorParam::ClRibWidth(i) => Field::ClRib(i, ClRibKey::Width),
            ActuatorParam::ClRibHeight(i) => Field::ClRib(i, ClRibKey::Height),
        }
    }

    /// The parameter's value in `actuator` (`None`: it has no such
    /// parameter, as `e1` of an isotropic layer).
    pub fn value(self, actuator: &Actuator) -> Option<f64> {
        let p = actuator.params();
        let g = &p.geometry;
        let c = &p.channel;
        let law = &p.pemc.law;
        Some(match self {
            ActuatorParam::Eps0 => p.pemc.eps0,
            ActuatorParam::PemcE2 => p.pemc.e2,
            ActuatorParam::PsiP1 => law.p1,
            ActuatorParam::PsiP2 => law.p2,
            ActuatorParam::PsiP3 => law.p3,
            ActuatorParam::PsiP4 => law.p4,
            ActuatorParam::H => g.h,
            ActuatorParam::H1 => g.h1,
            ActuatorParam::H2 => g.h2,
            ActuatorParam::H3 => g.h3,
            ActuatorParam::Ly => g.ly,
            ActuatorParam::ChannelCy => c.cy,
            ActuatorParam::ChannelH3a => c.h3a,
            ActuatorParam::ChannelH3b => c.h3b,
            ActuatorParam::Elastic(l, k) => k.value(material(p, l))?,
            ActuatorParam::RibsW2 => match p.ribs {
                RibLayout::Paper { w2, .. } => w2,
                _ => return None,
            },
            ActuatorParam::ShearCorrection => p.shear.correction,
            ActuatorParam::ShearModulus(l) => actuator.g13(l),
            ActuatorParam::ClRibWidth(i) => p.cl_ribs.get(i)?.width,
            ActuatorParam::ClRibHeight(i) => p.cl_ribs.get(i)?.height,
        })
    }

    /// `actuator` with this parameter set to `value`, validated again (a
    /// layer's G13 is then given, no longer the default from its
    /// constants).
    pub fn with_value(self, actuator: &Actuator, value: f64) -> Result<Actuator, InputError> {
        let mut p = actuator.params().clone();
        let missing = || InputError::Inconsistent {
            field: self.field(),
            rule: "the actuator has no such parameter".into(),
        };
        let slot: &mut f64 = match self {
            ActuatorParam::Eps0 => &mut p.pemc.eps0,
            ActuatorParam::PemcE2 => &mut p.pemc.e2,
            ActuatorParam::PsiP1 => &mut p.pemc.law.p1,
            ActuatorParam::PsiP2 => &mut p.pemc.law.p2,
            ActuatorParam::PsiP3 => &mut p.pemc.law.p3,
            ActuatorParam::PsiP4 => &mut p.pemc.law.p4,
            ActuatorParam::H => &mut p.geometry.h,
            ActuatorParam::H1 => &mut p.geometry.h1,
            ActuatorParam::H2 => &mut p.geometry.h2,
            ActuatorParam::H3 => &mut p.geometry.h3,
            ActuatorParam::Ly => &mut p.geometry.ly,
            ActuatorParam::ChannelCy => &mut p.channel.cy,
            ActuatorParam::ChannelH3a => &mut p.channel.h3a,
            ActuatorParam::ChannelH3b => &mut p.channel.h3b,
            ActuatorParam::Elastic(l, k) => {
                let m = match l {
                    Lamina::Cl => &mut p.cl,
                    Lamina::Emc => &mut p.emc,
                    Lamina::Fluidic => &mut p.fluidic,
                };
                k.slot(m).ok_or_else(missing)?
            }
            ActuatorParam::RibsW2 => match &mut p.ribs {
                RibLayout::Paper { w2, .. } => w2,
                _ => return Err(missing()),
            },
            ActuatorParam::ShearCorrection => &mut p.shear.correction,
            ActuatorParam::ShearModulus(l) => p.shear.g13[l as usize].insert(value),
            ActuatorParam::ClRibWidth(i) => &mut p.cl_ribs.get_mut(i).ok_or_else(missing)?.width,
            ActuatorParam::ClRibHeight(i) => &mut p.cl_ribs.get_mut(i).ok_or_else(missing)?.height,
        };
        *slot = value;
        Actuator::new(p)
    }
}

fn material(p: &ActuatorParams, l: Lamina) -> &Material {
    match l {
        Lamina::Cl => &p.cl,
        Lamina::Emc => &p.emc,
        Lamina::Fluidic => &p.fluidic,
    }
}

//! Resolution of `[actuator]`: geometry, channel, ribs and the layers'
//! materials.

use crate::actuator::{
    Actuator, ActuatorParams, ClRib, Isotropic, Material, Orthotropic, Prestressed, PsiLaw, Rib,
    RibLayout, TransverseShear,
};
use crate::error::InputError;
use crate::scene::fields::{
    forbid, inconsistent, name_written, Elastic, Lamina, PaperRibKey, SceneKey,
};
use crate::scene::schema::*;

/// The actuator of `a`, its keys written out in `echo`. `written`: whether
/// the scene gives a key (a rule between keys names the one given).
pub(super) fn resolve_actuator(
    a: &ActuatorSection,
    echo: &mut ActuatorSection,
    written: impl Fn(SceneKey) -> bool,
) -> Result<Actuator, InputError> {
    let d = ActuatorParams::default();
    let (geometry, channel) = (a.geometry.resolve(), a.channel.resolve());
    (echo.geometry, echo.channel) = (geometry.into(), channel.into());
    let (ribs, ribs_echo) = resolve_ribs(&a.ribs, &d.ribs)?;
    echo.ribs = ribs_echo;
    let (cl, e) = resolve_material(&a.cl, d.cl, Lamina::Cl)?;
    echo.cl = e;
    let (emc, e) = resolve_material(&a.emc, d.emc, Lamina::Emc)?;
    echo.emc = e;
    let (fluidic, e) = resolve_material(&a.fluidic, d.fluidic, Lamina::Fluidic)?;
    echo.fluidic = e;
    let pm = &a.pemc;
    let [q1, q2, q3, q4] = d.pemc.law.to_array();
    let pemc = Prestressed {
        e2: pm.e2.unwrap_or(d.pemc.e2),
        law: PsiLaw {
            p1: pm.p1.unwrap_or(q1),
            p2: pm.p2.unwrap_or(q2),
            p3: pm.p3.unwrap_or(q3),
            p4: pm.p4.unwrap_or(q4),
        },
        eps0: pm.eps0.unwrap_or(d.pemc.eps0),
    };
    echo.pemc = PemcSection {
        eps0: Some(pemc.eps0),
        e2: Some(pemc.e2),
        p1: Some(pemc.law.p1),
        p2: Some(pemc.law.p2),
        p3: Some(pemc.law.p3),
        p4: Some(pemc.law.p4),
        // the shear data echo as given: a scene without them resolves as
        // it always did
        g13: pm.g13,
    };
    let shear = TransverseShear {
        correction: a.laminate.shear_correction.unwrap_or(d.shear.correction),
        g13: [a.cl.g13, a.emc.g13, a.fluidic.g13, pm.g13],
    };
    echo.laminate = a.laminate.clone();
    // the ribs on the constraining layer echo as given: a scene without
    // them resolves as it always did
    echo.cl_ribs = a.cl_ribs.clone();
    let cl_ribs = a
        .cl_ribs
        .list
        .iter()
        .flatten()
        .map(|e| ClRib {
            x0: e.x0,
            x1: e.x1,
            width: e.width,
            height: e.height,
        })
        .collect();
    Actuator::checked(ActuatorParams {
        geometry,
        channel,
        ribs,
        cl,
        emc,
        fluidic,
        pemc,
        shear,
        plane_strain: a.laminate.plane_strain.unwrap_or(d.plane_strain),
        cl_ribs,
    })
    .map_err(|r| name_written(r.error, &r.against, written))
}

fn resolve_ribs(
    r: &RibsSection,
    default: &RibLayout,
) -> Result<(RibLayout, RibsSection), InputError> {
    let kind = r.kind.unwrap_or(if r.list.is_some() {
        RibKind::List
    } else {
        RibKind::Paper
    });
    let paper_keys = [
        (PaperRibKey::W1.into(), r.w1.is_some()),
        (PaperRibKey::W2.into(), r.w2.is_some()),
        (PaperRibKey::T.into(), r.t.is_some()),
    ];
    let list_key = [(SceneKey::RibsList, r.list.is_some())];
    let mut echo = RibsSection {
        kind: Some(kind),
        ..RibsSection::default()
    };
    let layout = match kind {
        RibKind::Paper => {
            forbid(&list_key, "only used with kind = \"list\"")?;
            let (dw1, dw2, dt) = match *default {
                RibLayout::Paper { w1, w2, t } => (w1, w2, t),
                _ => (8.0, 6.0, 2.0),
            };
            let (w1, w2, t) = (r.w1.unwrap_or(dw1), r.w2.unwrap_or(dw2), r.t.unwrap_or(dt));
            (echo.w1, echo.w2, echo.t) = (Some(w1), Some(w2), Some(t));
            RibLayout::Paper { w1, w2, t }
        }
        RibKind::List => {
            forbid(&paper_keys, "only used with kind = \"paper\"")?;
            let Some(list) = &r.list else {
                return Err(inconsistent(
                    SceneKey::RibsList,
                    "required with kind = \"list\" (an empty list means no ribs)",
                ));
            };
            echo.list = Some(list.clone());
            RibLayout::Explicit(
                list.iter()
                    .map(|e| Rib {
                        x0: e.x0,
                        x1: e.x1,
                        width: e.width,
                    })
                    .collect(),
            )
        }
        RibKind::None => {
            forbid(&paper_keys, "not used with kind = \"none\"")?;
            forbid(&list_key, "not used with kind = \"none\"")?;
            RibLayout::None
        }
    };
    Ok((layout, echo))
}

fn resolve_material(
    m: &MaterialSection,
    default: Material,
    layer: Lamina,
) -> Result<(Material, MaterialSection), InputError> {
    let iso_set = m.e.is_some() || m.nu.is_some();
    let ortho_set = m.e1.is_some() || m.e2.is_some() || m.nu12.is_some();
    let default_kind = match default {
        Material::Isotropic(_) => MaterialKind::Isotropic,
        Material::Orthotropic(_) => MaterialKind::Orthotropic,
    };
    let kind = m.kind.unwrap_or(match (iso_set, ortho_set) {
        (true, false) => MaterialKind::Isotropic,
        (false, true) => MaterialKind::Orthotropic,
        _ => default_kind,
    });
    let key = |k: Elastic| SceneKey::Material(layer, k);
    // a value of this kind: the file's, else the layer's default if it is
    // of the same kind, else required
    let value = |k: Elastic, v: Option<f64>, fallback: Option<f64>| -> Result<f64, InputError> {
        v.or(fallback).ok_or_else(|| {
            inconsistent(
                key(k),
                format!(
                    "required: the layer's default material is {}, so a {} one needs all its keys",
                    kind_name(default_kind),
                    kind_name(kind)
                ),
            )
        })
    };
    let mut echo = MaterialSection {
        kind: Some(kind),
        g13: m.g13,
        ..MaterialSection::default()
    };
    let material = match kind {
        MaterialKind::Isotropic => {
            forbid(
                &[
                    (key(Elastic::E1), m.e1.is_some()),
                    (key(Elastic::E2), m.e2.is_some()),
                    (key(Elastic::Nu12), m.nu12.is_some()),
                ],
                "an orthotropic key, but the layer is isotropic (keys e, nu)",
            )?;
            let d = match default {
                Material::Isotropic(d) => Some(d),
                Material::Orthotropic(_) => None,
            };
            let iso = Isotropic {
                e: value(Elastic::E, m.e, d.map(|d| d.e))?,
                nu: value(Elastic::Nu, m.nu, d.map(|d| d.nu))?,
            };
            (echo.e, echo.nu) = (Some(iso.e), Some(iso.nu));
            Material::Isotropic(iso)
        }
        MaterialKind::Orthotropic => {
            forbid(
                &[
                    (key(Elastic::E), m.e.is_some()),
                    (key(Elastic::Nu), m.nu.is_some()),
                ],
                "an isotropic key, but the layer is orthotropic (keys e1, e2, nu12)",
            )?;
            let d = match default {
                Material::Orthotropic(d) => Some(d),
                Material::Isotropic(_) => None,
            };
            let o = Orthotropic {
                e1: value(Elastic::E1, m.e1, d.map(|d| d.e1))?,
                e2: value(Elastic::E2, m.e2, d.map(|d| d.e2))?,
                nu12: value(Elastic::Nu12, m.nu12, d.map(|d| d.nu12))?,
            };
            (echo.e1, echo.e2, echo.nu12) = (Some(o.e1), Some(o.e2), Some(o.nu12));
            Material::Orthotropic(o)
        }
    };
    Ok((material, echo))
}

fn kind_name(k: MaterialKind) -> &'static str {
    match k {
        MaterialKind::Isotropic => "isotropic",
        MaterialKind::Orthotropic => "orthotropic",
    }
}

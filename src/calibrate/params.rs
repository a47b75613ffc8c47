//! The unknowns of a fit: parameter names resolved to the sensitivities'
//! [`Param`]s, each shared by every specimen or one per specimen (its
//! `own` tables), with a start value and bounds.

use serde::Serialize;

use super::options::{inconsistent, CalibrateOptions, MAX_UNKNOWNS};
use crate::actuator::ActuatorParam;
use crate::error::InputError;
use crate::field::{Elastic, Field};
use crate::measure::Manifest;
use crate::sensitivity::Param;

/// One unknown of a fit.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Unknown {
    /// The scene key (`actuator.pemc.eps0`, `load.kappa`, ...).
    pub key: String,
    /// The specimen it belongs to (`None`: shared by all).
    pub specimen: Option<String>,
    /// The parameter of the sensitivities (for a camera frame's
    /// parameters, [`Param::Target`], which is never fitted otherwise).
    #[serde(skip)]
    pub param: Param,
    /// A camera frame's parameter instead: the specimen's test (from 0)
    /// and the component (0: `angle_deg`, 1: `x_mm`, 2: `z_mm`).
    #[serde(skip)]
    pub camera: Option<(usize, usize)>,
    /// The start value (the manifest's).
    pub start: f64,
    /// Lower bound.
    pub lower: f64,
    /// Upper bound.
    pub upper: f64,
}

impl Unknown {
    /// `key`, or `key[specimen]` for a specimen's own parameter.
    pub fn label(&self) -> String {
        match (&self.specimen, self.camera) {
            (Some(s), Some((t, _))) => format!("{}[{s}, test {}]", self.key, t + 1),
            (Some(s), None) => format!("{}[{s}]", self.key),
            (None, _) => self.key.clone(),
        }
    }

    /// Whether this is a parameter of the model (not of a camera frame).
    pub fn is_model(&self) -> bool {
        self.camera.is_none()
    }

    /// Whether the unknown applies to specimen `name`.
    pub fn applies_to(&self, name: &str) -> bool {
        self.specimen.as_deref().is_none_or(|s| s == name)
    }
}

/// The parameter a user's name means.
fn parse(name: &str) -> Result<Param, InputError> {
    let n = name.trim();
    let alias = match n {
        "eps0" => Some("actuator.pemc.eps0"),
        "kappa" => Some("load.kappa"),
        "p1" => Some("actuator.pemc.p1"),
        "p2" => Some("actuator.pemc.p2"),
        "p3" => Some("actuator.pemc.p3"),
        "p4" => Some("actuator.pemc.p4"),
        "shear_correction" => Some("actuator.laminate.shear_correction"),
        _ => None,
    };
    let found = alias
        .and_then(Param::from_name)
        .or_else(|| Param::from_name(n))
        .or_else(|| Param::from_name(&format!("actuator.{n}")));
    match found {
        Some(p @ (Param::Actuator(_) | Param::Kappa)) => Ok(p),
        _ => Err(InputError::Unrecognised {
            field: Field::key("fit"),
            value: n.to_string(),
            rule: "not a parameter a calibration can fit: an actuator parameter of the sensitivities (docs/model.md, \"Sensitivities\": eps0, p1..p4, pemc.e2, cl.e, emc.e1, fluidic.nu, geometry.h, shear_correction, cl.g13, ...), kappa, or camera (every camera frame's angle and offset)".into(),
        }),
    }
}

/// Where a parameter may go: bounds that keep the actuator buildable.
fn bounds(p: Param, start: f64) -> (f64, f64) {
    let positive = (start.abs() * 1e-6, f64::INFINITY);
    match p {
        Param::Actuator(ActuatorParam::Eps0) => (0.0, 1.0),
        Param::Actuator(ActuatorParam::PsiP2 | ActuatorParam::PsiP3 | ActuatorParam::PsiP4) => {
            (f64::NEG_INFINITY, f64::INFINITY)
        }
        Param::Actuator(ActuatorParam::Elastic(_, Elastic::Nu | Elastic::Nu12)) => (-0.99, 0.499),
        // (a scene's own bound, which a fitted value must keep)
        Param::Kappa => (positive.0, crate::finger::MAX_KAPPA),
        _ => positive,
    }
}

/// The value of `p` in a specimen's scene (`kappa`: its `load.kappa`, the
/// only load key a manifest may set).
fn value_in(p: Param, scene: &crate::scene::Scene) -> Option<f64> {
    p.value(&scene.actuator, &scene.load, None)
}

/// The camera frames' components: name, bounds.
const CAMERA: [(&str, f64, f64); 3] = [
    ("camera.angle_deg", f64::NEG_INFINITY, f64::INFINITY),
    ("camera.x_mm", f64::NEG_INFINITY, f64::INFINITY),
    ("camera.z_mm", f64::NEG_INFINITY, f64::INFINITY),
];

/// Refuses a fit of `n` unknowns to `manifest` unless it has more
/// measured values than that (a marker row gives two); `what` names the
/// data in the message ("the manifest").
pub(crate) fn enough_values(manifest: &Manifest, n: usize, what: &str) -> Result<(), InputError> {
    let points: usize = manifest
        .specimens
        .iter()
        .flat_map(|s| &s.tests)
        .map(|t| match &t.data {
            crate::measure::TestData::Markers { rows, .. } => 2 * rows.len(),
            d => d.len(),
        })
        .sum();
    if points <= n {
        return Err(inconsistent(
            "fit",
            format!("{n} unknowns need more than {n} measured values; {what} has {points}"),
        ));
    }
    Ok(())
}

/// An angle in degrees taken into (-180, 180].
fn wrap_degrees(a: f64) -> f64 {
    let w = a.rem_euclid(360.0);
    if w > 180.0 {
        w - 360.0
    } else {
        w
    }
}

/// Three unknowns for every markers test with a camera frame.
fn camera_unknowns(manifest: &Manifest, out: &mut Vec<Unknown>) -> Result<(), InputError> {
    let before = out.len();
    for s in &manifest.specimens {
        for (t, test) in s.tests.iter().enumerate() {
            let crate::measure::TestData::Markers {
                camera: Some(c), ..
            } = &test.data
            else {
                continue;
            };
            for (k, (key, lower, upper)) in CAMERA.into_iter().enumerate() {
                let start = [c.angle_deg, c.x_mm, c.z_mm][k];
                // an angle is fitted within half a turn either side of its
                // start, taken into (-180, 180] (the manifest admits a
                // whole turn either way: -356 and 4 degrees are one frame)
                let (start, lower, upper) = if k == 0 {
                    let a = wrap_degrees(start);
                    (a, a - 180.0, a + 180.0)
                } else {
                    (start, lower, upper)
                };
                out.push(Unknown {
                    key: key.to_string(),
                    specimen: Some(s.name.clone()),
                    param: Param::Target,
                    camera: Some((t, k)),
                    start: start.clamp(lower, upper),
                    lower,
                    upper,
                });
            }
        }
    }
    if out.len() == before {
        return Err(inconsistent(
            "fit",
            "names camera, but no markers test has a camera frame".into(),
        ));
    }
    Ok(())
}

/// The unknowns of `options.fit` over `manifest`'s specimens.
pub(crate) fn unknowns(
    manifest: &Manifest,
    options: &CalibrateOptions,
) -> Result<Vec<Unknown>, InputError> {
    let mut out: Vec<Unknown> = Vec::new();
    let mut seen: Vec<Param> = Vec::new();
    let mut cameras = false;
    for name in &options.fit {
        if name.trim() == "camera" {
            if cameras {
                return Err(inconsistent("fit", "names camera twice".into()));
            }
            cameras = true;
            camera_unknowns(manifest, &mut out)?;
            continue;
        }
        let p = parse(name)?;
        if seen.contains(&p) {
            return Err(inconsistent("fit", format!("names {} twice", p.name())));
        }
        seen.push(p);
        let key = p.name();
        let own = manifest.specimens.iter().any(|s| s.own.contains(&key));
        let push = |out: &mut Vec<Unknown>, specimen: Option<String>, start: f64| {
            let (lower, upper) = bounds(p, start);
            out.push(Unknown {
                key: key.clone(),
                specimen,
                param: p,
                camera: None,
                start: start.clamp(lower, upper),
                lower,
                upper,
            });
        };
        let missing = |s: &str| {
            inconsistent(
                "fit",
                format!(
                    "specimen {s:?} has no parameter {key} ({})",
                    match p {
                        Param::Actuator(
                            ActuatorParam::ClRibWidth(_) | ActuatorParam::ClRibHeight(_),
                        ) => "its constraining layer has no such rib",
                        Param::Actuator(ActuatorParam::RibsW2) =>
                            "its ribs are not the paper's layout",
                        _ => "its materials lack it",
                    }
                ),
            )
        };
        if own {
            for s in &manifest.specimens {
                let v = value_in(p, &s.scene).ok_or_else(|| missing(&s.name))?;
                push(&mut out, Some(s.name.clone()), v);
            }
        } else {
            let mut first: Option<f64> = None;
            for s in &manifest.specimens {
                let v = value_in(p, &s.scene).ok_or_else(|| missing(&s.name))?;
                match first {
                    None => first = Some(v),
                    Some(f) if (f - v).abs() > 1e-12 * f.abs().max(v.abs()) => {
                        return Err(inconsistent(
                            "fit",
                            format!(
                                "{key} is shared (no specimen lists it in its own tables) but the specimens give it different values ({f} and {v} in {:?}); list it in every specimen's own tables to fit it per specimen",
                                s.name
                            ),
                        ))
                    }
                    Some(_) => {}
                }
            }
            push(&mut out, None, first.unwrap_or_default());
        }
    }
    // counted whole first (the manifest's own bounds keep the list short),
    // so the message gives the real number
    if out.len() > MAX_UNKNOWNS {
        return Err(InputError::OutOfRange {
            field: Field::key("fit"),
            value: out.len() as f64,
            rule: format!(
                "more than {MAX_UNKNOWNS} unknowns, the limit (a specimen's own parameter counts once per specimen, a camera frame three times)"
            ),
        });
    }
    Ok(out)
}

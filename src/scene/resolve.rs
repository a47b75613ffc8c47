//! Resolution: the defaults of absent keys, and every value checked
//! through the library's validating constructors into library types.

use std::f64::consts::FRAC_PI_2;

use crate::actuator::{
    Actuator, ActuatorParams, Channel, Geometry, Isotropic, Material, Orthotropic, Prestressed,
    PsiLaw, Rib, RibLayout,
};
use crate::blocks::{Partition, MIN_ELEMENT_FRACTION};
use crate::error::InputError;
use crate::finger::{Load, SolveOptions, Strategy, MAX_SAMPLES_PER_ELEMENT};
use crate::gripper::{GripperParams, PalmSpec};
use crate::model::ModelId;

use super::fields::{
    finite, forbid, inconsistent, positive, require, scene_input, ElasticKey, GraspKey, GripperKey,
    Layer, LoadKey, ModelKey, PaperRibKey, PartitionKey, SceneKey, SolveKey,
};
use super::schema::*;
use super::Scene;

// ------------------------------------------------------------ defaults

/// Default number of equal elements (the paper's N).
pub const DEFAULT_ELEMENTS: usize = 8;
/// Most elements of a partition: 1 / [`MIN_ELEMENT_FRACTION`].
const MAX_ELEMENTS: usize = 1000;
/// Default mounting angle of `[gripper]` (deg; the paper's Sec. 5).
pub const DEFAULT_MOUNTING_ANGLE_DEG: f64 = 60.0;
/// Default overlap of `[gripper]` (mm; the paper's Sec. 5).
pub const DEFAULT_OVERLAP_MM: f64 = 20.0;
/// Default grasping size of kinds "size" and "cuboid" (mm; Sec. 5.1.2).
pub const DEFAULT_GRASP_SIZE_MM: f64 = 100.0;
/// Default friction of kind "cuboid" (N per finger; Sec. 5.1.2).
pub const DEFAULT_CUBOID_FRICTION_N: f64 = 0.3;
/// Default sphere radius (mm; Sec. 5.2.2).
pub const DEFAULT_SPHERE_RADIUS_MM: f64 = 50.0;
/// Default lifting force of kind "sphere" (N per finger; Sec. 5.2.2).
pub const DEFAULT_SPHERE_LIFT_N: f64 = 0.5;
/// Default grasping angle of kind "sphere" (deg).
pub const DEFAULT_SPHERE_BETA_DEG: f64 = 20.0;

// ------------------------------------------------------------ the resolved scene

/// How the finger is split, resolved.
#[derive(Debug, Clone, PartialEq)]
pub enum PartitionPlan {
    /// A fixed partition (equal or custom elements).
    Fixed(Partition),
    /// Refined until the estimated tip error is at most `tip_tol_mm`
    /// ([`crate::solve_to_tip_tolerance`]): equal elements doubled from
    /// `start`, or without it the fastest configuration for the tolerance.
    TipTolerance {
        tip_tol_mm: f64,
        start: Option<usize>,
    },
    /// The automatic partition ([`crate::solve_auto`]): boundaries on the
    /// material changes, elements split until every one turns within the
    /// CCM's slope limit. A finger scene chooses it at its load, a gripper
    /// scene at the unloaded, zero-pressure state (the gripper's reference).
    Auto,
}

/// A resolved grasp (angles in degrees, as in the file).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GraspSpec {
    Size {
        pressure_kpa: f64,
        d_mm: f64,
        beta_deg: f64,
    },
    Cuboid {
        pressure_kpa: f64,
        d_mm: f64,
        friction_n: f64,
    },
    Sphere {
        pressure_kpa: f64,
        r_mm: f64,
        lift_n: f64,
        beta_deg: f64,
    },
}

impl GraspSpec {
    /// The grasp's kind.
    pub fn kind(&self) -> GraspKind {
        match self {
            GraspSpec::Size { .. } => GraspKind::Size,
            GraspSpec::Cuboid { .. } => GraspKind::Cuboid,
            GraspSpec::Sphere { .. } => GraspKind::Sphere,
        }
    }

    /// The kind's name in a scene file.
    pub fn name(&self) -> &'static str {
        match self {
            GraspSpec::Size { .. } => "size",
            GraspSpec::Cuboid { .. } => "cuboid",
            GraspSpec::Sphere { .. } => "sphere",
        }
    }
}

/// A resolved `[gripper]`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GripperScene {
    /// The design (mounting angle in rad).
    pub params: GripperParams,
    /// Judge the grasp's stability: the restricted Hessian's inertia, an
    /// unstable grasp is invalid (`solve.stability`, default true).
    pub stability: bool,
    /// The grasp to solve; `None`: the gripper at rest.
    pub grasp: Option<GraspSpec>,
}

impl SceneFile {
    /// Checks every value and builds the scene (the defaults fill absent
    /// keys). Errors name the key by its TOML path.
    pub fn resolve(&self) -> Result<Scene, InputError> {
        resolve(self)
    }
}

fn resolve(f: &SceneFile) -> Result<Scene, InputError> {
    let mut file = SceneFile::default();
    let model = resolve_model(&f.model)?;
    file.model.name = Some(model.name().to_string());
    let actuator = resolve_actuator(&f.actuator, &mut file.actuator)?;
    let lx = actuator.geometry().lx;
    let gripper_scene = f.gripper.is_some();

    // partition
    let p = &f.partition;
    let partition = match (&p.lengths, p.tip_tol_mm) {
        (Some(_), _) if p.elements.is_some() => {
            return Err(inconsistent(
                PartitionKey::Lengths,
                "give either elements or lengths, not both",
            ))
        }
        (Some(_), Some(_)) => {
            return Err(inconsistent(
                PartitionKey::TipTolMm,
                "refines equal elements; it cannot be combined with lengths",
            ))
        }
        (Some(lengths), None) => {
            // before any copy of the list
            if lengths.len() > MAX_ELEMENTS {
                return Err(inconsistent(
                    PartitionKey::Lengths,
                    format!(
                        "{} entries, more than the {MAX_ELEMENTS} allowed (each element at least {MIN_ELEMENT_FRACTION} lx long)",
                        lengths.len()
                    ),
                ));
            }
            file.partition.lengths = Some(lengths.clone());
            PartitionPlan::Fixed(Partition::custom(lengths.clone(), lx).map_err(scene_input)?)
        }
        (None, Some(tol)) => {
            if gripper_scene {
                return Err(inconsistent(
                    PartitionKey::TipTolMm,
                    "not supported in a gripper scene (give elements or lengths)",
                ));
            }
            positive(PartitionKey::TipTolMm, tol)?;
            // a count asks for equal elements doubled from it; absent or
            // "auto", the fastest configuration for the tolerance
            let start = match p.elements {
                None | Some(Elements::Auto) => None,
                Some(Elements::Count(n)) => {
                    Partition::equal(lx, n).map_err(scene_input)?;
                    Some(n)
                }
            };
            file.partition.tip_tol_mm = Some(tol);
            file.partition.elements = Some(match start {
                Some(n) => Elements::Count(n),
                None => Elements::Auto,
            });
            PartitionPlan::TipTolerance {
                tip_tol_mm: tol,
                start,
            }
        }
        (None, None) => match p.elements.unwrap_or(Elements::Count(DEFAULT_ELEMENTS)) {
            Elements::Count(n) => {
                file.partition.elements = Some(Elements::Count(n));
                PartitionPlan::Fixed(Partition::equal(lx, n).map_err(scene_input)?)
            }
            Elements::Auto => {
                file.partition.elements = Some(Elements::Auto);
                PartitionPlan::Auto
            }
        },
    };

    // load
    let l = &f.load;
    let load = if gripper_scene {
        forbid(
            &[
                (LoadKey::PressureKpa.into(), l.pressure_kpa.is_some()),
                (LoadKey::Kappa.into(), l.kappa.is_some()),
                (LoadKey::Fx.into(), l.fx.is_some()),
                (LoadKey::Fz.into(), l.fz.is_some()),
            ],
            "not used in a gripper scene: the grasp solves for the tip load (set the pressure with gripper.grasp.pressure_kpa)",
        )?;
        Load::unloaded()
    } else {
        let d = Load::default();
        let kpa = finite(LoadKey::PressureKpa, l.pressure_kpa.unwrap_or(0.0))?;
        let load = Load {
            pressure: kpa * 1e-3,
            kappa: l.kappa.unwrap_or(d.kappa),
            fx: l.fx.unwrap_or(d.fx),
            fz: l.fz.unwrap_or(d.fz),
        };
        load.validate().map_err(scene_input)?;
        file.load = LoadSection {
            pressure_kpa: Some(kpa),
            kappa: Some(load.kappa),
            fx: Some(load.fx),
            fz: Some(load.fz),
        };
        load
    };

    // solver settings
    let s = &f.solve;
    let d = SolveOptions::default();
    let options = if gripper_scene {
        forbid(
            &[
                (SolveKey::Rtol.into(), s.rtol.is_some()),
                (SolveKey::MaxIter.into(), s.max_iter.is_some()),
                (SolveKey::Strategy.into(), s.strategy.is_some()),
                (SolveKey::SamplesPerElement.into(), s.samples_per_element.is_some()),
                (SolveKey::Shape.into(), s.shape.is_some()),
                (SolveKey::Continuation.into(), s.continuation.is_some()),
                (SolveKey::MaxStep.into(), s.max_step.is_some()),
            ],
            "not used in a gripper scene: grasps are solved with the gripper's own settings (only solve.stability applies)",
        )?;
        file.solve.stability = Some(s.stability.unwrap_or(true));
        d
    } else {
        let o = SolveOptions {
            rtol: s.rtol.unwrap_or(d.rtol),
            max_iter: s.max_iter.unwrap_or(d.max_iter),
            strategy: match s.strategy {
                Some(SceneStrategy::Coupled) => Strategy::Coupled,
                Some(SceneStrategy::Auto) | None => Strategy::Auto,
            },
            shape: s.shape.unwrap_or(d.shape),
            stability: s.stability.unwrap_or(d.stability),
            samples_per_element: s.samples_per_element.unwrap_or(d.samples_per_element),
            continuation: s.continuation.unwrap_or(d.continuation),
            max_step: s.max_step.unwrap_or(d.max_step),
        };
        positive(SolveKey::Rtol, o.rtol)?;
        positive(SolveKey::MaxStep, o.max_step)?;
        require(
            o.max_iter >= 1,
            SolveKey::MaxIter,
            o.max_iter as f64,
            "must be at least 1",
        )?;
        require(
            (1..=MAX_SAMPLES_PER_ELEMENT).contains(&o.samples_per_element),
            SolveKey::SamplesPerElement,
            o.samples_per_element as f64,
            format!("must lie in [1, {MAX_SAMPLES_PER_ELEMENT}]"),
        )?;
        file.solve = SolveSection {
            rtol: Some(o.rtol),
            max_iter: Some(o.max_iter),
            strategy: Some(match o.strategy {
                Strategy::Auto => SceneStrategy::Auto,
                Strategy::Coupled => SceneStrategy::Coupled,
            }),
            samples_per_element: Some(o.samples_per_element),
            shape: Some(o.shape),
            stability: Some(o.stability),
            continuation: Some(o.continuation),
            max_step: Some(o.max_step),
        };
        o
    };

    // gripper
    let gripper = match &f.gripper {
        None => None,
        Some(g) => {
            let (scene, echo) = resolve_gripper(g, s.stability.unwrap_or(true))?;
            file.gripper = Some(echo);
            Some(scene)
        }
    };

    Ok(Scene {
        model,
        actuator,
        partition,
        load,
        options,
        gripper,
        file,
    })
}

fn resolve_model(m: &ModelSection) -> Result<ModelId, InputError> {
    match &m.name {
        None => Ok(ModelId::default()),
        Some(name) => ModelId::from_name(name).ok_or_else(|| {
            inconsistent(
                ModelKey::Name,
                format!(
                    "unknown model {name:?}; the models are {}",
                    ModelId::names()
                        .iter()
                        .map(|n| format!("{n:?}"))
                        .collect::<Vec<_>>()
                        .join(", ")
                ),
            )
        }),
    }
}

fn resolve_actuator(
    a: &ActuatorSection,
    echo: &mut ActuatorSection,
) -> Result<Actuator, InputError> {
    let d = ActuatorParams::default();
    let g = &a.geometry;
    let geometry = Geometry {
        lx: g.lx.unwrap_or(d.geometry.lx),
        ly: g.ly.unwrap_or(d.geometry.ly),
        lc: g.lc.unwrap_or(d.geometry.lc),
        h: g.h.unwrap_or(d.geometry.h),
        h1: g.h1.unwrap_or(d.geometry.h1),
        h2: g.h2.unwrap_or(d.geometry.h2),
        h3: g.h3.unwrap_or(d.geometry.h3),
    };
    echo.geometry = GeometrySection {
        lx: Some(geometry.lx),
        ly: Some(geometry.ly),
        lc: Some(geometry.lc),
        h: Some(geometry.h),
        h1: Some(geometry.h1),
        h2: Some(geometry.h2),
        h3: Some(geometry.h3),
    };
    let c = &a.channel;
    let channel = Channel {
        cx: c.cx.unwrap_or(d.channel.cx),
        cy: c.cy.unwrap_or(d.channel.cy),
        h3a: c.h3a.unwrap_or(d.channel.h3a),
        h3b: c.h3b.unwrap_or(d.channel.h3b),
    };
    echo.channel = ChannelSection {
        cx: Some(channel.cx),
        cy: Some(channel.cy),
        h3a: Some(channel.h3a),
        h3b: Some(channel.h3b),
    };
    let (ribs, ribs_echo) = resolve_ribs(&a.ribs, &d.ribs)?;
    echo.ribs = ribs_echo;
    let (cl, e) = resolve_material(&a.cl, d.cl, Layer::Cl)?;
    echo.cl = e;
    let (emc, e) = resolve_material(&a.emc, d.emc, Layer::Emc)?;
    echo.emc = e;
    let (fluidic, e) = resolve_material(&a.fluidic, d.fluidic, Layer::Fluidic)?;
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
    };
    Actuator::new(ActuatorParams {
        geometry,
        channel,
        ribs,
        cl,
        emc,
        fluidic,
        pemc,
    })
    .map_err(scene_input)
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
    layer: Layer,
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
    let key = |k: ElasticKey| SceneKey::Material(layer, k);
    // a value of this kind: the file's, else the layer's default if it is
    // of the same kind, else required
    let value = |k: ElasticKey, v: Option<f64>, fallback: Option<f64>| -> Result<f64, InputError> {
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
        ..MaterialSection::default()
    };
    let material = match kind {
        MaterialKind::Isotropic => {
            forbid(
                &[
                    (key(ElasticKey::E1), m.e1.is_some()),
                    (key(ElasticKey::E2), m.e2.is_some()),
                    (key(ElasticKey::Nu12), m.nu12.is_some()),
                ],
                "an orthotropic key, but the layer is isotropic (keys e, nu)",
            )?;
            let d = match default {
                Material::Isotropic(d) => Some(d),
                Material::Orthotropic(_) => None,
            };
            let iso = Isotropic {
                e: value(ElasticKey::E, m.e, d.map(|d| d.e))?,
                nu: value(ElasticKey::Nu, m.nu, d.map(|d| d.nu))?,
            };
            (echo.e, echo.nu) = (Some(iso.e), Some(iso.nu));
            Material::Isotropic(iso)
        }
        MaterialKind::Orthotropic => {
            forbid(
                &[
                    (key(ElasticKey::E), m.e.is_some()),
                    (key(ElasticKey::Nu), m.nu.is_some()),
                ],
                "an isotropic key, but the layer is orthotropic (keys e1, e2, nu12)",
            )?;
            let d = match default {
                Material::Orthotropic(d) => Some(d),
                Material::Isotropic(_) => None,
            };
            let o = Orthotropic {
                e1: value(ElasticKey::E1, m.e1, d.map(|d| d.e1))?,
                e2: value(ElasticKey::E2, m.e2, d.map(|d| d.e2))?,
                nu12: value(ElasticKey::Nu12, m.nu12, d.map(|d| d.nu12))?,
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

fn resolve_gripper(
    g: &GripperSection,
    stability: bool,
) -> Result<(GripperScene, GripperSection), InputError> {
    let d = GripperParams::default();
    let angle_deg = finite(
        GripperKey::MountingAngleDeg,
        g.mounting_angle_deg.unwrap_or(DEFAULT_MOUNTING_ANGLE_DEG),
    )?;
    require(
        angle_deg > 0.0 && angle_deg < 180.0,
        GripperKey::MountingAngleDeg,
        angle_deg,
        "must lie in (0, 180) degrees: the finger points away from the palm",
    )?;
    let mu = positive(GripperKey::Mu, g.mu.unwrap_or(d.mu))?;
    let strict = g.strict.unwrap_or(false);
    let fingers = g.fingers.unwrap_or(d.fingers);
    require(
        fingers >= 1,
        GripperKey::Fingers,
        fingers as f64,
        "must be at least 1",
    )?;
    let mut echo = GripperSection {
        mounting_angle_deg: Some(angle_deg),
        fingers: Some(fingers),
        mu: Some(mu),
        strict: Some(strict),
        ..GripperSection::default()
    };
    let geometry = match (g.overlap_mm, g.palm_mm) {
        (Some(_), Some(_)) => {
            return Err(inconsistent(
                GripperKey::PalmMm,
                "give either overlap_mm or palm_mm, not both",
            ))
        }
        (_, Some(l)) => {
            finite(GripperKey::PalmMm, l)?;
            require(l >= 0.0, GripperKey::PalmMm, l, "must not be negative")?;
            echo.palm_mm = Some(l);
            PalmSpec::Palm(l)
        }
        (o, None) => {
            let o = finite(GripperKey::OverlapMm, o.unwrap_or(DEFAULT_OVERLAP_MM))?;
            echo.overlap_mm = Some(o);
            PalmSpec::Overlap(o)
        }
    };
    let grasp = match &g.grasp {
        None => None,
        Some(s) => {
            let (spec, e) = resolve_grasp(s)?;
            echo.grasp = Some(e);
            Some(spec)
        }
    };
    Ok((
        GripperScene {
            params: GripperParams {
                mounting_angle: angle_deg.to_radians(),
                geometry,
                fingers,
                mu,
                strict,
            },
            stability,
            grasp,
        },
        echo,
    ))
}

fn resolve_grasp(s: &GraspSection) -> Result<(GraspSpec, GraspSection), InputError> {
    let kind = s.kind.unwrap_or(GraspKind::Cuboid);
    let name = match kind {
        GraspKind::Size => "size",
        GraspKind::Cuboid => "cuboid",
        GraspKind::Sphere => "sphere",
    };
    let rule = format!("not used by kind = \"{name}\"");
    let pressure_kpa = finite(GraspKey::PressureKpa, s.pressure_kpa.unwrap_or(0.0))?;
    let beta = |limit_open: bool| -> Result<f64, InputError> {
        let default = if limit_open {
            DEFAULT_SPHERE_BETA_DEG
        } else {
            0.0
        };
        let b = finite(GraspKey::BetaDeg, s.beta_deg.unwrap_or(default))?;
        let ok = if limit_open {
            b.abs() < 90.0 && b.to_radians().abs() < FRAC_PI_2
        } else {
            b.abs() <= 90.0
        };
        let range = if limit_open { "(-90, 90)" } else { "[-90, 90]" };
        require(ok, GraspKey::BetaDeg, b, format!("must lie in {range}"))?;
        Ok(b)
    };
    let spec = match kind {
        GraspKind::Size => {
            forbid(
                &[
                    (GraspKey::FrictionN.into(), s.friction_n.is_some()),
                    (GraspKey::RMm.into(), s.r_mm.is_some()),
                    (GraspKey::LiftN.into(), s.lift_n.is_some()),
                ],
                &rule,
            )?;
            GraspSpec::Size {
                pressure_kpa,
                d_mm: finite(GraspKey::DMm, s.d_mm.unwrap_or(DEFAULT_GRASP_SIZE_MM))?,
                beta_deg: beta(false)?,
            }
        }
        GraspKind::Cuboid => {
            forbid(
                &[
                    (GraspKey::BetaDeg.into(), s.beta_deg.is_some()),
                    (GraspKey::RMm.into(), s.r_mm.is_some()),
                    (GraspKey::LiftN.into(), s.lift_n.is_some()),
                ],
                &format!("{rule} (a cuboid is held at b = 0)"),
            )?;
            GraspSpec::Cuboid {
                pressure_kpa,
                d_mm: positive(GraspKey::DMm, s.d_mm.unwrap_or(DEFAULT_GRASP_SIZE_MM))?,
                friction_n: finite(
                    GraspKey::FrictionN,
                    s.friction_n.unwrap_or(DEFAULT_CUBOID_FRICTION_N),
                )?,
            }
        }
        GraspKind::Sphere => {
            forbid(
                &[
                    (GraspKey::DMm.into(), s.d_mm.is_some()),
                    (GraspKey::FrictionN.into(), s.friction_n.is_some()),
                ],
                &format!("{rule} (the sphere's size is r_mm; F and f are solved for)"),
            )?;
            GraspSpec::Sphere {
                pressure_kpa,
                r_mm: positive(GraspKey::RMm, s.r_mm.unwrap_or(DEFAULT_SPHERE_RADIUS_MM))?,
                lift_n: finite(GraspKey::LiftN, s.lift_n.unwrap_or(DEFAULT_SPHERE_LIFT_N))?,
                beta_deg: beta(true)?,
            }
        }
    };
    let echo = match spec {
        GraspSpec::Size {
            pressure_kpa,
            d_mm,
            beta_deg,
        } => GraspSection {
            kind: Some(kind),
            pressure_kpa: Some(pressure_kpa),
            d_mm: Some(d_mm),
            beta_deg: Some(beta_deg),
            ..GraspSection::default()
        },
        GraspSpec::Cuboid {
            pressure_kpa,
            d_mm,
            friction_n,
        } => GraspSection {
            kind: Some(kind),
            pressure_kpa: Some(pressure_kpa),
            d_mm: Some(d_mm),
            friction_n: Some(friction_n),
            ..GraspSection::default()
        },
        GraspSpec::Sphere {
            pressure_kpa,
            r_mm,
            lift_n,
            beta_deg,
        } => GraspSection {
            kind: Some(kind),
            pressure_kpa: Some(pressure_kpa),
            r_mm: Some(r_mm),
            lift_n: Some(lift_n),
            beta_deg: Some(beta_deg),
            ..GraspSection::default()
        },
    };
    Ok((spec, echo))
}
#[cfg(test)]
mod tests {
    use super::*;
    use crate::actuator::{ActuatorParams, Isotropic};
    use crate::scene::testing::{input_err, schema_keys, schema_path, syntax_err, SCENES};
    use crate::scene::Scene;

    #[test]
    fn empty_scene_is_the_default_actuator() {
        let s = Scene::from_toml("").unwrap();
        assert_eq!(s.actuator.params(), &ActuatorParams::default());
        assert_eq!(
            s.partition,
            PartitionPlan::Fixed(Partition::equal(110.0, DEFAULT_ELEMENTS).unwrap())
        );
        assert_eq!(s.load, Load::default());
        assert_eq!(s.options, SolveOptions::default());
        assert!(s.gripper.is_none());
    }

    #[test]
    fn echo_spells_out_every_default_and_resolves_to_the_same_scene() {
        let more = [
            ("empty", ""),
            ("auto", "[partition]\nelements = \"auto\""),
            (
                "auto gripper",
                "[partition]\nelements = \"auto\"\n[gripper]\n",
            ),
            ("model", "[model]\nname = \"ccm\""),
            ("strict", "[gripper]\nstrict = true\n[gripper.grasp]\n"),
        ];
        for (name, text) in SCENES.iter().chain(&more) {
            let s = Scene::from_toml(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let again = s.file().resolve().unwrap();
            assert_eq!(again.model, s.model, "{name}");
            assert_eq!(again.actuator, s.actuator, "{name}");
            assert_eq!(again.partition, s.partition, "{name}");
            assert_eq!(again.load, s.load, "{name}");
            assert_eq!(again.options, s.options, "{name}");
            assert_eq!(again.gripper, s.gripper, "{name}");
            assert_eq!(again.file(), s.file(), "{name}: the echo is a fixed point");
            // and survives JSON
            let json = serde_json::to_string(s.file()).unwrap();
            let back: SceneFile = serde_json::from_str(&json).unwrap();
            assert_eq!(&back, s.file(), "{name}");
        }
        let echo = Scene::from_toml("").unwrap().file().clone();
        assert_eq!(echo.actuator.geometry.h1, Some(3.7));
        assert_eq!(echo.actuator.emc.kind, Some(MaterialKind::Orthotropic));
        assert_eq!(echo.actuator.pemc.p4, Some(0.698));
        assert_eq!(echo.partition.elements, Some(Elements::Count(8)));
    }

    #[test]
    fn every_section_reaches_the_library() {
        let s = Scene::from_toml(
            r#"
            [actuator.geometry]
            lx = 100
            h1 = 3.6
            [actuator.channel]
            cx = 95.0
            [actuator.ribs]
            list = [{ x0 = 0, x1 = 95, width = 2 }, { x0 = 10, x1 = 12, width = 12 }]
            [actuator.cl]
            e = 300
            [actuator.emc]
            kind = "isotropic"
            e = 2.0
            nu = 0.3
            [actuator.fluidic]
            nu = 0.45
            [actuator.pemc]
            eps0 = 0.4
            p2 = 2.0
            [partition]
            lengths = [50, 30, 20]
            [load]
            pressure_kpa = 40
            kappa = 1
            fx = 0.1
            fz = -0.2
            [solve]
            rtol = 1e-10
            max_iter = 40
            strategy = "coupled"
            samples_per_element = 4
            shape = true
            stability = false
            continuation = false
            "#,
        )
        .unwrap();
        let p = s.actuator.params();
        assert_eq!(p.geometry.lx, 100.0);
        assert_eq!(p.geometry.h1, 3.6);
        assert_eq!(p.channel.cx, 95.0);
        assert_eq!(s.actuator.ribs().len(), 2);
        assert_eq!(p.cl, Isotropic { e: 300.0, nu: 0.43 }.into());
        assert_eq!(p.emc, Isotropic { e: 2.0, nu: 0.3 }.into());
        assert_eq!(p.fluidic, Isotropic { e: 1.2, nu: 0.45 }.into());
        assert_eq!(p.pemc.eps0, 0.4);
        assert_eq!(p.pemc.law.to_array(), [1.598, 2.0, 2.29, 0.698]);
        let PartitionPlan::Fixed(part) = &s.partition else {
            panic!()
        };
        assert_eq!(part.lengths(), &[50.0, 30.0, 20.0]);
        assert_eq!(
            s.load,
            Load {
                pressure: 0.04,
                kappa: 1.0,
                fx: 0.1,
                fz: -0.2
            }
        );
        assert_eq!(s.options.strategy, Strategy::Coupled);
        assert_eq!(s.options.max_iter, 40);
        assert_eq!(s.options.samples_per_element, 4);
        assert!(!s.options.stability && !s.options.continuation);
        let sol = s.solve().unwrap();
        assert!(sol.solution().report.coupled);
    }

    #[test]
    fn model_name_selects_the_element_model() {
        let s = Scene::from_toml("").unwrap();
        assert_eq!(s.model, ModelId::default());
        assert_eq!(s.file().model.name.as_deref(), Some("ccm"));
        for name in ModelId::names() {
            let s = Scene::from_toml(&format!("[model]\nname = \"{name}\"\n")).unwrap();
            assert_eq!(s.model.name(), name);
            assert_eq!(s.file().model.name.as_deref(), Some(name));
        }
        let e = input_err("[model]\nname = \"nope\"\n");
        assert_eq!(e.field(), "model.name");
        let listed: Vec<String> = ModelId::names()
            .iter()
            .map(|n| format!("\"{n}\""))
            .collect();
        assert_eq!(
            e.to_string(),
            format!(
                "model.name: unknown model \"nope\"; the models are {}",
                listed.join(", ")
            )
        );
        // a name that is not one line stays one line in the message
        let e = input_err("[model]\nname = \"a\\nb\"\n");
        assert!(!e.to_string().contains('\n'), "{e}");
        // a wrong type or an unknown key is the parser's
        let e = syntax_err("[model]\nname = 3\n");
        assert_eq!((e.line, e.col), (2, 8), "{e}");
        let e = syntax_err("[model]\nnmae = \"ccm\"\n");
        assert_eq!(e.line, 2, "{e}");
        assert!(e.message.contains("nmae"), "{e}");
    }

    #[test]
    fn gripper_strict() {
        let strict = |text: &str| {
            Scene::from_toml(text)
                .unwrap()
                .gripper
                .unwrap()
                .params
                .strict
        };
        assert!(!strict("[gripper]\n"));
        assert!(!strict("[gripper]\nstrict = false\n"));
        assert!(strict("[gripper]\nstrict = true\n"));
        let s = Scene::from_toml("[gripper]\n").unwrap();
        assert_eq!(s.file().gripper.as_ref().unwrap().strict, Some(false));
        // a boolean, in [gripper] only
        for text in ["[gripper]\nstrict = \"yes\"\n", "[gripper]\nstrict = 1\n"] {
            let e = syntax_err(text);
            assert_eq!((e.line, e.col), (2, 10), "{text:?}: {e}");
        }
        let e = syntax_err("[gripper.grasp]\nstrict = true\n");
        assert_eq!(e.line, 2, "{e}");
        assert!(e.message.contains("strict"), "{e}");
    }

    #[test]
    fn elements_auto() {
        for text in [
            "[partition]\nelements = \"auto\"\n",
            "[partition]\nelements = \"auto\"\n[gripper]\n",
        ] {
            let s = Scene::from_toml(text).unwrap();
            assert_eq!(s.partition, PartitionPlan::Auto, "{text:?}");
            assert_eq!(s.file().partition.elements, Some(Elements::Auto));
            assert_eq!(s.file().partition.lengths, None);
        }
        let echo = Scene::from_toml("[partition]\nelements = \"auto\"").unwrap();
        let json = serde_json::to_value(echo.file()).unwrap();
        assert_eq!(json["partition"]["elements"], "auto");
        let json = serde_json::to_value(Scene::from_toml("").unwrap().file()).unwrap();
        assert_eq!(json["partition"]["elements"], 8);
        // with a tolerance, "auto" (or no count) is the fastest configuration
        for text in [
            "[partition]\nelements = \"auto\"\ntip_tol_mm = 0.1\n",
            "[partition]\ntip_tol_mm = 0.1\n",
        ] {
            let s = Scene::from_toml(text).unwrap();
            assert_eq!(
                s.partition,
                PartitionPlan::TipTolerance {
                    tip_tol_mm: 0.1,
                    start: None
                },
                "{text:?}"
            );
            assert_eq!(s.file().partition.elements, Some(Elements::Auto));
        }
        // anything else is the parser's, at the value
        for (text, col) in [
            ("[partition]\nelements = \"Auto\"\n", 12),
            ("[partition]\nelements = \"\"\n", 12),
            ("[partition]\nelements = true\n", 12),
            ("[partition]\nelements = -3\n", 12),
            ("[partition]\nelements = 2.0\n", 12),
        ] {
            let e = syntax_err(text);
            assert_eq!((e.line, e.col), (2, col), "{text:?}: {e}");
            assert!(e.message.contains("\"auto\""), "{text:?}: {e}");
        }
    }

    #[test]
    fn bounded_counts() {
        assert_eq!(MAX_ELEMENTS as f64, (1.0 / MIN_ELEMENT_FRACTION).round());
        // the most samples are accepted, one more is not
        let s = Scene::from_toml(&format!(
            "[solve]\nsamples_per_element = {MAX_SAMPLES_PER_ELEMENT}"
        ))
        .unwrap();
        assert_eq!(s.options.samples_per_element, MAX_SAMPLES_PER_ELEMENT);
        let e = input_err(&format!(
            "[solve]\nsamples_per_element = {}",
            MAX_SAMPLES_PER_ELEMENT + 1
        ));
        assert_eq!(
            e.to_string(),
            "solve.samples_per_element = 4097: must lie in [1, 4096]"
        );
        // 1000 lengths are a partition, 1001 are refused as too many, even
        // when each is too short as well
        let list = |n: usize| {
            let l = vec![format!("{}", 110.0 / n as f64); n];
            format!("[partition]\nlengths = [{}]", l.join(", "))
        };
        let s = Scene::from_toml(&list(1000)).unwrap();
        let PartitionPlan::Fixed(p) = &s.partition else {
            panic!()
        };
        assert_eq!(p.len(), 1000);
        let e = input_err(&list(1001));
        assert_eq!(e.field(), "partition.lengths");
        assert!(
            e.to_string()
                .contains("1001 entries, more than the 1000 allowed"),
            "{e}"
        );
    }

    #[test]
    fn library_errors_give_the_value_in_the_keys_unit() {
        // the library checks the pressure in MPa; the scene key is in kPa
        let e = input_err("[load]\npressure_kpa = -200");
        assert!(
            e.to_string()
                .starts_with("load.pressure_kpa = -200: is below absolute vacuum"),
            "{e}"
        );
    }

    #[test]
    fn validation_errors_name_the_toml_path() {
        let cases: &[(&str, &str)] = &[
            ("[model]\nname = \"CCM\"", "model.name"),
            ("[model]\nname = \"\"", "model.name"),
            ("[actuator.geometry]\nh1 = 5", "actuator.geometry.h1"),
            ("[actuator.geometry]\nlx = -1", "actuator.geometry.lx"),
            ("[actuator.geometry]\nlx = nan", "actuator.geometry.lx"),
            ("[actuator.channel]\ncx = 120", "actuator.channel.cx"),
            ("[actuator.ribs]\nw1 = 0", "actuator.ribs.w1"),
            ("[actuator.ribs]\nkind = \"none\"\nt = 1", "actuator.ribs.t"),
            ("[actuator.ribs]\nkind = \"paper\"\nlist = []", "actuator.ribs.list"),
            ("[actuator.ribs]\nkind = \"list\"", "actuator.ribs.list"),
            (
                "[actuator.ribs]\nlist = [{ x0 = 0, x1 = 5, width = 2 }, { x0 = 3, x1 = 2, width = 1 }]",
                "actuator.ribs.list[1].x1",
            ),
            (
                "[actuator.ribs]\nlist = [{ x0 = 0, x1 = 5, width = 20 }, { x0 = 3, x1 = 4, width = 20 }]",
                "actuator.ribs",
            ),
            ("[actuator.cl]\nnu = 0.5", "actuator.cl.nu"),
            ("[actuator.cl]\ne = 1\ne1 = 2", "actuator.cl.e1"),
            ("[actuator.emc]\nkind = \"isotropic\"\ne = 2", "actuator.emc.nu"),
            ("[actuator.emc]\ne2 = -1", "actuator.emc.e2"),
            ("[actuator.fluidic]\nkind = \"orthotropic\"\ne = 1", "actuator.fluidic.e"),
            ("[actuator.pemc]\neps0 = inf", "actuator.pemc.eps0"),
            ("[actuator.pemc]\np1 = 0", "actuator.pemc.p1"),
            ("[actuator.pemc]\np3 = nan", "actuator.pemc.p3"),
            ("[actuator.pemc]\ne2 = 0", "actuator.pemc.e2"),
            ("[partition]\nelements = 0", "partition.elements"),
            ("[partition]\nelements = 5000", "partition.elements"),
            ("[partition]\nlengths = [50, 50]", "partition.lengths"),
            ("[partition]\nlengths = [110, 0]", "partition.lengths[1]"),
            ("[partition]\nlengths = []", "partition.lengths"),
            ("[partition]\nlengths = [110]\nelements = 1", "partition.lengths"),
            ("[partition]\nlengths = [110]\ntip_tol_mm = 1", "partition.tip_tol_mm"),
            ("[partition]\ntip_tol_mm = 0", "partition.tip_tol_mm"),
            (
                "[partition]\nelements = \"auto\"\nlengths = [110]",
                "partition.lengths",
            ),
            ("[load]\npressure_kpa = nan", "load.pressure_kpa"),
            ("[load]\nkappa = 0", "load.kappa"),
            ("[load]\nfx = inf", "load.fx"),
            ("[solve]\nrtol = 0", "solve.rtol"),
            ("[solve]\nmax_iter = 0", "solve.max_iter"),
            ("[solve]\nsamples_per_element = 0", "solve.samples_per_element"),
            ("[solve]\nsamples_per_element = 4097", "solve.samples_per_element"),
            (
                "[solve]\nshape = false\nsamples_per_element = 100000000000",
                "solve.samples_per_element",
            ),
            ("[gripper]\nmounting_angle_deg = nan", "gripper.mounting_angle_deg"),
            ("[gripper]\nmu = 0", "gripper.mu"),
            ("[gripper]\nfingers = 0", "gripper.fingers"),
            ("[gripper]\noverlap_mm = 1\npalm_mm = 2", "gripper.palm_mm"),
            ("[gripper]\npalm_mm = -2", "gripper.palm_mm"),
            ("[gripper]\noverlap_mm = inf", "gripper.overlap_mm"),
            ("[gripper]\n[load]\nfx = 1", "load.fx"),
            ("[gripper]\n[solve]\nrtol = 1e-9", "solve.rtol"),
            ("[gripper]\n[partition]\ntip_tol_mm = 0.1", "partition.tip_tol_mm"),
            ("[gripper.grasp]\nkind = \"size\"\nbeta_deg = 91", "gripper.grasp.beta_deg"),
            ("[gripper.grasp]\nkind = \"sphere\"\nbeta_deg = 90", "gripper.grasp.beta_deg"),
            ("[gripper.grasp]\nkind = \"sphere\"\nr_mm = 0", "gripper.grasp.r_mm"),
            ("[gripper.grasp]\nkind = \"sphere\"\nd_mm = 10", "gripper.grasp.d_mm"),
            ("[gripper.grasp]\nkind = \"sphere\"\nlift_n = nan", "gripper.grasp.lift_n"),
            ("[gripper.grasp]\nkind = \"cuboid\"\nbeta_deg = 10", "gripper.grasp.beta_deg"),
            ("[gripper.grasp]\nd_mm = -3", "gripper.grasp.d_mm"),
            ("[gripper.grasp]\nfriction_n = nan", "gripper.grasp.friction_n"),
            ("[gripper.grasp]\npressure_kpa = inf", "gripper.grasp.pressure_kpa"),
            ("[gripper.grasp]\nkind = \"size\"\nr_mm = 3", "gripper.grasp.r_mm"),
            ("[gripper.grasp]\nkind = \"size\"\nd_mm = nan", "gripper.grasp.d_mm"),
        ];
        for (text, path) in cases {
            let e = input_err(text);
            assert_eq!(e.field(), *path, "{text:?}: {e}");
            assert!(e.to_string().starts_with(path), "{text:?}: {e}");
            assert!(
                schema_keys().contains(&schema_path(path)),
                "{path} is not a key of the schema"
            );
        }
    }
}

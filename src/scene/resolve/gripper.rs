//! Resolution of `[gripper]` and its grasp.

use std::f64::consts::FRAC_PI_2;

use crate::error::InputError;
use crate::gripper::{GripperParams, PalmSpec, MAX_FINGERS};
use crate::scene::fields::{finite, forbid, inconsistent, positive, require, GraspKey, GripperKey};
use crate::scene::schema::*;

// ------------------------------------------------------------ defaults

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

pub(super) fn resolve_gripper(
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
        (1..=MAX_FINGERS).contains(&fingers),
        GripperKey::Fingers,
        fingers as f64,
        format!("must lie in [1, {MAX_FINGERS}]"),
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

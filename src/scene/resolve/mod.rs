//! Resolution: the defaults of absent keys, and every value checked
//! through the library's validating constructors into library types.

mod actuator;
mod gripper;
#[cfg(test)]
mod tests;

use crate::error::InputError;
use crate::finger::{Load, SolveOptions, Strategy, MAX_SAMPLES_PER_ELEMENT};
use crate::model::ModelId;
use crate::partition::{Partition, MIN_ELEMENT_FRACTION};

use super::fields::{
    finite, forbid, inconsistent, positive, require, scene_input, LoadKey, ModelKey, PartitionKey,
    SolveKey,
};
use super::schema::*;
use super::Scene;

use actuator::resolve_actuator;
use gripper::resolve_gripper;
pub use gripper::{GraspSpec, GripperScene};

// ------------------------------------------------------------ defaults

/// Default number of equal elements (the paper's N).
pub const DEFAULT_ELEMENTS: usize = 8;
/// Most elements of a partition: 1 / [`MIN_ELEMENT_FRACTION`].
pub(super) const MAX_ELEMENTS: usize = 1000;
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
    /// ([`crate::Plan::TipTolerance`]): equal elements doubled from
    /// `start`, or without it the fastest configuration for the tolerance.
    TipTolerance {
        tip_tol_mm: f64,
        start: Option<usize>,
    },
    /// The automatic partition ([`crate::Plan::Auto`]): boundaries on the
    /// material changes, elements split until every one turns within the
    /// CCM's slope limit. A finger scene chooses it at its load, a gripper
    /// scene at the unloaded, zero-pressure state (the gripper's reference).
    Auto,
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

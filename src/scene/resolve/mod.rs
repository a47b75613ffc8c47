//! Resolution: the defaults of absent keys, and every value checked
//! through the library's validating constructors into library types.

mod actuator;
mod gripper;
#[cfg(test)]
mod tests;

use crate::actuator::Actuator;
use crate::error::{InputError, Warning};
use crate::field::Field;
use crate::finger::{Load, SolveOptions, Strategy, MAX_SAMPLES_PER_ELEMENT};
use crate::model::ModelId;
use crate::partition::{Partition, MIN_ELEMENT_FRACTION};

use super::covariance::covariance_of;
use super::fields::{
    finite, forbid, inconsistent, positive, require, scene_input, written_in, LoadKey, ModelKey,
    PartitionKey, SceneKey, SolveKey,
};
use super::schema::*;
use super::syntax::SceneError;
use crate::sensitivity::Covariance;

use actuator::resolve_actuator;
use gripper::resolve_gripper;
pub use gripper::{
    GraspSpec, GripperScene, DEFAULT_CUBOID_FRICTION_N, DEFAULT_GRASP_SIZE_MM,
    DEFAULT_MOUNTING_ANGLE_DEG, DEFAULT_OVERLAP_MM, DEFAULT_SPHERE_BETA_DEG, DEFAULT_SPHERE_LIFT_N,
    DEFAULT_SPHERE_RADIUS_MM,
};

// ------------------------------------------------------------ defaults

/// Default number of equal elements (the paper's N).
pub const DEFAULT_ELEMENTS: usize = 8;
/// Most elements of a partition: 1 / [`MIN_ELEMENT_FRACTION`].
pub(super) const MAX_ELEMENTS: usize = 1000;

// ------------------------------------------------------------ the resolved scene

/// Why a scene document could not be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SceneReadError {
    /// Not TOML, an unknown key, or a value of the wrong type.
    #[error(transparent)]
    Syntax(#[from] SceneError),
    /// A value the model rejects (named by its TOML path).
    #[error(transparent)]
    Input(#[from] InputError),
}

/// A validated scene, ready to solve.
#[derive(Debug, Clone)]
pub struct Scene {
    /// The element model of the finger.
    pub model: ModelId,
    /// The validated actuator.
    pub actuator: Actuator,
    /// The partition.
    pub partition: PartitionPlan,
    /// Pressure and tip load (unloaded in gripper scenes).
    pub load: Load,
    /// Solver settings of a finger scene.
    pub options: SolveOptions,
    /// The gripper, if the scene has one.
    pub gripper: Option<GripperScene>,
    /// The `[calibration]` covariance, checked (`Scene::covariance`).
    pub(super) covariance: Option<Covariance>,
    file: SceneFile,
    /// The document as written (absent keys are `None`), read only to
    /// word an error.
    given: SceneFile,
}

impl Scene {
    /// Parses and resolves a scene document.
    pub fn from_toml(text: &str) -> Result<Scene, SceneReadError> {
        Ok(SceneFile::parse(text)?.resolve()?)
    }

    /// The scene with every default written out: the keys that apply, with
    /// the values used (resolving it again gives the same scene).
    pub fn file(&self) -> &SceneFile {
        &self.file
    }

    /// What validation found about the actuator, known before solving:
    /// notes on the input and the laminate's `thickness_ratio` finding
    /// (the solution repeats them with every other warning,
    /// [`SceneSolution::warnings`](crate::SceneSolution::warnings)).
    pub fn warnings(&self) -> &[Warning] {
        self.actuator.warnings()
    }

    /// Whether the scene as written gives `key` (not its default).
    pub(crate) fn written(&self, key: SceneKey) -> bool {
        written(&self.given, key)
    }
}

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

/// Whether the document `f` gives `key`. Absent keys are not serialized,
/// so the document is serialized here, on an error's way only, not on
/// every resolve (a sweep resolves a scene per point). A document that does
/// not serialize, which parsing never gives, counts as giving nothing.
fn written(f: &SceneFile, key: SceneKey) -> bool {
    written_in(&toml::Table::try_from(f).unwrap_or_default(), key)
}

fn resolve(f: &SceneFile) -> Result<Scene, InputError> {
    let mut file = SceneFile::default();
    let model = resolve_model(&f.model)?;
    file.model.name = Some(model.name().to_string());
    let actuator = resolve_actuator(&f.actuator, &mut file.actuator, |k| written(f, k))?;
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
        // the scene's samples are checked even where the shape is not
        // sampled (stricter than the solver), then the solver's own checks
        require(
            (1..=MAX_SAMPLES_PER_ELEMENT).contains(&o.samples_per_element),
            SolveKey::SamplesPerElement,
            o.samples_per_element as f64,
            format!("must lie in [1, {MAX_SAMPLES_PER_ELEMENT}]"),
        )?;
        o.validate().map_err(scene_input)?;
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

    let mut covariance = None;
    if let Some(c) = &f.calibration {
        check_calibration(c)?;
        covariance = covariance_of(c, &actuator, gripper.is_some())?;
        file.calibration = Some(c.clone());
    }
    Ok(Scene {
        model,
        actuator,
        partition,
        load,
        options,
        gripper,
        covariance,
        file,
        given: f.clone(),
    })
}

/// The field of a `[calibration]` key (its scene key's spelling).
fn calibration_key(k: &'static str) -> Field {
    Field::from(SceneKey::Calibration(k).to_string())
}

/// A `[calibration]` table: at most [`MAX_CALIBRATION_KEYS`] keys, finite
/// numbers, standard errors and a square covariance matching the keys;
/// standard errors not negative, no standard error or variance's square
/// root above [`MAX_CALIBRATION_SD`], and with both, each standard error
/// the square root of its variance (within [`CALIBRATION_SD_TOLERANCE`]).
fn check_calibration(c: &CalibrationSection) -> Result<(), InputError> {
    let n = c.parameters.len();
    if n > MAX_CALIBRATION_KEYS {
        return Err(InputError::OutOfRange {
            field: Field::key("calibration.parameters"),
            value: n as f64,
            rule: format!("at most {MAX_CALIBRATION_KEYS} keys"),
        });
    }
    if let Some(se) = &c.standard_errors {
        if se.len() != n {
            return Err(InputError::Inconsistent {
                field: Field::key("calibration.standard_errors"),
                rule: format!("must hold one value per parameter ({n}), not {}", se.len()),
            });
        }
        for &v in se {
            let field = Field::key("calibration.standard_errors");
            crate::error::finite(field.clone(), v)?;
            crate::error::require((0.0..=MAX_CALIBRATION_SD).contains(&v), field, v, || {
                format!(
                    "a standard error must lie in [0, {MAX_CALIBRATION_SD:e}] (in its key's unit)"
                )
            })?;
        }
    }
    if let Some(cov) = &c.covariance {
        if cov.len() != n || cov.iter().any(|r| r.len() != n) {
            return Err(InputError::Inconsistent {
                field: Field::key("calibration.covariance"),
                rule: format!("must be {n} rows of {n} values, one per parameter"),
            });
        }
        let max = MAX_CALIBRATION_SD * MAX_CALIBRATION_SD;
        for &v in cov.iter().flatten() {
            let field = Field::key("calibration.covariance");
            crate::error::finite(field.clone(), v)?;
            crate::error::require(v.abs() <= max, field, v, || {
                format!(
                    "an entry must be at most {max:e} in magnitude (a standard deviation of at most {MAX_CALIBRATION_SD:e} in its key's unit)"
                )
            })?;
        }
        if let Some(se) = &c.standard_errors {
            // (a negative variance is refused with the covariance's checks)
            for (i, &s) in se.iter().enumerate().filter(|&(i, _)| cov[i][i] >= 0.0) {
                let root = cov[i][i].sqrt();
                if (s - root).abs() > CALIBRATION_SD_TOLERANCE * s.max(root) {
                    return Err(InputError::Inconsistent {
                        field: Field::key("calibration.standard_errors"),
                        rule: format!(
                            "{s} disagrees with the square root of the covariance's diagonal, {root} (entry {}; they must agree within {CALIBRATION_SD_TOLERANCE:e} relative)",
                            i + 1
                        ),
                    });
                }
            }
        }
    }
    if let Some(v) = c.chi_square_per_dof {
        crate::error::finite(calibration_key("chi_square_per_dof"), v)?;
    }
    Ok(())
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

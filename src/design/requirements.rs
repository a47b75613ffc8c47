//! The requirements file of `fpc design`: what the gripper must hold and
//! which design variables may vary, as TOML. Every key is documented here
//! and unknown keys are rejected with their line and column, as in scene
//! files.
//!
//! Every value is checked when the file is read ([`Requirements::validate`]),
//! before any work, and an error names the key as written
//! (`object[1].lift_n`); [`RequirementsError::position`] finds the line
//! and column where the file writes it, as a syntax error has them. The
//! bounds are physically generous, there to keep every normalised margin
//! and its sensitivities finite (a margin divides by the size, the lift,
//! the normal force or the opening it is measured against) and every run
//! bounded:
//!
//! - lengths (`size_mm`, `radius_mm`, `open.size_mm`) within
//!   [`LENGTH_RANGE_MM`], a micrometre to ten metres;
//! - forces (`lift_n`, `max_normal_n`) within [`FORCE_RANGE_N`], a
//!   micronewton to ten kilonewtons;
//! - `mu` within [`MU_RANGE`]; `open.pressure_kpa` within [0, 1000] kPa;
//! - the design variables' bounds within [0, 0.6] (eps0), [1, 179] degrees
//!   and [-200, 200] mm;
//! - at most [`MAX_OBJECTS`] `[[object]]` tables: each one's margins are
//!   solved at every design the search tries, so the run time grows with
//!   their number (module docs of [`crate::design`]);
//! - `fingers` within [2, 12], `elements` within [1, 256].
//!
//! A scene's `[gripper]` takes a single finger (`gripper.fingers = 1`: its
//! shape at rest, or a finger pressed on an object by something else), but
//! a requirement is a grasp: the object is held between fingers facing
//! each other, the model solving one of them and mirroring it (docs/model.md
//! Sec. 5.2), so a gripper that must hold something has at least two. The
//! upper bound, 12, is a generous count: the Sec. 5 palm holds 3 to 6
//! fingers of the paper's width, and twelve need a palm of at least 3.9
//! finger widths (docs/model.md Sec. 5.4).

use serde::{Deserialize, Serialize};

use crate::actuator::Actuator;
use crate::error::{finite, positive, require, InputError};
use crate::field::Field;
use crate::model::ModelId;
use crate::scene::{line_col, Scene, SceneError, SceneFile};

/// A requirements document as written.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Requirements {
    /// Fingers of the gripper (default 3).
    #[serde(default = "default_fingers")]
    pub fingers: usize,
    /// Friction coefficient between finger and object (default 0.6).
    #[serde(default = "default_mu")]
    pub mu: f64,
    /// Elements per finger (default 8, the paper's).
    #[serde(default = "default_elements")]
    pub elements: usize,
    /// Strict grasps (default false): a grasp that bends an element
    /// backwards does not count as holding an object, as in the paper's
    /// grasp analysis ([`crate::GripperParams::strict`]); otherwise such a
    /// grasp counts and its reproduction carries the reversal as a note.
    #[serde(default)]
    pub strict: bool,
    /// Every object must be held.
    #[serde(default, rename = "object", with = "object_list")]
    pub objects: Vec<ObjectRequirement>,
    /// Optional: the gripper opens to at least `size_mm` at a pressure of
    /// at most `pressure_kpa`.
    #[serde(default)]
    pub open: Option<OpenRequirement>,
    /// The design variables and their bounds; everything else stays at the
    /// paper's defaults (or the base scene's).
    pub vary: Vary,
    /// The finger the design starts from (not a key of the file: `fpc
    /// design --scene`, [`Requirements::with_base`]); `None` is the
    /// paper's actuator with the default element model.
    #[serde(skip)]
    pub base: Option<DesignBase>,
}

/// The finger a design starts from: a scene's element model, actuator,
/// pressure factor and `[calibration]` table (a calibrated scene from
/// `fpc calibrate`, say). The design sets eps0 (the base's unless
/// varied), the elements and the gripper; the scene's partition, load and
/// gripper tables are not used.
#[derive(Debug, Clone, PartialEq)]
pub struct DesignBase {
    /// The element model.
    pub model: ModelId,
    /// The actuator; a design replaces its eps0.
    pub actuator: Actuator,
    /// The pressure factor of the `open` requirement's pressurised finger
    /// (the scene's `load.kappa`).
    pub kappa: f64,
    /// The scene as resolved (every default written out): the tables a
    /// reproduced scene copies.
    pub file: SceneFile,
    /// Where the base came from, for notes (a path, say).
    pub source: String,
}

impl DesignBase {
    /// The base of a resolved scene; `source` names it in notes.
    pub fn from_scene(scene: &Scene, source: impl Into<String>) -> DesignBase {
        DesignBase {
            model: scene.model,
            actuator: scene.actuator.clone(),
            kappa: scene.load.kappa,
            file: scene.file().clone(),
            source: source.into(),
        }
    }
}

fn default_fingers() -> usize {
    3
}
fn default_mu() -> f64 {
    0.6
}
fn default_elements() -> usize {
    8
}

/// One object the gripper must hold, at zero pressure.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum ObjectRequirement {
    /// A cuboid (or any object held between flat faces) of every width in
    /// `size_mm`, touched at grasping angle 0.
    Cuboid {
        /// The widths to hold, `[smallest, largest]` (mm).
        size_mm: [f64; 2],
        /// The weight each finger must carry by friction (N).
        lift_n: f64,
        /// Optional: a fragile object; the normal force at most this (N).
        max_normal_n: Option<f64>,
    },
    /// A sphere of every radius in `radius_mm`, at its best grasping angle.
    Sphere {
        /// The radii to hold, `[smallest, largest]` (mm).
        radius_mm: [f64; 2],
        /// The lifting force each finger must provide (N).
        lift_n: f64,
        /// Optional: the normal force at most this (N).
        max_normal_n: Option<f64>,
    },
}

/// An `[[object]]` table as written (a flat table, so that an unknown key
/// is located by line and column): `kind` says which keys apply.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
struct ObjectTable {
    kind: ObjectKind,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "pair::size_mm"
    )]
    size_mm: Option<[f64; 2]>,
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        deserialize_with = "pair::radius_mm"
    )]
    radius_mm: Option<[f64; 2]>,
    lift_n: f64,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    max_normal_n: Option<f64>,
}

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
enum ObjectKind {
    Cuboid,
    Sphere,
}

/// `[[object]]` tables to and from [`ObjectRequirement`]s: the keys that do
/// not apply to the kind are errors.
mod object_list {
    use super::{ObjectKind, ObjectRequirement, ObjectTable};
    use serde::{de::Error as _, Deserialize, Deserializer, Serialize, Serializer};

    pub fn deserialize<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Vec<ObjectRequirement>, D::Error> {
        let tables = Vec::<ObjectTable>::deserialize(d)?;
        tables
            .into_iter()
            .map(|t| match t.kind {
                ObjectKind::Cuboid => {
                    if t.radius_mm.is_some() {
                        return Err(D::Error::custom("a cuboid has `size_mm`, not `radius_mm`"));
                    }
                    Ok(ObjectRequirement::Cuboid {
                        size_mm: t.size_mm.ok_or_else(|| {
                            D::Error::custom("a cuboid needs `size_mm = [smallest, largest]`")
                        })?,
                        lift_n: t.lift_n,
                        max_normal_n: t.max_normal_n,
                    })
                }
                ObjectKind::Sphere => {
                    if t.size_mm.is_some() {
                        return Err(D::Error::custom("a sphere has `radius_mm`, not `size_mm`"));
                    }
                    Ok(ObjectRequirement::Sphere {
                        radius_mm: t.radius_mm.ok_or_else(|| {
                            D::Error::custom("a sphere needs `radius_mm = [smallest, largest]`")
                        })?,
                        lift_n: t.lift_n,
                        max_normal_n: t.max_normal_n,
                    })
                }
            })
            .collect()
    }

    pub fn serialize<S: Serializer>(v: &[ObjectRequirement], s: S) -> Result<S::Ok, S::Error> {
        v.serialize(s)
    }
}

/// The two-number arrays of a requirements file, read whole: an array of
/// any other length is an error naming the key (serde's fixed-size arrays
/// would drop the extra entries silently).
mod pair {
    use serde::{de::Error as _, Deserialize, Deserializer};

    fn two<'de, D: Deserializer<'de>>(
        d: D,
        key: &str,
        form: &str,
    ) -> Result<Option<[f64; 2]>, D::Error> {
        let v = Vec::<f64>::deserialize(d)?;
        match v[..] {
            [a, b] => Ok(Some([a, b])),
            _ => Err(D::Error::custom(format!(
                "`{key}` has {} number(s): it must be two, {form}",
                v.len()
            ))),
        }
    }

    pub fn size_mm<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
        two(d, "size_mm", "[smallest, largest]")
    }

    pub fn radius_mm<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
        two(d, "radius_mm", "[smallest, largest]")
    }

    pub fn eps0<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
        two(d, "eps0", "[low, high]")
    }

    pub fn mounting_angle_deg<'de, D: Deserializer<'de>>(
        d: D,
    ) -> Result<Option<[f64; 2]>, D::Error> {
        two(d, "mounting_angle_deg", "[low, high]")
    }

    pub fn overlap_mm<'de, D: Deserializer<'de>>(d: D) -> Result<Option<[f64; 2]>, D::Error> {
        two(d, "overlap_mm", "[low, high]")
    }
}

/// The gripper must open to at least `size_mm` at `pressure_kpa` or less.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct OpenRequirement {
    /// The opening to reach (mm, as a grasp size).
    pub size_mm: f64,
    /// The largest pressure allowed (kPa).
    pub pressure_kpa: f64,
}

/// The design variables: each one given is varied within its bounds, the
/// others are fixed at the base scene's eps0 or the paper's defaults
/// ([`DEFAULT_DESIGN`]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, Default)]
#[serde(deny_unknown_fields)]
pub struct Vary {
    /// Prestrain of the prestressed layer, `[low, high]`.
    #[serde(default, deserialize_with = "pair::eps0")]
    pub eps0: Option<[f64; 2]>,
    /// Mounting angle (degrees), `[low, high]`.
    #[serde(default, deserialize_with = "pair::mounting_angle_deg")]
    pub mounting_angle_deg: Option<[f64; 2]>,
    /// Overlap (mm), `[low, high]`.
    #[serde(default, deserialize_with = "pair::overlap_mm")]
    pub overlap_mm: Option<[f64; 2]>,
    /// Search mounting angles outside the model's design space
    /// `[arccot mu, 90]` degrees (default false: the bounds are clamped to
    /// it); a design found there is reported with a note.
    #[serde(default)]
    pub allow_outside_design_space: bool,
}

/// The paper's Sec. 5 design: eps0 0.25, 60 degrees, 20 mm overlap.
pub const DEFAULT_DESIGN: [f64; 3] = [0.25, 60.0, 20.0];

/// The names of the design variables, in their order in a design vector.
pub const VARIABLES: [&str; 3] = ["eps0", "mounting_angle_deg", "overlap_mm"];

/// The most `[[object]]` tables of a requirements file. Each object's
/// margins are solved at every design the search evaluates, so a run's
/// time grows with their number: with the default search, 32 objects,
/// half of them spheres, take about 15 s on two cores on the paper's
/// finger (more starts: [`MAX_RANDOM_STARTS`](super::MAX_RANDOM_STARTS)).
pub const MAX_OBJECTS: usize = 32;

/// The lengths of a requirements file, `[smallest, largest]` (mm): object
/// widths and radii and the opening to reach. A margin is normalised by
/// them, so the floor keeps it finite; the ceiling is far beyond any
/// gripper the model describes.
pub const LENGTH_RANGE_MM: [f64; 2] = [1e-3, 1e4];

/// The forces of a requirements file, `[smallest, largest]` (N): the lift
/// per finger and the largest normal force. A margin is normalised by
/// them, so the floor keeps it finite.
pub const FORCE_RANGE_N: [f64; 2] = [1e-6, 1e4];

/// The friction coefficient `mu`, `[smallest, largest]`.
pub const MU_RANGE: [f64; 2] = [1e-3, 10.0];

/// Fails unless `value` is finite, positive and within `[lo, hi]` (`unit`
/// after the range in the message).
fn within(field: Field, value: f64, [lo, hi]: [f64; 2], unit: &str) -> Result<(), InputError> {
    positive(field.clone(), value)?;
    require(
        (lo..=hi).contains(&value),
        field,
        value,
        format!("must lie in [{lo}, {hi}]{unit}"),
    )
}

impl Requirements {
    /// Parses and validates a requirements document: TOML syntax, known
    /// keys and types (with line and column), then the values (naming the
    /// field).
    pub fn parse(text: &str) -> Result<Requirements, RequirementsError> {
        let r: Requirements = toml::from_str(text)
            .map_err(|e| RequirementsError::Syntax(SceneError::from_toml(text, &e)))?;
        r.validate().map_err(RequirementsError::Input)?;
        Ok(r)
    }

    /// The requirements with the design starting from `base` (its eps0
    /// becomes the fixed one when eps0 does not vary).
    pub fn with_base(self, base: DesignBase) -> Requirements {
        Requirements {
            base: Some(base),
            ..self
        }
    }

    /// The values of the design variables that do not vary: the base's
    /// eps0 (else the paper's) and the paper's angle and overlap.
    pub fn fixed_design(&self) -> [f64; 3] {
        let mut x = DEFAULT_DESIGN;
        if let Some(b) = &self.base {
            x[0] = b.actuator.eps0();
        }
        x
    }

    /// Checks every value.
    pub fn validate(&self) -> Result<(), InputError> {
        require(
            (2..=12).contains(&self.fingers),
            Field::key("fingers"),
            self.fingers as f64,
            "must lie in [2, 12]: an object is held between fingers facing each other".into(),
        )?;
        within(Field::key("mu"), self.mu, MU_RANGE, "")?;
        require(
            (1..=256).contains(&self.elements),
            Field::key("elements"),
            self.elements as f64,
            "must lie in [1, 256]".into(),
        )?;
        require(
            !self.objects.is_empty() || self.open.is_some(),
            Field::key("object"),
            0.0,
            "at least one [[object]] (or an [open] requirement) is needed".into(),
        )?;
        require(
            self.objects.len() <= MAX_OBJECTS,
            Field::key("object"),
            self.objects.len() as f64,
            format!(
                "at most {MAX_OBJECTS} [[object]] tables (each one's margins are solved at every design the search tries)"
            ),
        )?;
        for (i, o) in self.objects.iter().enumerate() {
            let field = |k: &str| Field::from(format!("object[{i}].{k}"));
            let (range, range_key, lift, max_normal) = match o {
                ObjectRequirement::Cuboid {
                    size_mm,
                    lift_n,
                    max_normal_n,
                } => (size_mm, "size_mm", lift_n, max_normal_n),
                ObjectRequirement::Sphere {
                    radius_mm,
                    lift_n,
                    max_normal_n,
                } => (radius_mm, "radius_mm", lift_n, max_normal_n),
            };
            for (k, &v) in range.iter().enumerate() {
                within(
                    field(&format!("{range_key}[{k}]")),
                    v,
                    LENGTH_RANGE_MM,
                    " mm",
                )?;
            }
            require(
                range[0] <= range[1],
                field(range_key),
                range[1],
                "must be [smallest, largest]".into(),
            )?;
            within(field("lift_n"), *lift, FORCE_RANGE_N, " N")?;
            if let Some(m) = max_normal {
                within(field("max_normal_n"), *m, FORCE_RANGE_N, " N")?;
            }
        }
        if let Some(o) = &self.open {
            within(
                Field::key("open.size_mm"),
                o.size_mm,
                LENGTH_RANGE_MM,
                " mm",
            )?;
            finite(Field::key("open.pressure_kpa"), o.pressure_kpa)?;
            require(
                (0.0..=1000.0).contains(&o.pressure_kpa),
                Field::key("open.pressure_kpa"),
                o.pressure_kpa,
                "must lie in [0, 1000] kPa".into(),
            )?;
        }
        let bound = |key: &str, b: Option<[f64; 2]>, lo: f64, hi: f64| -> Result<(), InputError> {
            if let Some([a, z]) = b {
                finite(format!("vary.{key}[0]").into(), a)?;
                finite(format!("vary.{key}[1]").into(), z)?;
                require(
                    a <= z,
                    format!("vary.{key}").into(),
                    z,
                    "must be [low, high]".into(),
                )?;
                require(
                    a >= lo && z <= hi,
                    format!("vary.{key}").into(),
                    if a < lo { a } else { z },
                    format!("must lie within [{lo}, {hi}]"),
                )?;
            }
            Ok(())
        };
        bound("eps0", self.vary.eps0, 0.0, 0.6)?;
        bound(
            "mounting_angle_deg",
            self.vary.mounting_angle_deg,
            1.0,
            179.0,
        )?;
        bound("overlap_mm", self.vary.overlap_mm, -200.0, 200.0)?;
        if !self.vary.allow_outside_design_space {
            let [lo, hi] = self.design_space_deg();
            let given = self
                .vary
                .mounting_angle_deg
                .unwrap_or([DEFAULT_DESIGN[1]; 2]);
            let (field, value) = match self.vary.mounting_angle_deg {
                Some(_) => ("vary.mounting_angle_deg", given[1]),
                // fixed at the paper's value, outside this mu's design space
                None => ("mu", self.mu),
            };
            require(
                given[1] >= lo && given[0] <= hi,
                Field::key(field),
                value,
                format!(
                    "leaves no mounting angle in the design space [{lo:.3}, {hi}] deg (arccot mu to 90 deg); set vary.allow_outside_design_space = true to search outside it"
                ),
            )?;
        }
        require(
            self.vary.eps0.is_some()
                || self.vary.mounting_angle_deg.is_some()
                || self.vary.overlap_mm.is_some(),
            Field::key("vary"),
            0.0,
            "must give at least one design variable".into(),
        )?;
        Ok(())
    }

    /// The bounds of each design variable, `[low, high]` (equal ends for a
    /// fixed one). The mounting angle's are clamped to the design space
    /// [`Requirements::design_space_deg`] unless
    /// `vary.allow_outside_design_space`.
    pub fn bounds(&self) -> [[f64; 2]; 3] {
        let or = |b: Option<[f64; 2]>, d: f64| b.unwrap_or([d, d]);
        let fixed = self.fixed_design();
        let mut angle = or(self.vary.mounting_angle_deg, fixed[1]);
        if !self.vary.allow_outside_design_space {
            let [lo, hi] = self.design_space_deg();
            angle = [angle[0].clamp(lo, hi), angle[1].clamp(lo, hi)];
        }
        [
            or(self.vary.eps0, fixed[0]),
            angle,
            or(self.vary.overlap_mm, fixed[2]),
        ]
    }

    /// The model's design space of mounting angles, `[arccot mu, 90]`
    /// degrees (docs/model.md M25): with the fingers pressed flat, friction
    /// at its limit must carry the object.
    pub fn design_space_deg(&self) -> [f64; 2] {
        let [lo, hi] = crate::gripper::design_space(self.mu);
        [lo.to_degrees(), hi.to_degrees()]
    }

    /// Notes on the requirements as read: mounting-angle bounds clamped to
    /// the design space, or, with `allow_outside_design_space`, bounds that
    /// reach outside it.
    pub fn notes(&self) -> Vec<String> {
        let [lo, hi] = self.design_space_deg();
        let given = self
            .vary
            .mounting_angle_deg
            .unwrap_or([DEFAULT_DESIGN[1]; 2]);
        let mut notes: Vec<String> = self
            .base
            .iter()
            .map(|b| {
                let eps0 = match self.vary.eps0 {
                    Some(_) => "eps0 as varied".to_string(),
                    None => format!("its eps0 = {}", b.actuator.eps0()),
                };
                let calibrated = if b.file.calibration.is_some() {
                    " and its [calibration] table (error bars in the reproduced scenes)"
                } else {
                    ""
                };
                format!(
                    "the finger is {}'s: element model {}, its actuator with {eps0}, load.kappa = {} for the open requirement{calibrated}; its partition, load and gripper tables are not used",
                    b.source,
                    b.model.name(),
                    b.kappa
                )
            })
            .collect();
        if given[0] >= lo && given[1] <= hi {
            return notes;
        }
        notes.push(if self.vary.allow_outside_design_space {
            format!(
                "vary.mounting_angle_deg = [{}, {}] reaches outside the design space [{lo:.3}, {hi}] deg (arccot mu to 90 deg), as vary.allow_outside_design_space asks: fingers pressed flat there cannot hold an object by friction",
                given[0], given[1]
            )
        } else {
            let b = self.bounds()[1];
            format!(
                "vary.mounting_angle_deg = [{}, {}] is searched within the design space, [{:.3}, {:.3}] deg (arccot mu to 90 deg); set vary.allow_outside_design_space = true to search outside it",
                given[0], given[1], b[0], b[1]
            )
        });
        notes
    }
}

/// A requirements file that cannot be used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RequirementsError {
    /// Not TOML, an unknown key or a value of the wrong type, at a line and
    /// column.
    #[error("{0}")]
    Syntax(SceneError),
    /// A value out of range, naming its field.
    #[error("{0}")]
    Input(InputError),
}

impl RequirementsError {
    /// Where the error lies in `text`, the document that was parsed: line
    /// and column, both from 1. A syntax error's own; for a value error,
    /// the value of the key it names (`object[1].size_mm[0]` is the first
    /// number of the second `[[object]]`'s `size_mm`), or `None` where the
    /// file does not write that key (`object = 0`: no `[[object]]` table
    /// at all). Too many `[[object]]` tables: the first one past
    /// [`MAX_OBJECTS`].
    pub fn position(&self, text: &str) -> Option<(usize, usize)> {
        match self {
            RequirementsError::Syntax(s) => Some((s.line, s.col)),
            RequirementsError::Input(i) => {
                let field = i.field().to_string();
                let path = match i {
                    InputError::OutOfRange { value, .. }
                        if field == "object" && *value > MAX_OBJECTS as f64 =>
                    {
                        format!("object[{MAX_OBJECTS}]")
                    }
                    _ => field,
                };
                locate(text, &path)
            }
        }
    }
}

/// Line and column of the value at `path` (`vary.eps0`,
/// `object[1].size_mm[0]`: keys separated by dots, each followed by any
/// array indices) in the TOML document `text`; `None` if it is not there.
fn locate(text: &str, path: &str) -> Option<(usize, usize)> {
    let doc = toml::de::DeTable::parse(text).ok()?;
    let root = toml::de::DeValue::Table(doc.into_inner());
    let mut at: (&toml::de::DeValue<'_>, Option<std::ops::Range<usize>>) = (&root, None);
    for segment in path.split('.') {
        let mut parts = segment.split('[');
        let v = at.0.get(parts.next()?)?;
        at = (v.get_ref(), Some(v.span()));
        for index in parts {
            let i: usize = index.strip_suffix(']')?.parse().ok()?;
            let v = at.0.get(i)?;
            at = (v.get_ref(), Some(v.span()));
        }
    }
    at.1.map(|span| line_col(text, span.start))
}

#[cfg(test)]
mod tests {
    use super::*;

    const PAPER: &str = r#"
fingers = 3
mu = 0.6
[[object]]
kind = "cuboid"
size_mm = [60.0, 120.0]
lift_n = 0.3
[vary]
eps0 = [0.1, 0.5]
mounting_angle_deg = [60.0, 90.0]
"#;

    #[test]
    fn a_requirements_file_parses_with_defaults() {
        let r = Requirements::parse(PAPER).unwrap();
        assert_eq!((r.fingers, r.elements), (3, 8));
        assert_eq!(r.objects.len(), 1);
        assert_eq!(r.bounds()[2], [20.0, 20.0]);
        assert_eq!(r.bounds()[1], [60.0, 90.0]);
    }

    #[test]
    fn unknown_keys_and_bad_values_are_located_or_named() {
        let e = Requirements::parse(&PAPER.replace("lift_n", "lift")).unwrap_err();
        let RequirementsError::Syntax(s) = e else {
            panic!("{e:?}")
        };
        assert!(s.message.contains("lift"), "{s}");
        assert_eq!(s.line, 7, "{s}");
        let e = Requirements::parse(&PAPER.replace("kind = \"cuboid\"", "kind = \"cube\""))
            .unwrap_err();
        assert!(matches!(e, RequirementsError::Syntax(_)), "{e:?}");
        for (from, to, field) in [
            ("lift_n = 0.3", "lift_n = -1", "object[0].lift_n"),
            ("[60.0, 120.0]", "[120.0, 60.0]", "object[0].size_mm"),
            ("eps0 = [0.1, 0.5]", "eps0 = [0.1, 0.9]", "vary.eps0"),
            ("mu = 0.6", "mu = 0", "mu"),
            ("fingers = 3", "fingers = 1", "fingers"),
        ] {
            let e = Requirements::parse(&PAPER.replace(from, to)).unwrap_err();
            let RequirementsError::Input(i) = e else {
                panic!("{to}: {e:?}")
            };
            assert_eq!(i.field(), field, "{to}: {i}");
        }
        let e = Requirements::parse("[vary]\neps0 = [0.1, 0.2]\n").unwrap_err();
        assert!(e.to_string().contains("object"), "{e}");
    }

    /// The audit's values: sizes that overflow a sample, requirements so
    /// small that a margin normalised by them is infinite, friction that
    /// overflows a force. Each is refused on reading, naming its key; the
    /// bounds themselves are accepted.
    #[test]
    fn lengths_forces_and_friction_are_bounded_on_reading() {
        let sphere = PAPER.replace(
            "kind = \"cuboid\"\nsize_mm = [60.0, 120.0]",
            "kind = \"sphere\"\nradius_mm = [20.0, 30.0]",
        );
        let open = format!("{PAPER}[open]\nsize_mm = 100.0\npressure_kpa = 50.0\n");
        let fragile = PAPER.replace("lift_n = 0.3", "lift_n = 0.3\nmax_normal_n = 2.0");
        for (text, from, to, field) in [
            (
                PAPER,
                "[60.0, 120.0]",
                "[60.0, 1e308]",
                "object[0].size_mm[1]",
            ),
            (
                PAPER,
                "[60.0, 120.0]",
                "[1e-320, 120.0]",
                "object[0].size_mm[0]",
            ),
            (
                PAPER,
                "[60.0, 120.0]",
                "[60.0, 20000.0]",
                "object[0].size_mm[1]",
            ),
            (
                &sphere,
                "[20.0, 30.0]",
                "[1e-320, 30.0]",
                "object[0].radius_mm[0]",
            ),
            (
                &sphere,
                "[20.0, 30.0]",
                "[20.0, inf]",
                "object[0].radius_mm[1]",
            ),
            (PAPER, "lift_n = 0.3", "lift_n = 1e-320", "object[0].lift_n"),
            (PAPER, "lift_n = 0.3", "lift_n = 5e-7", "object[0].lift_n"),
            (PAPER, "lift_n = 0.3", "lift_n = 1e300", "object[0].lift_n"),
            (
                &fragile,
                "max_normal_n = 2.0",
                "max_normal_n = 1e-320",
                "object[0].max_normal_n",
            ),
            (
                &fragile,
                "max_normal_n = 2.0",
                "max_normal_n = 2e4",
                "object[0].max_normal_n",
            ),
            (&open, "size_mm = 100.0", "size_mm = 1e-320", "open.size_mm"),
            (&open, "size_mm = 100.0", "size_mm = 1e308", "open.size_mm"),
            (PAPER, "mu = 0.6", "mu = 1e300", "mu"),
            (PAPER, "mu = 0.6", "mu = 1e-9", "mu"),
        ] {
            let changed = text.replace(from, to);
            assert_ne!(changed, text, "{to}");
            let e = Requirements::parse(&changed).unwrap_err();
            let RequirementsError::Input(i) = e else {
                panic!("{to}: {e:?}")
            };
            assert_eq!(i.field(), field, "{to}: {i}");
        }
        // the bounds themselves pass
        let [short, long] = LENGTH_RANGE_MM;
        let [light, heavy] = FORCE_RANGE_N;
        let at_bounds = fragile
            .replace("[60.0, 120.0]", &format!("[{short:e}, {long:e}]"))
            .replace("lift_n = 0.3", &format!("lift_n = {light:e}"))
            .replace("max_normal_n = 2.0", &format!("max_normal_n = {heavy:e}"));
        Requirements::parse(&at_bounds).unwrap();
        let mu = PAPER.replace("mu = 0.6", &format!("mu = {:e}", MU_RANGE[1]));
        assert_eq!(Requirements::parse(&mu).unwrap().mu, 10.0);
    }

    /// `n` cuboid tables and a `[vary]` table.
    fn objects(n: usize) -> String {
        let table = "[[object]]\nkind = \"cuboid\"\nsize_mm = [60.0, 80.0]\nlift_n = 0.3\n";
        format!("{}[vary]\neps0 = [0.1, 0.5]\n", table.repeat(n))
    }

    #[test]
    fn the_number_of_objects_is_bounded_and_the_first_one_past_it_located() {
        assert_eq!(
            Requirements::parse(&objects(MAX_OBJECTS))
                .unwrap()
                .objects
                .len(),
            MAX_OBJECTS
        );
        for n in [MAX_OBJECTS + 1, 2000] {
            let text = objects(n);
            let e = Requirements::parse(&text).unwrap_err();
            let RequirementsError::Input(i) = &e else {
                panic!("{e:?}")
            };
            assert_eq!(i.field(), "object", "{i}");
            assert!(
                i.to_string().contains(&format!("at most {MAX_OBJECTS}")),
                "{i}"
            );
            // four lines per table: the header of the one past the limit
            assert_eq!(e.position(&text), Some((4 * MAX_OBJECTS + 1, 1)), "{i}");
        }
    }

    /// A value error is located at the value of the key it names, as the
    /// file writes it; a key the file does not write has no position.
    #[test]
    fn value_errors_are_located_at_their_key() {
        let text = "fingers = 3\n\n[[object]]\nkind = \"cuboid\"\nsize_mm = [60.0, 80.0]\nlift_n = 0.3\n\n[[object]]\nkind = \"sphere\"\nradius_mm = [30.0, 40.0]\nlift_n = 0.5\n\n[vary]\neps0 = [0.1, 0.5]\n";
        // (replace, with, field, line, column of the value)
        for (from, to, field, line, col) in [
            ("fingers = 3", "fingers = 1", "fingers", 1, 11),
            ("fingers = 3", "fingers =  40", "fingers", 1, 12),
            (
                "[30.0, 40.0]",
                "[30.0, 0.0]",
                "object[1].radius_mm[1]",
                10,
                20,
            ),
            (
                "[30.0, 40.0]",
                "[30.0, 20.0]",
                "object[1].radius_mm",
                10,
                13,
            ),
            ("lift_n = 0.5", "lift_n = -0.5", "object[1].lift_n", 11, 10),
            ("eps0 = [0.1, 0.5]", "eps0 = [0.5, 0.1]", "vary.eps0", 14, 8),
            ("eps0 = [0.1, 0.5]", "", "vary", 13, 1),
        ] {
            let changed = text.replace(from, to);
            let e = Requirements::parse(&changed).unwrap_err();
            let RequirementsError::Input(i) = &e else {
                panic!("{to}: {e:?}")
            };
            assert_eq!(i.field(), field, "{to}: {i}");
            assert_eq!(e.position(&changed), Some((line, col)), "{to}: {i}");
        }
        // one finger is refused, saying why
        let e = Requirements::parse(&text.replace("fingers = 3", "fingers = 1")).unwrap_err();
        assert!(e.to_string().contains("facing each other"), "{e}");
        // the paper's fixed mounting angle outside the design space of mu:
        // the error names mu, at its value
        let angle = "[[object]]\nkind = \"cuboid\"\nsize_mm = [60.0, 80.0]\nlift_n = 0.3\n[vary]\neps0 = [0.1, 0.5]\n";
        let e = Requirements::parse(&format!("mu = 0.1\n{angle}")).unwrap_err();
        assert_eq!(
            e.position(&format!("mu = 0.1\n{angle}")),
            Some((1, 6)),
            "{e}"
        );
        // no object: nothing the file writes to point at
        let e = Requirements::parse("[vary]\neps0 = [0.1, 0.5]\n").unwrap_err();
        assert!(e.to_string().starts_with("object = 0"), "{e}");
        assert_eq!(e.position("[vary]\neps0 = [0.1, 0.5]\n"), None, "{e}");
        // a syntax error keeps its own
        let e = Requirements::parse("fingers = 3\nfingerz = 2\n").unwrap_err();
        assert_eq!(
            e.position("fingers = 3\nfingerz = 2\n"),
            Some((2, 1)),
            "{e}"
        );
    }

    #[test]
    fn arrays_of_the_wrong_length_are_located_errors() {
        // (replace, with, key, line, column of the array)
        for (from, to, key, line, col) in [
            (
                "size_mm = [60.0, 120.0]",
                "size_mm = [90.0, 100.0, 200.0, 5000.0]",
                "size_mm",
                6,
                11,
            ),
            (
                "size_mm = [60.0, 120.0]",
                "size_mm = [60.0]",
                "size_mm",
                6,
                11,
            ),
            ("size_mm = [60.0, 120.0]", "size_mm = []", "size_mm", 6, 11),
            ("eps0 = [0.1, 0.5]", "eps0 = [0.1, 0.2, 0.5]", "eps0", 9, 8),
            (
                "mounting_angle_deg = [60.0, 90.0]",
                "mounting_angle_deg = [60.0]",
                "mounting_angle_deg",
                10,
                22,
            ),
            (
                "mounting_angle_deg = [60.0, 90.0]",
                "overlap_mm = [0.0, 10.0, 20.0]",
                "overlap_mm",
                10,
                14,
            ),
        ] {
            let text = PAPER.replace(from, to);
            let e = Requirements::parse(&text).unwrap_err();
            let RequirementsError::Syntax(s) = e else {
                panic!("{to}: {e:?}")
            };
            assert!(s.message.contains(&format!("`{key}`")), "{to}: {s}");
            assert!(s.message.contains("must be two"), "{to}: {s}");
            assert_eq!((s.line, s.col), (line, col), "{to}: {s}");
        }
        // a sphere's radii likewise
        let sphere = PAPER.replace(
            "kind = \"cuboid\"\nsize_mm = [60.0, 120.0]",
            "kind = \"sphere\"\nradius_mm = [20.0, 30.0, 40.0]",
        );
        let e = Requirements::parse(&sphere).unwrap_err();
        assert!(e.to_string().contains("`radius_mm` has 3"), "{e}");
        // two numbers still read as before
        let ok = PAPER.replace(
            "kind = \"cuboid\"\nsize_mm = [60.0, 120.0]",
            "kind = \"sphere\"\nradius_mm = [20.0, 30.0]",
        );
        let r = Requirements::parse(&ok).unwrap();
        assert!(matches!(
            r.objects[0],
            ObjectRequirement::Sphere {
                radius_mm: [20.0, 30.0],
                ..
            }
        ));
        assert_eq!(r.vary.eps0, Some([0.1, 0.5]));
    }
}

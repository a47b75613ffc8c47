//! The requirements file of `fpc design`: what the gripper must hold and
//! which design variables may vary, as TOML. Every key is documented here
//! and unknown keys are rejected with their line and column, as in scene
//! files.
//! Its values' bounds and their check: `limits.rs`.

use serde::{Deserialize, Serialize};

use crate::actuator::Actuator;
use crate::error::InputError;
use crate::model::ModelId;
use crate::scene::{Scene, SceneError, SceneFile};

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

impl Requirements {
    /// Parses and validates a requirements document: TOML syntax, known
    /// keys and types (with line and column), then the values (naming the
    /// field).
    pub fn parse(text: &str) -> Result<Requirements, RequirementsError> {
        let r: Requirements = toml::from_str(text).map_err(|e| {
            // a missing [vary] table is named here: the parser's error
            // spans the whole document and would name its first key; the
            // position is where the table would be added, after the end
            if e.message().trim() == "missing field `vary`" {
                let (line, col) = crate::scene::line_col(text, text.len());
                return RequirementsError::Syntax(SceneError {
                    line,
                    col,
                    message: "vary: missing table [vary], the design variables and their bounds (required, with at least one variable)".into(),
                });
            }
            RequirementsError::Syntax(SceneError::from_toml(text, &e))
        })?;
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

#[cfg(test)]
pub(super) mod tests {
    use super::*;

    /// The paper's Sec. 5 cuboid, varying eps0 and the angle.
    pub(in crate::design) const PAPER: &str = r#"
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
    fn a_missing_vary_table_is_named_at_the_end_of_the_file() {
        // it named the file's first key (`fingers`, or `object[0]`)
        let without = PAPER.split("[vary]").next().unwrap();
        for text in [
            without.to_string(),
            without.replace("fingers = 3\n", "fingers = 1\n"),
            without.replace("fingers = 3\nmu = 0.6\n", ""),
        ] {
            let e = Requirements::parse(&text).unwrap_err();
            let RequirementsError::Syntax(s) = e else {
                panic!("{e:?}")
            };
            assert!(s.message.starts_with("vary: missing table [vary]"), "{s}");
            // the line after the last (the text ends in a newline)
            assert_eq!((s.line, s.col), (text.lines().count() + 1, 1), "{s}");
        }
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

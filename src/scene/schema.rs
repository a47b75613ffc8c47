//! The file format: the serde structs of a scene document, every key
//! optional, unknown keys rejected (the syntax errors of parsing:
//! `syntax.rs`). An absent key is `None` everywhere: whether it was given
//! decides what the others mean, and which key an error names (a rule
//! between two keys names the one the scene wrote).

use super::fields::{SceneKey, ValueKind};
use super::syntax::SceneError;
use crate::actuator::{Channel, Geometry};
use crate::error::InputError;
use crate::field::Field;
use serde::{Deserialize, Serialize};

// ------------------------------------------------------------ the document

/// A scene document as written: every key optional (absent keys take the
/// paper's defaults, while reading or in [`SceneFile::resolve`]), unknown
/// keys rejected.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SceneFile {
    /// The element model.
    pub model: ModelSection,
    /// The finger: geometry, channel, ribs, materials.
    pub actuator: ActuatorSection,
    /// How the finger is split into elements.
    pub partition: PartitionSection,
    /// Pressure and tip load (finger scenes only).
    pub load: LoadSection,
    /// Solver settings.
    pub solve: SolveSection,
    /// A gripper built from the finger, and the grasp to solve.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gripper: Option<GripperSection>,
    /// Where the parameters came from: a calibration's fitted keys and
    /// their covariance (written by `fpc calibrate`; it changes nothing
    /// the scene solves).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub calibration: Option<CalibrationSection>,
}

/// `[calibration]`: the scene keys a calibration fitted and their
/// covariance, in the keys' order (`covariance[i][j]` in the units of key
/// i times key j); absent when the data could not determine them.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct CalibrationSection {
    /// The measurement manifest the calibration read.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub manifest: Option<String>,
    /// The fitted scene keys (`actuator.pemc.eps0`, `load.kappa`, ...).
    pub parameters: Vec<String>,
    /// Their standard errors, in the keys' order.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub standard_errors: Option<Vec<f64>>,
    /// Their covariance, one row per key.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub covariance: Option<Vec<Vec<f64>>>,
    /// The fit's chi-square per degree of freedom.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub chi_square_per_dof: Option<f64>,
}

/// Most keys of a `[calibration]` table.
pub const MAX_CALIBRATION_KEYS: usize = 64;

/// Largest standard error (or square root of a variance) a
/// `[calibration]` table may give, in its key's unit: the largest value
/// any scene key admits (a modulus of 1e7 MPa). A larger one is no
/// measurement's, and its square, propagated, overflows the error bars.
pub const MAX_CALIBRATION_SD: f64 = 1e7;

/// Relative tolerance between a `[calibration]` table's standard errors
/// and the square roots of its covariance's diagonal: both are written
/// from one fit, so they agree to round-off.
pub const CALIBRATION_SD_TOLERANCE: f64 = 1e-6;

/// `[model]`: the element model the finger is built from.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ModelSection {
    /// A model's name ([`crate::ModelId::from_name`]); default the paper's
    /// element, `"ccm"` ([`crate::ModelId::default`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub name: Option<String>,
}

/// `[actuator]`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ActuatorSection {
    /// `[actuator.geometry]`, mm; a key not given is the default's.
    pub geometry: GeometrySection,
    /// `[actuator.channel]`, mm; a key not given is the default's.
    pub channel: ChannelSection,
    pub ribs: RibsSection,
    /// Constraining layer (default isotropic, E = 305 MPa, nu = 0.43).
    pub cl: MaterialSection,
    /// Regular EMC (default orthotropic, E1 = 1.5, E2 = 250 MPa, nu12 = 0).
    pub emc: MaterialSection,
    /// Fluidic layer and ribs (default isotropic, E = 1.2 MPa, nu = 0.48).
    pub fluidic: MaterialSection,
    /// Prestressed EMC.
    pub pemc: PemcSection,
    /// Options of the laminate as a whole.
    #[serde(skip_serializing_if = "LaminateSection::is_empty")]
    pub laminate: LaminateSection,
    /// Ribs on the constraining layer (none by default).
    #[serde(skip_serializing_if = "ClRibsSection::is_empty")]
    pub cl_ribs: ClRibsSection,
}

/// `[actuator.geometry]` (mm): the keys of [`Geometry`], each optional
/// (a key not given is [`Geometry::default`]'s).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GeometrySection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lx: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub ly: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lc: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h1: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h2: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h3: Option<f64>,
}

impl GeometrySection {
    /// The geometry: the keys given, the default's elsewhere.
    pub fn resolve(&self) -> Geometry {
        let d = Geometry::default();
        Geometry {
            lx: self.lx.unwrap_or(d.lx),
            ly: self.ly.unwrap_or(d.ly),
            lc: self.lc.unwrap_or(d.lc),
            h: self.h.unwrap_or(d.h),
            h1: self.h1.unwrap_or(d.h1),
            h2: self.h2.unwrap_or(d.h2),
            h3: self.h3.unwrap_or(d.h3),
        }
    }
}

impl From<Geometry> for GeometrySection {
    /// Every key given.
    fn from(g: Geometry) -> GeometrySection {
        GeometrySection {
            lx: Some(g.lx),
            ly: Some(g.ly),
            lc: Some(g.lc),
            h: Some(g.h),
            h1: Some(g.h1),
            h2: Some(g.h2),
            h3: Some(g.h3),
        }
    }
}

/// `[actuator.channel]` (mm): the keys of [`Channel`], each optional (a
/// key not given is [`Channel::default`]'s).
#[derive(Debug, Clone, Copy, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ChannelSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cx: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub cy: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h3a: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub h3b: Option<f64>,
}

impl ChannelSection {
    /// The channel: the keys given, the default's elsewhere.
    pub fn resolve(&self) -> Channel {
        let d = Channel::default();
        Channel {
            cx: self.cx.unwrap_or(d.cx),
            cy: self.cy.unwrap_or(d.cy),
            h3a: self.h3a.unwrap_or(d.h3a),
            h3b: self.h3b.unwrap_or(d.h3b),
        }
    }
}

impl From<Channel> for ChannelSection {
    /// Every key given.
    fn from(c: Channel) -> ChannelSection {
        ChannelSection {
            cx: Some(c.cx),
            cy: Some(c.cy),
            h3a: Some(c.h3a),
            h3b: Some(c.h3b),
        }
    }
}

/// `[actuator.cl_ribs]`: ribs of the constraining layer's material on its
/// top surface (docs/model.md section 4.10); absent from a resolved scene
/// when none is given.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ClRibsSection {
    /// The ribs (default none).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub list: Option<Vec<ClRibEntry>>,
}

impl ClRibsSection {
    /// No key given.
    pub fn is_empty(&self) -> bool {
        self.list.is_none()
    }
}

/// One rib on the constraining layer: X_ref in [x0, x1], total width
/// across Y and height above the layer's top surface z = H/2 (all mm).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ClRibEntry {
    pub x0: f64,
    pub x1: f64,
    pub width: f64,
    pub height: f64,
}

/// How the ribs are given.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum RibKind {
    /// docs/model.md decision D5 from `w1`, `w2`, `t`.
    Paper,
    /// An explicit `list` of ribs.
    List,
    /// No ribs.
    None,
}

/// `[actuator.ribs]`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct RibsSection {
    /// Default: "list" when `list` is given, "paper" otherwise.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kind: Option<RibKind>,
    /// Transverse rib pitch (mm), kind "paper".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub w1: Option<f64>,
    /// Transverse rib width each side of the longitudinal rib (mm), kind "paper".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub w2: Option<f64>,
    /// Rib thickness (mm), kind "paper".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub t: Option<f64>,
    /// The ribs, kind "list".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub list: Option<Vec<RibEntry>>,
}

/// One rib of a list: X_ref in [x0, x1] (mm), total width across Y (mm).
/// Written as a table `{ x0, x1, width }`; an array is read only when it
/// holds exactly the three numbers `[x0, x1, width]` (serde would drop
/// extra entries silently).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct RibEntry {
    pub x0: f64,
    pub x1: f64,
    pub width: f64,
}

impl<'de> Deserialize<'de> for RibEntry {
    fn deserialize<D: serde::Deserializer<'de>>(d: D) -> Result<RibEntry, D::Error> {
        use serde::de::{self, MapAccess, SeqAccess, Visitor};

        #[derive(Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Table {
            x0: f64,
            x1: f64,
            width: f64,
        }

        struct Rib;
        impl<'de> Visitor<'de> for Rib {
            type Value = RibEntry;
            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a rib { x0, x1, width } (mm)")
            }
            fn visit_map<A: MapAccess<'de>>(self, map: A) -> Result<RibEntry, A::Error> {
                let t = Table::deserialize(de::value::MapAccessDeserializer::new(map))?;
                Ok(RibEntry {
                    x0: t.x0,
                    x1: t.x1,
                    width: t.width,
                })
            }
            fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<RibEntry, A::Error> {
                let mut v: Vec<f64> = Vec::new();
                while let Some(x) = seq.next_element()? {
                    v.push(x);
                }
                match v[..] {
                    [x0, x1, width] => Ok(RibEntry { x0, x1, width }),
                    _ => Err(de::Error::custom(format!(
                        "a rib given as an array has {} number(s): it must be three, [x0, x1, width] (or a table {{ x0, x1, width }})",
                        v.len()
                    ))),
                }
            }
        }
        // a struct accepts a table or an array (TOML asks the visitor which)
        d.deserialize_struct("RibEntry", &["x0", "x1", "width"], Rib)
    }
}

/// A linear lamina's material model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum MaterialKind {
    /// Keys `e` (MPa) and `nu`.
    Isotropic,
    /// Keys `e1`, `e2` (MPa, along X and Y) and `nu12`.
    Orthotropic,
}

/// `[actuator.cl]`, `[actuator.emc]`, `[actuator.fluidic]`. The kind
/// defaults to the one the keys belong to, else to the layer's default.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct MaterialSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kind: Option<MaterialKind>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub e: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nu: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub e1: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub e2: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub nu12: Option<f64>,
    /// Transverse shear modulus G13 (MPa) of shear-deformable models;
    /// default from the layer's E and nu, E / (2 (1 + nu)).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g13: Option<f64>,
}

/// `[actuator.pemc]`: prestrain, Y modulus (MPa) and the axial law
/// psi(s) = p1/2 s^2 - p2/3 s^3 + p3/4 s^4 - p4/5 s^5 (MPa).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PemcSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub eps0: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub e2: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p1: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p2: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p3: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub p4: Option<f64>,
    /// Transverse shear modulus G13 (MPa) of shear-deformable models;
    /// default p1 / 2 (the law's initial modulus, nu = 0).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub g13: Option<f64>,
}

/// `[actuator.laminate]`: options of the laminate as a whole (absent from
/// a resolved scene when none is given).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LaminateSection {
    /// The shear correction factor ks of shear-deformable models (default
    /// 5/6).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shear_correction: Option<f64>,
    /// Plane strain across the width: the strain across the width held at
    /// zero (default false: plane stress, the width free to contract).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub plane_strain: Option<bool>,
}

impl LaminateSection {
    /// Nothing given.
    pub fn is_empty(&self) -> bool {
        *self == LaminateSection::default()
    }
}

/// `[partition]`: `elements` equal elements (default 8) or `"auto"` (the
/// automatic partition), or custom `lengths` (mm, root to tip, adding up
/// to lx), or `tip_tol_mm` (equal elements doubled from `elements` until
/// the tip moves at most this much).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PartitionSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elements: Option<Elements>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lengths: Option<Vec<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tip_tol_mm: Option<f64>,
}

/// `partition.elements`: a number of elements, or `"auto"`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Elements {
    /// `N` equal elements (with `tip_tol_mm`: the number to start from).
    Count(usize),
    /// `"auto"`: element boundaries on the material changes, elements
    /// split until each turns within the CCM's slope limit
    /// ([`crate::Plan::Auto`]).
    Auto,
}

impl Serialize for Elements {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        match *self {
            Elements::Count(n) => serializer.serialize_u64(n as u64),
            Elements::Auto => serializer.serialize_str("auto"),
        }
    }
}

impl<'de> Deserialize<'de> for Elements {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Elements, D::Error> {
        struct ElementsVisitor;

        impl serde::de::Visitor<'_> for ElementsVisitor {
            type Value = Elements;

            fn expecting(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
                f.write_str("a number of elements or \"auto\"")
            }

            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Elements, E> {
                usize::try_from(v)
                    .map(Elements::Count)
                    .map_err(|_| E::invalid_value(serde::de::Unexpected::Unsigned(v), &self))
            }

            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Elements, E> {
                match u64::try_from(v) {
                    Ok(u) => self.visit_u64(u),
                    Err(_) => Err(E::invalid_value(serde::de::Unexpected::Signed(v), &self)),
                }
            }

            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Elements, E> {
                match v {
                    "auto" => Ok(Elements::Auto),
                    _ => Err(E::invalid_value(serde::de::Unexpected::Str(v), &self)),
                }
            }
        }

        deserializer.deserialize_any(ElementsVisitor)
    }
}

/// `[load]`: channel pressure (kPa), pressure factor kappa, tip force (N,
/// finger frame).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct LoadSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pressure_kpa: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kappa: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fx: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fz: Option<f64>,
}

/// The solve strategy's name in a scene.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum SceneStrategy {
    /// Decoupled elements without a tip load, the coupled system otherwise.
    Auto,
    /// Always the coupled system.
    Coupled,
}

/// `[solve]`: the fields of [`crate::SolveOptions`].
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SolveSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub rtol: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_iter: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub strategy: Option<SceneStrategy>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub samples_per_element: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub shape: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub stability: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub continuation: Option<bool>,
    /// Largest Newton step in the scaled unknowns.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub max_step: Option<f64>,
}

/// `[gripper]`: the gripper of the paper's Sec. 5 by default (a = 60 deg,
/// overlap 20 mm, three fingers, mu = 0.6).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GripperSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mounting_angle_deg: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub overlap_mm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub palm_mm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fingers: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub mu: Option<f64>,
    /// Strict mode (default false): grasps that bend an element backwards
    /// are invalid, not only flagged ([`crate::GripperParams::strict`]).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub strict: Option<bool>,
    /// The grasp to solve (none: the gripper at rest).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grasp: Option<GraspSection>,
}

/// What a grasp solves for.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum GraspKind {
    /// The normal force F that gives grasping size `d_mm` at angle
    /// `beta_deg`, with full friction f = mu F.
    Size,
    /// Force control (Sec. 5.1.2): the normal force F that holds a cuboid
    /// of size `d_mm` with friction `friction_n` per finger (b = 0).
    Cuboid,
    /// A sphere of radius `r_mm` held at angle `beta_deg` with lifting
    /// force `lift_n` per finger; F and f are solved for.
    Sphere,
}

/// `[gripper.grasp]`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GraspSection {
    /// Default "cuboid".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub kind: Option<GraspKind>,
    /// Channel pressure during the grasp (kPa), every kind.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub pressure_kpa: Option<f64>,
    /// Grasping size d (mm), kinds "size" and "cuboid".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub d_mm: Option<f64>,
    /// Grasping angle b (deg), kinds "size" and "sphere".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub beta_deg: Option<f64>,
    /// Friction f per finger (N), kind "cuboid".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub friction_n: Option<f64>,
    /// Sphere radius (mm), kind "sphere".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub r_mm: Option<f64>,
    /// Lifting force per finger (N), kind "sphere".
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lift_n: Option<f64>,
}

impl SceneFile {
    /// Parses a scene document: TOML syntax, known keys, value types.
    pub fn parse(text: &str) -> Result<SceneFile, SceneError> {
        toml::from_str(text).map_err(|e| SceneError::from_toml(text, &e))
    }

    /// [`SceneFile::parse`] of a parsed document (a sweep's point: a file
    /// with keys set by [`SceneFile::set_number`]), without writing it out
    /// and reading it back; an error is that of the written document.
    pub fn from_table(doc: &toml::Table) -> Result<SceneFile, SceneError> {
        toml::Value::Table(doc.clone())
            .try_into()
            .or_else(|e: toml::de::Error| match toml::to_string(doc) {
                Ok(text) => SceneFile::parse(&text),
                Err(_) => Err(SceneError::from_toml("", &e)),
            })
    }

    /// Sets `key` of a TOML document to `value`, making the tables on the
    /// way; a key that takes whole numbers (`partition.elements`,
    /// `solve.max_iter`, ...) gets an integer. A list's entry
    /// (`partition.lengths[2]`, `actuator.ribs.list[0].x0`) must exist. A key
    /// that takes no number, a fraction for a whole number, a missing list
    /// entry or a part of the path that holds a value, not a table, is an
    /// error naming `key`.
    pub fn set_number(doc: &mut toml::Table, key: SceneKey, value: f64) -> Result<(), InputError> {
        let field = || Field::from(key.to_string());
        let wrong = |rule: String| InputError::Inconsistent {
            field: field(),
            rule,
        };
        let v = match key.value() {
            ValueKind::Number => toml::Value::Float(value),
            ValueKind::WholeNumber if value.fract() == 0.0 && (0.0..9e15).contains(&value) => {
                toml::Value::Integer(value as i64)
            }
            ValueKind::WholeNumber => {
                return Err(InputError::OutOfRange {
                    field: field(),
                    value,
                    rule: "must be a whole number, zero or more".into(),
                })
            }
            kind => return Err(wrong(format!("takes {kind}, not a number"))),
        };
        let steps = key.steps();
        let mut table = doc;
        for (i, (name, index)) in steps.iter().enumerate() {
            let last = i + 1 == steps.len();
            let slot = match index {
                None if last => {
                    table.insert(name.clone(), v);
                    return Ok(());
                }
                None => table
                    .entry(name.clone())
                    .or_insert_with(|| toml::Value::Table(toml::Table::new())),
                Some(k) => {
                    let list = table
                        .get_mut(name)
                        .and_then(toml::Value::as_array_mut)
                        .ok_or_else(|| wrong(format!("the scene has no list '{name}'")))?;
                    let len = list.len();
                    let entry = list.get_mut(*k).ok_or_else(|| {
                        wrong(format!("'{name}' has {len} entries, counted from 0"))
                    })?;
                    if last {
                        *entry = v;
                        return Ok(());
                    }
                    entry
                }
            };
            table = slot
                .as_table_mut()
                .ok_or_else(|| wrong(format!("'{name}' is not a table in the scene")))?;
        }
        Ok(())
    }

    /// The document as TOML text, without the tables that hold no key
    /// (parsing it gives this file again).
    pub fn to_toml(&self) -> Result<String, toml::ser::Error> {
        fn prune(t: &mut toml::Table) {
            for (_, v) in t.iter_mut() {
                if let toml::Value::Table(inner) = v {
                    prune(inner);
                }
            }
            t.retain(|_, v| !matches!(v, toml::Value::Table(inner) if inner.is_empty()));
        }
        let mut table = toml::Table::try_from(self)?;
        prune(&mut table);
        toml::to_string(&table)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A parsed document reads as its text does: every example scene, with
    /// and without numbers set, and the same message for a bad value.
    #[test]
    fn a_table_reads_as_its_text() {
        let key = |text: &str| text.parse::<SceneKey>().unwrap();
        for (name, text) in crate::scene::testing::SCENES {
            let mut doc: toml::Table = toml::from_str(text).unwrap();
            let direct = SceneFile::from_table(&doc).unwrap();
            assert_eq!(direct, SceneFile::parse(text).unwrap(), "{name}");
            // an integer where a float goes, a whole number, a new table
            SceneFile::set_number(&mut doc, key("actuator.pemc.eps0"), 0.3).unwrap();
            doc["actuator"]["pemc"]["eps0"] = toml::Value::Integer(1);
            SceneFile::set_number(&mut doc, key("solve.max_iter"), 40.0).unwrap();
            let written = SceneFile::parse(&toml::to_string(&doc).unwrap()).unwrap();
            assert_eq!(SceneFile::from_table(&doc).unwrap(), written, "{name}");
            assert_eq!(written.actuator.pemc.eps0, Some(1.0), "{name}");
        }
        let doc: toml::Table = toml::from_str("[load]\nfx = \"one\"\n").unwrap();
        let via_text = SceneFile::parse(&toml::to_string(&doc).unwrap()).unwrap_err();
        assert_eq!(SceneFile::from_table(&doc).unwrap_err(), via_text);
    }

    #[test]
    fn numbers_are_set_in_nested_tables() {
        let mut doc: toml::Table = toml::from_str("[load]\nfx = 1.0\n").unwrap();
        let key = |text: &str| text.parse::<SceneKey>().unwrap();
        SceneFile::set_number(&mut doc, key("load.fx"), 2.5).unwrap();
        SceneFile::set_number(&mut doc, key("actuator.pemc.eps0"), 0.3).unwrap();
        SceneFile::set_number(&mut doc, key("partition.elements"), 16.0).unwrap();
        let s = toml::to_string(&doc).unwrap();
        let back: toml::Table = toml::from_str(&s).unwrap();
        assert_eq!(back["load"]["fx"].as_float(), Some(2.5));
        assert_eq!(back["actuator"]["pemc"]["eps0"].as_float(), Some(0.3));
        assert_eq!(back["partition"]["elements"].as_integer(), Some(16));
        let mut doc: toml::Table = toml::from_str("load = 3\n").unwrap();
        let e = SceneFile::set_number(&mut doc, key("load.fx"), 1.0).unwrap_err();
        assert!(e.to_string().starts_with("load.fx"), "{e}");
        // list entries that exist; whole numbers; keys that take no number
        let mut doc: toml::Table = toml::from_str("[partition]\nlengths = [50.0, 60.0]\n").unwrap();
        SceneFile::set_number(&mut doc, key("partition.lengths[1]"), 55.0).unwrap();
        assert_eq!(doc["partition"]["lengths"][1].as_float(), Some(55.0));
        for (k, v, says) in [
            ("partition.lengths[2]", 1.0, "'lengths' has 2 entries"),
            ("actuator.ribs.list[0].x0", 1.0, "no list 'list'"),
            ("partition.elements", 2.5, "must be a whole number"),
            ("gripper.fingers", -1.0, "must be a whole number"),
            ("gripper.strict", 1.0, "takes true or false, not a number"),
            ("model.name", 1.0, "takes a name, not a number"),
        ] {
            let e = SceneFile::set_number(&mut doc, key(k), v).unwrap_err();
            assert!(
                e.to_string().starts_with(k) && e.to_string().contains(says),
                "{e}"
            );
        }
    }

    #[test]
    fn ribs_read_as_tables_or_arrays_of_three() {
        let f = SceneFile::parse(
            "[actuator.ribs]\nlist = [{ x0 = 0, x1 = 5, width = 2 }, [10, 20, 3]]\n",
        )
        .unwrap();
        let list = f.actuator.ribs.list.unwrap();
        assert_eq!((list[0].x0, list[0].x1, list[0].width), (0.0, 5.0, 2.0));
        assert_eq!((list[1].x0, list[1].x1, list[1].width), (10.0, 20.0, 3.0));
        // the table form round-trips
        let text =
            toml::to_string(&SceneFile::parse("[actuator.ribs]\nlist = [[1, 2, 3]]\n").unwrap())
                .unwrap();
        assert_eq!(
            SceneFile::parse(&text).unwrap().actuator.ribs.list.unwrap()[0],
            RibEntry {
                x0: 1.0,
                x1: 2.0,
                width: 3.0
            }
        );
    }
}

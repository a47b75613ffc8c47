//! Scene files: one TOML document describes a finger (every actuator
//! option, the partition, the load, the solver settings) and, optionally, a
//! gripper built from it with one grasp to solve.
//!
//! Every key has the paper's default (docs/model.md), so an empty document is
//! the default actuator (eps0 = 0.25) in eight equal elements, unloaded.
//! Unknown keys are errors: a typo is reported with its line and column,
//! never ignored. Units are in the key names where they are not the
//! library's (mm, MPa, N): `pressure_kpa`, `mounting_angle_deg`, ...
//!
//! ```toml
//! [actuator.geometry]          # mm: lx, ly, lc, h, h1, h2, h3
//! lx = 110.0
//! [actuator.channel]           # mm: cx, cy, h3a, h3b
//! [actuator.ribs]              # kind = "paper" (w1, w2, t) | "list" (list) | "none"
//! kind = "paper"
//! w1 = 8.0
//! [actuator.cl]                # isotropic (e, nu) or orthotropic (e1, e2, nu12), MPa
//! [actuator.emc]
//! [actuator.fluidic]
//! [actuator.pemc]              # eps0, e2 (MPa), p1..p4 (MPa)
//! eps0 = 0.25
//! [partition]                  # elements = N | lengths = [...] | tip_tol_mm (+ elements to start)
//! elements = 8
//! [load]                       # pressure_kpa, kappa, fx, fz (N, finger frame)
//! [solve]                      # rtol, max_iter, strategy, samples_per_element, shape, stability, continuation, max_step
//! [gripper]                    # mounting_angle_deg, overlap_mm | palm_mm, fingers, mu
//! [gripper.grasp]              # kind = "size" | "cuboid" | "sphere", with its keys
//! ```
//!
//! Reading is two steps: [`SceneFile::parse`] checks the TOML and its keys
//! and types ([`SceneError`] with line and column), [`SceneFile::resolve`]
//! checks the values through the library's validating constructors
//! ([`InputError`] naming the key by its TOML path, e.g.
//! `actuator.geometry.h1`). [`Scene::solve`] then solves the finger or the
//! grasp.

use std::f64::consts::FRAC_PI_2;

use serde::{Deserialize, Serialize};

use crate::actuator::{
    Actuator, ActuatorParams, Channel, Geometry, Isotropic, Material, Orthotropic, Prestressed,
    PsiLaw, Rib, RibLayout,
};
use crate::blocks::Partition;
use crate::error::{finite, positive, require, InputError, SolveError, Warning};
use crate::finger::{Finger, Load, Solution, SolveOptions, Strategy};
use crate::gripper::{Grasp, Gripper, GripperParams, Invalid, PalmSpec, SphereContact};
use crate::refine::solve_to_tip_tolerance;

// ------------------------------------------------------------ errors

/// A scene document that is not valid TOML, or has an unknown key or a
/// value of the wrong type. `line` and `col` (both from 1; the column
/// counts characters) locate the offending text.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("{line}:{col}: {message}")]
pub struct SceneError {
    /// Line of the offending text (from 1).
    pub line: usize,
    /// Column of the offending text (from 1, in characters).
    pub col: usize,
    /// What is wrong and, where the parser knows, what was expected (one line).
    pub message: String,
}

impl SceneError {
    fn from_toml(text: &str, e: &toml::de::Error) -> SceneError {
        let (line, col) = match e.span() {
            Some(span) => line_col(text, span.start),
            None => (1, 1),
        };
        let mut message = e
            .message()
            .lines()
            .map(str::trim)
            .filter(|l| !l.is_empty())
            .collect::<Vec<_>>()
            .join("; ");
        if e.span().is_none() {
            message.push_str(" (position unknown)");
        }
        SceneError { line, col, message }
    }
}

/// Line and column (both from 1; the column in characters) of a byte
/// offset into `text`. An offset past the end is the end; one inside a
/// character is that character.
pub fn line_col(text: &str, offset: usize) -> (usize, usize) {
    let mut o = offset.min(text.len());
    while !text.is_char_boundary(o) {
        o -= 1;
    }
    let before = &text[..o];
    let line = before.matches('\n').count() + 1;
    let start = before.rfind('\n').map_or(0, |i| i + 1);
    (line, before[start..].chars().count() + 1)
}

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

// ------------------------------------------------------------ the document

/// A scene document as written: every key optional (absent keys take the
/// paper's defaults in [`SceneFile::resolve`]), unknown keys rejected.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SceneFile {
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
}

/// `[actuator]`.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct ActuatorSection {
    pub geometry: GeometrySection,
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
}

/// `[actuator.geometry]`, mm.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
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

/// `[actuator.channel]`, mm.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
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
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RibEntry {
    pub x0: f64,
    pub x1: f64,
    pub width: f64,
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
}

/// `[partition]`: `elements` equal elements (default 8), or custom
/// `lengths` (mm, root to tip, adding up to lx), or `tip_tol_mm` (equal
/// elements doubled from `elements` until the tip moves at most this much).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct PartitionSection {
    #[serde(skip_serializing_if = "Option::is_none")]
    pub elements: Option<usize>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub lengths: Option<Vec<f64>>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tip_tol_mm: Option<f64>,
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

/// `[solve]`: the fields of [`SolveOptions`].
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
    /// Strict mode: grasps that bend an element backwards are invalid.
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

// ------------------------------------------------------------ defaults

/// Default number of equal elements (the paper's N).
pub const DEFAULT_ELEMENTS: usize = 8;
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
    /// Equal elements doubled from `start` until the estimated tip error is
    /// at most `tip_tol_mm` ([`solve_to_tip_tolerance`]).
    TipTolerance { tip_tol_mm: f64, start: usize },
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
    /// Compute the Hessian's smallest eigenvalue of the grasp (`solve.stability`).
    pub stability: bool,
    /// The grasp to solve; `None`: the gripper at rest.
    pub grasp: Option<GraspSpec>,
}

/// A validated scene, ready to solve.
#[derive(Debug, Clone)]
pub struct Scene {
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
    file: SceneFile,
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

    /// Non-fatal notes about the actuator (gripper notes come with the
    /// solution, [`SceneSolution::warnings`]).
    pub fn warnings(&self) -> &[Warning] {
        self.actuator.warnings()
    }

    /// Solves the finger, or builds the gripper and solves its grasp.
    /// Input errors name the scene's keys.
    pub fn solve(&self) -> Result<SceneSolution, SolveError> {
        self.solve_inner().map_err(rename_solve)
    }

    fn solve_inner(&self) -> Result<SceneSolution, SolveError> {
        let finger = |part: &Partition| Finger::new(&self.actuator, part, true);
        let Some(g) = &self.gripper else {
            return Ok(match &self.partition {
                PartitionPlan::Fixed(part) => SceneSolution::Finger {
                    solution: finger(part).solve(&self.load, &self.options)?,
                    elements: part.len(),
                    tip_error_estimate_mm: None,
                },
                &PartitionPlan::TipTolerance { tip_tol_mm, start } => {
                    let r = solve_to_tip_tolerance(
                        crate::ModelId::default(),
                        &self.actuator,
                        true,
                        &self.load,
                        tip_tol_mm,
                        start,
                        &self.options,
                    )?;
                    SceneSolution::Finger {
                        solution: r.solution,
                        elements: r.elements,
                        tip_error_estimate_mm: Some(r.estimated_tip_error_mm),
                    }
                }
            });
        };
        let PartitionPlan::Fixed(part) = &self.partition else {
            // resolve() rejects tip_tol_mm with a gripper
            return Err(InputError::Inconsistent {
                field: "partition.tip_tol_mm".into(),
                rule: "not supported in a gripper scene".into(),
            }
            .into());
        };
        let gripper = Gripper::new(finger(part), g.params)?.with_stability(g.stability);
        let grasp = match g.grasp {
            None => None,
            Some(spec) => Some(Box::new(solve_grasp(&gripper, spec)?)),
        };
        Ok(SceneSolution::Gripper {
            gripper: Box::new(gripper),
            grasp,
        })
    }
}

fn solve_grasp(gripper: &Gripper, spec: GraspSpec) -> Result<GraspOutcome, SolveError> {
    let (grasp, sphere) = match spec {
        GraspSpec::Size {
            pressure_kpa,
            d_mm,
            beta_deg,
        } => (
            gripper.grasp_load_for_size(pressure_kpa, d_mm, beta_deg.to_radians(), None)?,
            None,
        ),
        GraspSpec::Cuboid {
            pressure_kpa,
            d_mm,
            friction_n,
        } => (
            gripper.force_control(pressure_kpa, d_mm, friction_n, None)?,
            None,
        ),
        GraspSpec::Sphere {
            pressure_kpa,
            r_mm,
            lift_n,
            beta_deg,
        } => {
            let sg =
                gripper.sphere_grasp(pressure_kpa, r_mm, lift_n, beta_deg.to_radians(), None)?;
            let contact = SphereContact {
                radius: sg.radius,
                center: sg.center,
                invalid: sg.invalid,
            };
            (sg.grasp, Some(contact))
        }
    };
    let invalid = match &sphere {
        Some(c) => c.invalid,
        None => open_and_friction(&grasp, gripper.mu()),
    };
    Ok(GraspOutcome {
        spec,
        grasp,
        sphere,
        invalid,
    })
}

/// The validity of a cuboid or size grasp: the fingers open (`d > 0` and a
/// positive tip gap), `F >= 0` and `0 <= f <= mu F`.
fn open_and_friction(g: &Grasp, mu: f64) -> Option<Invalid> {
    if !(g.size > 0.0 && g.tip_gap > 0.0) {
        return Some(Invalid::NotOpen {
            size: g.size,
            tip_gap: g.tip_gap,
        });
    }
    let tol = 1e-12 * (1.0 + g.normal.abs());
    if g.normal < -tol {
        return Some(Invalid::NegativeNormal { normal: g.normal });
    }
    if !g.friction_ok(mu) {
        return Some(Invalid::FrictionCone {
            friction: g.friction,
            limit: mu * g.normal,
        });
    }
    None
}

/// A solved grasp.
#[derive(Debug, Clone, PartialEq)]
pub struct GraspOutcome {
    /// What was asked.
    pub spec: GraspSpec,
    /// The equilibrium and its measures (F, f, f_v, d, tip gap, h).
    pub grasp: Grasp,
    /// For a sphere: its radius, centre (gripper frame) and geometric validity.
    pub sphere: Option<SphereContact>,
    /// The first rule the grasp breaks (`None`: valid).
    pub invalid: Option<Invalid>,
}

impl GraspOutcome {
    /// True when the grasp breaks no rule.
    pub fn is_valid(&self) -> bool {
        self.invalid.is_none()
    }
}

/// The result of [`Scene::solve`].
#[derive(Debug, Clone)]
pub enum SceneSolution {
    /// A finger scene.
    Finger {
        solution: Solution,
        /// The number of elements used.
        elements: usize,
        /// With `tip_tol_mm`: the estimated tip error (mm).
        tip_error_estimate_mm: Option<f64>,
    },
    /// A gripper scene: the gripper (its reference state, l0, palm,
    /// overlap) and the grasp, if one was asked.
    Gripper {
        gripper: Box<Gripper>,
        grasp: Option<Box<GraspOutcome>>,
    },
}

impl SceneSolution {
    /// The finger's equilibrium: the grasp's, or the gripper's reference
    /// state when there is no grasp.
    pub fn solution(&self) -> &Solution {
        match self {
            SceneSolution::Finger { solution, .. } => solution,
            SceneSolution::Gripper { grasp: Some(g), .. } => &g.grasp.solution,
            SceneSolution::Gripper { gripper, .. } => gripper.reference(),
        }
    }

    /// The number of elements used.
    pub fn elements(&self) -> usize {
        match self {
            SceneSolution::Finger { elements, .. } => *elements,
            SceneSolution::Gripper { gripper, .. } => gripper.finger().len(),
        }
    }

    /// Non-fatal notes about the gripper's design.
    pub fn warnings(&self) -> &[Warning] {
        match self {
            SceneSolution::Finger { .. } => &[],
            SceneSolution::Gripper { gripper, .. } => gripper.warnings(),
        }
    }
}

/// A warning in the scene's terms (its keys and units).
pub fn warning_text(w: &Warning) -> String {
    match *w {
        Warning::MountingAngleOutsideDesignSpace { angle, lo, hi } => format!(
            "gripper.mounting_angle_deg = {}: outside the design space [{}, {}] deg (arccot mu to 90 deg)",
            degrees(angle),
            degrees(lo),
            degrees(hi)
        ),
        Warning::PalmGapAtRest { palm, reach } => format!(
            "gripper: the palm diameter {palm:.4} mm is wider than twice the finger's inward reach l0 = {reach:.4} mm (negative overlap): the fingers leave a gap at rest"
        ),
        _ => w.to_string(),
    }
}

/// Radians in degrees, rounded to 1e-9 deg (so 60 deg prints as 60).
fn degrees(rad: f64) -> f64 {
    (rad.to_degrees() * 1e9).round() / 1e9
}

// ------------------------------------------------------------ parsing

impl SceneFile {
    /// Parses a scene document: TOML syntax, known keys, value types.
    pub fn parse(text: &str) -> Result<SceneFile, SceneError> {
        toml::from_str(text).map_err(|e| SceneError::from_toml(text, &e))
    }

    /// Checks every value and builds the scene (the defaults fill absent
    /// keys). Errors name the key by its TOML path.
    pub fn resolve(&self) -> Result<Scene, InputError> {
        resolve(self).map_err(rename)
    }
}

fn inconsistent(field: &str, rule: impl Into<String>) -> InputError {
    InputError::Inconsistent {
        field: field.into(),
        rule: rule.into(),
    }
}

/// Fails for the first key of `keys` that is set.
fn forbid(keys: &[(&str, bool)], rule: &str) -> Result<(), InputError> {
    match keys.iter().find(|(_, set)| *set) {
        Some((k, _)) => Err(inconsistent(k, rule)),
        None => Ok(()),
    }
}

fn resolve(f: &SceneFile) -> Result<Scene, InputError> {
    let mut file = SceneFile::default();
    let actuator = resolve_actuator(&f.actuator, &mut file.actuator)?;
    let lx = actuator.geometry().lx;
    let gripper_scene = f.gripper.is_some();

    // partition
    let p = &f.partition;
    let partition = match (&p.lengths, p.tip_tol_mm) {
        (Some(_), _) if p.elements.is_some() => {
            return Err(inconsistent(
                "partition.lengths",
                "give either elements or lengths, not both",
            ))
        }
        (Some(_), Some(_)) => {
            return Err(inconsistent(
                "partition.tip_tol_mm",
                "refines equal elements; it cannot be combined with lengths",
            ))
        }
        (Some(lengths), None) => {
            file.partition.lengths = Some(lengths.clone());
            PartitionPlan::Fixed(Partition::custom(lengths.clone(), lx)?)
        }
        (None, Some(tol)) => {
            if gripper_scene {
                return Err(inconsistent(
                    "partition.tip_tol_mm",
                    "not supported in a gripper scene (give elements or lengths)",
                ));
            }
            positive("partition.tip_tol_mm", tol)?;
            let start = p.elements.unwrap_or(DEFAULT_ELEMENTS);
            Partition::equal(lx, start)?;
            file.partition.tip_tol_mm = Some(tol);
            file.partition.elements = Some(start);
            PartitionPlan::TipTolerance {
                tip_tol_mm: tol,
                start,
            }
        }
        (None, None) => {
            let n = p.elements.unwrap_or(DEFAULT_ELEMENTS);
            file.partition.elements = Some(n);
            PartitionPlan::Fixed(Partition::equal(lx, n)?)
        }
    };

    // load
    let l = &f.load;
    let load = if gripper_scene {
        forbid(
            &[
                ("load.pressure_kpa", l.pressure_kpa.is_some()),
                ("load.kappa", l.kappa.is_some()),
                ("load.fx", l.fx.is_some()),
                ("load.fz", l.fz.is_some()),
            ],
            "not used in a gripper scene: the grasp solves for the tip load (set the pressure with gripper.grasp.pressure_kpa)",
        )?;
        Load::unloaded()
    } else {
        let d = Load::default();
        let kpa = finite("load.pressure_kpa", l.pressure_kpa.unwrap_or(0.0))?;
        let load = Load {
            pressure: kpa * 1e-3,
            kappa: l.kappa.unwrap_or(d.kappa),
            fx: l.fx.unwrap_or(d.fx),
            fz: l.fz.unwrap_or(d.fz),
        };
        load.validate()?;
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
                ("solve.rtol", s.rtol.is_some()),
                ("solve.max_iter", s.max_iter.is_some()),
                ("solve.strategy", s.strategy.is_some()),
                ("solve.samples_per_element", s.samples_per_element.is_some()),
                ("solve.shape", s.shape.is_some()),
                ("solve.continuation", s.continuation.is_some()),
                ("solve.max_step", s.max_step.is_some()),
            ],
            "not used in a gripper scene: grasps are solved with the gripper's own settings (only solve.stability applies)",
        )?;
        file.solve.stability = Some(s.stability.unwrap_or(false));
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
        positive("solve.rtol", o.rtol)?;
        positive("solve.max_step", o.max_step)?;
        require(
            o.max_iter >= 1,
            "solve.max_iter",
            o.max_iter as f64,
            "must be at least 1".into(),
        )?;
        require(
            o.samples_per_element >= 1,
            "solve.samples_per_element",
            o.samples_per_element as f64,
            "must be at least 1".into(),
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
            let (scene, echo) = resolve_gripper(g, s.stability.unwrap_or(false))?;
            file.gripper = Some(echo);
            Some(scene)
        }
    };

    Ok(Scene {
        actuator,
        partition,
        load,
        options,
        gripper,
        file,
    })
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
    let (cl, e) = resolve_material(&a.cl, d.cl, "actuator.cl")?;
    echo.cl = e;
    let (emc, e) = resolve_material(&a.emc, d.emc, "actuator.emc")?;
    echo.emc = e;
    let (fluidic, e) = resolve_material(&a.fluidic, d.fluidic, "actuator.fluidic")?;
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
        ("actuator.ribs.w1", r.w1.is_some()),
        ("actuator.ribs.w2", r.w2.is_some()),
        ("actuator.ribs.t", r.t.is_some()),
    ];
    let list_key = [("actuator.ribs.list", r.list.is_some())];
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
                    "actuator.ribs.list",
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
    path: &str,
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
    let key = |k: &str| format!("{path}.{k}");
    // a value of this kind: the file's, else the layer's default if it is
    // of the same kind, else required
    let value = |k: &str, v: Option<f64>, fallback: Option<f64>| -> Result<f64, InputError> {
        v.or(fallback).ok_or_else(|| {
            inconsistent(
                &key(k),
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
                    (&key("e1"), m.e1.is_some()),
                    (&key("e2"), m.e2.is_some()),
                    (&key("nu12"), m.nu12.is_some()),
                ],
                "an orthotropic key, but the layer is isotropic (keys e, nu)",
            )?;
            let d = match default {
                Material::Isotropic(d) => Some(d),
                Material::Orthotropic(_) => None,
            };
            let iso = Isotropic {
                e: value("e", m.e, d.map(|d| d.e))?,
                nu: value("nu", m.nu, d.map(|d| d.nu))?,
            };
            (echo.e, echo.nu) = (Some(iso.e), Some(iso.nu));
            Material::Isotropic(iso)
        }
        MaterialKind::Orthotropic => {
            forbid(
                &[(&key("e"), m.e.is_some()), (&key("nu"), m.nu.is_some())],
                "an isotropic key, but the layer is orthotropic (keys e1, e2, nu12)",
            )?;
            let d = match default {
                Material::Orthotropic(d) => Some(d),
                Material::Isotropic(_) => None,
            };
            let o = Orthotropic {
                e1: value("e1", m.e1, d.map(|d| d.e1))?,
                e2: value("e2", m.e2, d.map(|d| d.e2))?,
                nu12: value("nu12", m.nu12, d.map(|d| d.nu12))?,
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
        "gripper.mounting_angle_deg",
        g.mounting_angle_deg.unwrap_or(DEFAULT_MOUNTING_ANGLE_DEG),
    )?;
    require(
        angle_deg > 0.0 && angle_deg < 180.0,
        "gripper.mounting_angle_deg",
        angle_deg,
        "must lie in (0, 180) degrees: the finger points away from the palm".into(),
    )?;
    let mu = positive("gripper.mu", g.mu.unwrap_or(d.mu))?;
    let strict = g.strict.unwrap_or(false);
    let fingers = g.fingers.unwrap_or(d.fingers);
    require(
        fingers >= 1,
        "gripper.fingers",
        fingers as f64,
        "must be at least 1".into(),
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
                "gripper.palm_mm",
                "give either overlap_mm or palm_mm, not both",
            ))
        }
        (_, Some(l)) => {
            finite("gripper.palm_mm", l)?;
            require(
                l >= 0.0,
                "gripper.palm_mm",
                l,
                "must not be negative".into(),
            )?;
            echo.palm_mm = Some(l);
            PalmSpec::Palm(l)
        }
        (o, None) => {
            let o = finite("gripper.overlap_mm", o.unwrap_or(DEFAULT_OVERLAP_MM))?;
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
    let pressure_kpa = finite("gripper.grasp.pressure_kpa", s.pressure_kpa.unwrap_or(0.0))?;
    let beta = |limit_open: bool| -> Result<f64, InputError> {
        let default = if limit_open {
            DEFAULT_SPHERE_BETA_DEG
        } else {
            0.0
        };
        let b = finite("gripper.grasp.beta_deg", s.beta_deg.unwrap_or(default))?;
        let ok = if limit_open {
            b.abs() < 90.0 && b.to_radians().abs() < FRAC_PI_2
        } else {
            b.abs() <= 90.0
        };
        let range = if limit_open { "(-90, 90)" } else { "[-90, 90]" };
        require(
            ok,
            "gripper.grasp.beta_deg",
            b,
            format!("must lie in {range}"),
        )?;
        Ok(b)
    };
    let spec = match kind {
        GraspKind::Size => {
            forbid(
                &[
                    ("gripper.grasp.friction_n", s.friction_n.is_some()),
                    ("gripper.grasp.r_mm", s.r_mm.is_some()),
                    ("gripper.grasp.lift_n", s.lift_n.is_some()),
                ],
                &rule,
            )?;
            GraspSpec::Size {
                pressure_kpa,
                d_mm: finite(
                    "gripper.grasp.d_mm",
                    s.d_mm.unwrap_or(DEFAULT_GRASP_SIZE_MM),
                )?,
                beta_deg: beta(false)?,
            }
        }
        GraspKind::Cuboid => {
            forbid(
                &[
                    ("gripper.grasp.beta_deg", s.beta_deg.is_some()),
                    ("gripper.grasp.r_mm", s.r_mm.is_some()),
                    ("gripper.grasp.lift_n", s.lift_n.is_some()),
                ],
                &format!("{rule} (a cuboid is held at b = 0)"),
            )?;
            GraspSpec::Cuboid {
                pressure_kpa,
                d_mm: positive(
                    "gripper.grasp.d_mm",
                    s.d_mm.unwrap_or(DEFAULT_GRASP_SIZE_MM),
                )?,
                friction_n: finite(
                    "gripper.grasp.friction_n",
                    s.friction_n.unwrap_or(DEFAULT_CUBOID_FRICTION_N),
                )?,
            }
        }
        GraspKind::Sphere => {
            forbid(
                &[
                    ("gripper.grasp.d_mm", s.d_mm.is_some()),
                    ("gripper.grasp.friction_n", s.friction_n.is_some()),
                ],
                &format!("{rule} (the sphere's size is r_mm; F and f are solved for)"),
            )?;
            GraspSpec::Sphere {
                pressure_kpa,
                r_mm: positive(
                    "gripper.grasp.r_mm",
                    s.r_mm.unwrap_or(DEFAULT_SPHERE_RADIUS_MM),
                )?,
                lift_n: finite(
                    "gripper.grasp.lift_n",
                    s.lift_n.unwrap_or(DEFAULT_SPHERE_LIFT_N),
                )?,
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

// ------------------------------------------------------------ field names

/// The scene key of a field the library names in its own terms.
fn toml_path(field: &str) -> String {
    if let Some(rest) = field.strip_prefix("actuator.pemc.law.") {
        return format!("actuator.pemc.{rest}");
    }
    if let Some(rest) = field.strip_prefix("actuator.ribs[") {
        return format!("actuator.ribs.list[{rest}");
    }
    let renamed = match field {
        "partition.n" => "partition.elements",
        "partition.lx" => "actuator.geometry.lx",
        "partition.lengths (sum)" => "partition.lengths",
        "tip_tol_mm" => "partition.tip_tol_mm",
        "load.pressure" => "load.pressure_kpa",
        "gripper.mounting_angle" => "gripper.mounting_angle_deg",
        "gripper.overlap" => "gripper.overlap_mm",
        "gripper.palm" => "gripper.palm_mm",
        "grasp.pressure_kpa" => "gripper.grasp.pressure_kpa",
        "grasp.size" => "gripper.grasp.d_mm",
        "grasp.beta" | "sphere.beta" => "gripper.grasp.beta_deg",
        "grasp.friction" => "gripper.grasp.friction_n",
        "sphere.radius" => "gripper.grasp.r_mm",
        "sphere.lift" => "gripper.grasp.lift_n",
        other => other,
    };
    renamed.to_string()
}

/// The same error naming the field by its scene key.
fn rename(e: InputError) -> InputError {
    match e {
        InputError::NotFinite { field, value } => InputError::NotFinite {
            field: toml_path(&field),
            value,
        },
        InputError::NotPositive { field, value } => InputError::NotPositive {
            field: toml_path(&field),
            value,
        },
        InputError::OutOfRange { field, value, rule } => InputError::OutOfRange {
            field: toml_path(&field),
            value,
            rule,
        },
        InputError::Inconsistent { field, rule } => InputError::Inconsistent {
            field: toml_path(&field),
            rule,
        },
        InputError::Unrecognised { field, value, rule } => InputError::Unrecognised {
            field: toml_path(&field),
            value,
            rule,
        },
    }
}

fn rename_solve(e: SolveError) -> SolveError {
    match e {
        SolveError::Input(i) => SolveError::Input(rename(i)),
        other => other,
    }
}

// ------------------------------------------------------------ tests

#[cfg(test)]
mod tests {
    use super::*;

    const SCENES: &[(&str, &str)] = &[
        ("default.toml", include_str!("../scenes/default.toml")),
        (
            "pressurised.toml",
            include_str!("../scenes/pressurised.toml"),
        ),
        ("tip_load.toml", include_str!("../scenes/tip_load.toml")),
        (
            "no_ribs_custom.toml",
            include_str!("../scenes/no_ribs_custom.toml"),
        ),
        (
            "cuboid_grasp.toml",
            include_str!("../scenes/cuboid_grasp.toml"),
        ),
        (
            "sphere_grasp.toml",
            include_str!("../scenes/sphere_grasp.toml"),
        ),
    ];

    fn input_err(text: &str) -> InputError {
        match Scene::from_toml(text) {
            Err(SceneReadError::Input(e)) => e,
            other => panic!("expected an input error for {text:?}, got {other:?}"),
        }
    }

    fn syntax_err(text: &str) -> SceneError {
        match SceneFile::parse(text) {
            Err(e) => e,
            Ok(f) => panic!("expected a syntax error for {text:?}, got {f:?}"),
        }
    }

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
        for (name, text) in SCENES.iter().chain(&[("empty", "")]) {
            let s = Scene::from_toml(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let again = s.file().resolve().unwrap();
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
        assert_eq!(echo.partition.elements, Some(8));
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
    fn unknown_key_is_rejected_with_its_name_and_line() {
        let e = syntax_err("[actuator.geometry]\nlx = 100\nlxx = 3\n");
        assert_eq!(e.line, 3, "{e}");
        assert_eq!(e.col, 1, "{e}");
        assert!(e.message.contains("lxx"), "{e}");
        let e = syntax_err("[load]\npresure_kpa = 3\n");
        assert_eq!((e.line, e.col), (2, 1), "{e}");
        assert!(e.message.contains("presure_kpa"), "{e}");
        // a misspelled section
        let e = syntax_err("# comment\n\n[actuatr]\n");
        assert_eq!(e.line, 3, "{e}");
        assert!(e.message.contains("actuatr"), "{e}");
        // a misspelled key inside an inline table in a list
        let e = syntax_err("[actuator.ribs]\nlist = [\n  { x0 = 0, x1 = 5, widht = 2 },\n]\n");
        assert_eq!(e.line, 3, "{e}");
        assert!(e.message.contains("widht"), "{e}");
        // a bad enumeration value
        let e = syntax_err("[gripper.grasp]\nkind = \"cube\"\n");
        assert_eq!(e.line, 2, "{e}");
        assert!(e.message.contains("cube"), "{e}");
    }

    #[test]
    fn syntax_errors_give_line_and_column() {
        let e = syntax_err("[load]\nfx = 0.1\nfz = = 2\n");
        assert_eq!(e.line, 3, "{e}");
        assert_eq!(e.col, 6, "{e}");
        let e = syntax_err("[partition]\nelements = 8.5\n");
        assert_eq!(e.line, 2, "{e}");
        assert_eq!(e.col, 12, "{e}");
        assert!(e.to_string().starts_with("2:12: "), "{e}");
        let e = syntax_err("[solve\n");
        assert_eq!(e.line, 1, "{e}");
        let e = syntax_err("[load]\nfx = \"a\"\n");
        assert_eq!((e.line, e.col), (2, 6), "{e}");
        let e = syntax_err("[partition]\nelements = -1\n");
        assert_eq!((e.line, e.col), (2, 12), "{e}");
        // columns count characters, not bytes
        let e = syntax_err("# é\n[load] # ü\nfx = ä\n");
        assert_eq!((e.line, e.col), (3, 6), "{e}");
        // messages are one line
        for text in [
            "[a",
            "x = [1,",
            "a = \"\n\"",
            "[[gripper]]",
            "a.b = 1\na = 2",
        ] {
            let e = syntax_err(text);
            assert!(!e.message.contains('\n'), "{e}");
        }
    }

    #[test]
    fn line_col_of_offsets() {
        let t = "ab\ncé\n";
        assert_eq!(line_col(t, 0), (1, 1));
        assert_eq!(line_col(t, 2), (1, 3));
        assert_eq!(line_col(t, 3), (2, 1));
        assert_eq!(line_col(t, 4), (2, 2));
        assert_eq!(line_col(t, 5), (2, 2)); // inside é
        assert_eq!(line_col(t, 6), (2, 3));
        assert_eq!(line_col(t, 7), (3, 1));
        assert_eq!(line_col(t, 100), (3, 1));
    }

    #[test]
    fn validation_errors_name_the_toml_path() {
        let cases: &[(&str, &str)] = &[
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
            ("[load]\npressure_kpa = nan", "load.pressure_kpa"),
            ("[load]\nkappa = 0", "load.kappa"),
            ("[load]\nfx = inf", "load.fx"),
            ("[solve]\nrtol = 0", "solve.rtol"),
            ("[solve]\nmax_iter = 0", "solve.max_iter"),
            ("[solve]\nsamples_per_element = 0", "solve.samples_per_element"),
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
        }
    }

    #[test]
    fn solve_errors_name_the_toml_path() {
        // an overlap larger than the finger's reach is found by the gripper
        let s = Scene::from_toml("[gripper]\noverlap_mm = 500\n").unwrap();
        match s.solve() {
            Err(SolveError::Input(e)) => assert_eq!(e.field(), "gripper.overlap_mm", "{e}"),
            other => panic!("{other:?}"),
        }
        // a tip tolerance that cannot be reached
        let s = Scene::from_toml("[partition]\ntip_tol_mm = 1e-30\nelements = 256\n").unwrap();
        match s.solve() {
            Err(SolveError::Input(e)) => assert_eq!(e.field(), "partition.tip_tol_mm", "{e}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn toml_paths_of_library_fields() {
        assert_eq!(toml_path("actuator.pemc.law.p1"), "actuator.pemc.p1");
        assert_eq!(toml_path("actuator.pemc.law.p4"), "actuator.pemc.p4");
        assert_eq!(
            toml_path("actuator.ribs[2].width"),
            "actuator.ribs.list[2].width"
        );
        assert_eq!(toml_path("actuator.ribs.w1"), "actuator.ribs.w1");
        assert_eq!(toml_path("actuator.ribs"), "actuator.ribs");
        assert_eq!(toml_path("load.pressure"), "load.pressure_kpa");
    }

    #[test]
    fn warnings_use_scene_keys() {
        let s = Scene::from_toml("[gripper]\nmounting_angle_deg = 30\n").unwrap();
        let sol = s.solve().unwrap();
        let texts: Vec<String> = sol.warnings().iter().map(warning_text).collect();
        assert!(
            texts
                .iter()
                .any(|t| t.starts_with("gripper.mounting_angle_deg = 30")),
            "{texts:?}"
        );
        let s = Scene::from_toml("[actuator.pemc]\neps0 = 0.8\n").unwrap();
        let texts: Vec<String> = s.warnings().iter().map(warning_text).collect();
        assert!(
            texts[0].starts_with("actuator.pemc.eps0 = 0.8"),
            "{texts:?}"
        );
    }

    #[test]
    fn example_scenes_parse_and_solve() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".toml"))
            .collect();
        on_disk.sort();
        let mut listed: Vec<String> = SCENES.iter().map(|(n, _)| n.to_string()).collect();
        listed.sort();
        assert_eq!(on_disk, listed, "every scene in scenes/ is tested here");
        for (name, text) in SCENES {
            let scene = Scene::from_toml(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let sol = scene.solve().unwrap_or_else(|e| panic!("{name}: {e}"));
            let s = sol.solution();
            assert!(s.tip.iter().all(|v| v.is_finite()), "{name}");
            assert!(!s.points.is_empty(), "{name}");
            if let SceneSolution::Gripper { grasp: Some(g), .. } = &sol {
                assert!(g.is_valid(), "{name}: {:?}", g.invalid);
            }
        }
    }

    #[test]
    fn example_grasps_match_the_library() {
        // the cuboid example is the paper's force control scene
        let text = SCENES
            .iter()
            .find(|(n, _)| *n == "cuboid_grasp.toml")
            .unwrap()
            .1;
        let scene = Scene::from_toml(text).unwrap();
        let g = scene.gripper.unwrap();
        assert_eq!(g.params.mounting_angle, 60f64.to_radians());
        assert_eq!(g.params.geometry, PalmSpec::Overlap(20.0));
        let Some(GraspSpec::Cuboid {
            d_mm, friction_n, ..
        }) = g.grasp
        else {
            panic!()
        };
        let SceneSolution::Gripper {
            gripper,
            grasp: Some(out),
        } = scene.solve().unwrap()
        else {
            panic!()
        };
        let direct = gripper
            .force_control(out.grasp.pressure_kpa, d_mm, friction_n, None)
            .unwrap();
        assert_eq!(direct.normal, out.grasp.normal);
        assert!((out.grasp.size - d_mm).abs() < 1e-6);
        assert!((out.grasp.friction - friction_n).abs() < 1e-9);
    }
}

#[cfg(test)]
mod fuzz {
    //! The parser and the resolution never panic and always return, on
    //! random text and on random edits of the example scenes.

    use super::SceneFile;
    use proptest::prelude::*;
    use proptest::test_runner::{Config, RngAlgorithm, TestRng, TestRunner};
    use std::sync::mpsc;
    use std::time::Duration;

    const EXAMPLES: &[&str] = &[
        include_str!("../scenes/default.toml"),
        include_str!("../scenes/pressurised.toml"),
        include_str!("../scenes/tip_load.toml"),
        include_str!("../scenes/no_ribs_custom.toml"),
        include_str!("../scenes/cuboid_grasp.toml"),
        include_str!("../scenes/sphere_grasp.toml"),
    ];

    /// Parse and resolve; every error must carry a usable position or path.
    fn read(text: &str) {
        match SceneFile::parse(text) {
            Ok(f) => match f.resolve() {
                Ok(s) => {
                    let _ = s.file().resolve();
                }
                Err(e) => assert!(!e.field().is_empty()),
            },
            Err(e) => {
                let lines = text.split('\n').count();
                assert!(e.line >= 1 && e.line <= lines, "{e} in {lines} lines");
                assert!(e.col >= 1, "{e}");
                assert!(!e.message.contains('\n'), "{e}");
            }
        }
    }

    #[derive(Debug, Clone)]
    enum Edit {
        Delete(usize),
        Insert(usize, char),
        Replace(usize, char),
    }

    fn edit_char() -> impl Strategy<Value = char> {
        prop_oneof![
            4 => prop::sample::select(
                "[]{}=\"'#.,\n -+0123456789eEinfatrusl_".chars().collect::<Vec<_>>()
            ),
            1 => any::<char>(),
        ]
    }

    fn edit() -> impl Strategy<Value = Edit> {
        prop_oneof![
            any::<usize>().prop_map(Edit::Delete),
            (any::<usize>(), edit_char()).prop_map(|(i, c)| Edit::Insert(i, c)),
            (any::<usize>(), edit_char()).prop_map(|(i, c)| Edit::Replace(i, c)),
        ]
    }

    fn apply(text: &str, edits: &[Edit]) -> String {
        let mut chars: Vec<char> = text.chars().collect();
        for e in edits {
            match *e {
                Edit::Delete(i) if !chars.is_empty() => {
                    let i = i % chars.len();
                    chars.remove(i);
                }
                Edit::Insert(i, c) => {
                    let i = i % (chars.len() + 1);
                    chars.insert(i, c);
                }
                Edit::Replace(i, c) if !chars.is_empty() => {
                    let i = i % chars.len();
                    chars[i] = c;
                }
                _ => {}
            }
        }
        chars.into_iter().collect()
    }

    fn runner(cases: u32) -> TestRunner {
        let config = Config {
            cases,
            failure_persistence: None,
            ..Config::default()
        };
        TestRunner::new_with_rng(config, TestRng::from_seed(RngAlgorithm::ChaCha, &[7; 32]))
    }

    /// Runs `f` on another thread and fails if it does not return in time.
    fn within(limit: Duration, f: impl FnOnce() + Send + 'static) {
        let (tx, rx) = mpsc::channel();
        let handle = std::thread::spawn(move || {
            f();
            let _ = tx.send(());
        });
        match rx.recv_timeout(limit) {
            Ok(()) => handle.join().unwrap(),
            Err(mpsc::RecvTimeoutError::Disconnected) => {
                if let Err(p) = handle.join() {
                    std::panic::resume_unwind(p)
                }
            }
            Err(mpsc::RecvTimeoutError::Timeout) => {
                panic!("the parser did not return within {limit:?}")
            }
        }
    }

    #[test]
    fn random_text_never_panics_or_hangs() {
        within(Duration::from_secs(120), || {
            runner(300)
                .run(&"[ -~\t\n]{0,300}", |text| {
                    read(&text);
                    Ok(())
                })
                .unwrap();
            // TOML-flavoured text: brackets, keys, values
            let tokenish = prop::collection::vec(
                prop::sample::select(vec![
                    "[",
                    "]",
                    "[[",
                    "]]",
                    "{",
                    "}",
                    "=",
                    "\"",
                    "'",
                    "\n",
                    ",",
                    ".",
                    " ",
                    "#",
                    "actuator",
                    "geometry",
                    "lx",
                    "ribs",
                    "list",
                    "kind",
                    "gripper",
                    "grasp",
                    "load",
                    "fx",
                    "1",
                    "-2.5e3",
                    "nan",
                    "inf",
                    "true",
                    "\"paper\"",
                    "\"sphere\"",
                    "x0",
                    "partition",
                    "lengths",
                    "\"\"\"",
                    "'''",
                ]),
                0..80,
            )
            .prop_map(|v| v.concat());
            runner(300)
                .run(&tokenish, |text| {
                    read(&text);
                    Ok(())
                })
                .unwrap();
        });
    }

    #[test]
    fn mutated_examples_never_panic_or_hang() {
        within(Duration::from_secs(120), || {
            let strategy = (0..EXAMPLES.len(), prop::collection::vec(edit(), 1..12));
            runner(400)
                .run(&strategy, |(k, edits)| {
                    read(&apply(EXAMPLES[k], &edits));
                    Ok(())
                })
                .unwrap();
        });
    }
}

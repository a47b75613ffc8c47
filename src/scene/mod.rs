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
//! [model]                      # name = "ccm": the element model (crate::ModelId)
//! name = "ccm"
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
//! [actuator.laminate]         # shear_correction, plane_strain
//! [actuator.cl_ribs]           # list = [{ x0, x1, width, height }, ...] (mm; default none)
//! [partition]                  # elements = N | "auto" | lengths = [...] | tip_tol_mm (+ elements to start)
//! elements = 8
//! [load]                       # pressure_kpa, kappa, fx, fz (N, finger frame)
//! [solve]                      # rtol, max_iter, strategy, samples_per_element, shape, stability, continuation, max_step
//! [gripper]                    # mounting_angle_deg, overlap_mm | palm_mm, fingers, mu, strict
//! [gripper.grasp]              # kind = "size" | "cuboid" | "sphere", with its keys
//! ```
//!
//! `[model] name` picks the element model ([`crate::ModelId::from_name`];
//! default the paper's, `"ccm"`). `partition.tip_tol_mm` refines with the
//! default model only.
//!
//! A grasp's validity is the gripper's (`crate::gripper::rules`): a grasp
//! that bends an element backwards is flagged (`curvature_reversal`), and
//! with `[gripper] strict = true` it is invalid too.
//!
//! `[partition] elements = "auto"` asks for the automatic partition
//! ([`crate::Plan::Auto`]): element boundaries on the material changes,
//! and elements split until every one turns within the CCM's slope limit.
//! A finger scene chooses it at its load; a gripper scene at the unloaded,
//! zero-pressure state, and builds the gripper on it (a grasp far from
//! rest may still find elements beyond the limit). The number of elements
//! used is [`SceneSolution::elements`]. `partition.lengths` holds at most
//! 1000 entries (1 / [`crate::partition::MIN_ELEMENT_FRACTION`]) and
//! `solve.samples_per_element` is at most [`crate::finger::MAX_SAMPLES_PER_ELEMENT`],
//! and at most [`crate::finger::MAX_SHAPE_POINTS`] samples in all (times the
//! elements).
//!
//! Reading is two steps: [`SceneFile::parse`] checks the TOML and its keys
//! and types ([`SceneError`] with line and column), [`SceneFile::resolve`]
//! checks the values through the library's validating constructors
//! ([`InputError`](crate::InputError) naming the key by its TOML path, e.g.
//! `actuator.geometry.h1`). [`Scene::solve`] then solves the finger or the
//! grasp.

mod covariance;
mod fields;
mod record;
mod resolve;
mod schema;
mod solve;
mod syntax;
mod text;
mod uncertainty;

#[cfg(test)]
mod fuzz;
#[cfg(test)]
mod testing;

pub use crate::sensitivity::Covariance;
pub use fields::{
    degrees, edit_distance, scene_input, scene_solve, warning_text, GraspKey, GripperKey, LoadKey,
    ModelKey, PartitionKey, SceneKey, SolveKey, ValueKind,
};
pub use record::{GraspJson, GripperJson, SolutionRecord};
pub use resolve::{
    GraspSpec, GripperScene, PartitionPlan, Scene, SceneReadError, DEFAULT_CUBOID_FRICTION_N,
    DEFAULT_ELEMENTS, DEFAULT_GRASP_SIZE_MM, DEFAULT_MOUNTING_ANGLE_DEG, DEFAULT_OVERLAP_MM,
    DEFAULT_SPHERE_BETA_DEG, DEFAULT_SPHERE_LIFT_N, DEFAULT_SPHERE_RADIUS_MM,
};
pub use schema::{
    ActuatorSection, CalibrationSection, ChannelSection, ClRibEntry, ClRibsSection, Elements,
    GeometrySection, GraspKind, GraspSection, GripperSection, LoadSection, MaterialKind,
    MaterialSection, ModelSection, PartitionSection, PemcSection, RibEntry, RibKind, RibsSection,
    SceneFile, SceneStrategy, SolveSection, CALIBRATION_SD_TOLERANCE, MAX_CALIBRATION_KEYS,
    MAX_CALIBRATION_SD,
};
pub use solve::{GraspOutcome, SceneSolution};
pub(crate) use syntax::key_at;
pub use syntax::{line_col, locate, SceneError};
pub use text::{read_scene_text, read_text, TextFileError, MAX_SCENE_BYTES};
pub use uncertainty::{GraspUncertainty, Uncertainty};

//! fpc: the chained composite model (CCM) of fluidic prestressed composite
//! fingers, and the analysis of soft grippers built from them.
//!
//! The element models are generated at build time from the specs in
//! `energy-spec/` by the in-house symbolic crate; see [`model`].
//!
//! ```
//! use fpc::{Finger, Load, SolveOptions};
//!
//! // the paper's actuator at prestrain 0.25, eight equal elements
//! let finger = Finger::paper(0.25, 8)?;
//! let unloaded = finger.solve(&Load::unloaded(), &SolveOptions::default())?;
//! assert!(unloaded.tip[1] < 0.0); // curls towards the prestressed side
//!
//! // 50 kPa and a tip force (N, finger frame)
//! let load = Load::unloaded().with_pressure_kpa(50.0).with_tip_force(0.5, 0.2);
//! let loaded = finger.solve(&load, &SolveOptions::default())?;
//! assert!(loaded.report.residual_norm <= 1e-10);
//! assert_eq!(loaded.stable, Some(true)); // no negative Hessian eigenvalue
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod actuator;
mod brent;
mod circle_fit;
mod coefficients;
pub mod design;
mod element;
mod error;
mod finger;
pub mod model;
mod partition;
mod plan;
mod sensitivity;
mod solve_error;
mod validity;

pub use actuator::{
    Actuator, ActuatorParam, ActuatorParams, Channel, Elastic, Geometry, Isotropic, Lamina, Layer,
    Material, Orthotropic, PlaneStress, Prestressed, PsiLaw, Rib, RibLayout, EPS0_FIT_RANGE,
    MAX_GENERATED_RIBS,
};
pub use circle_fit::{fit_circle, Circle};
pub use coefficients::Coefficients;
pub use error::{InputError, StripDimension, Warning};
pub use finger::{
    input_warnings, Affine2, Finger, Fold, Load, LoadPath, LoadPathSpec, LoadPoint, PolyCurve,
    Problem, Solution, SolveOptions, SolveReport, Solver, Strategy, TargetFold, TargetProblem,
    Traced, MAX_SAMPLES_PER_ELEMENT, VACUUM_GAUGE_MPA,
};
pub use fpc_newton::{PathTermination, Termination};
pub use model::{ElementModel, ModelId, ModelInfo, ModelVisitor};
pub use partition::{Partition, LENGTH_SUM_TOLERANCE, MIN_ELEMENT_FRACTION};
pub use plan::refine::{
    Level, PartitionKind, Refinement, RefinementRecord, INTERMEDIATE_ELEMENTS, INTERMEDIATE_RTOL,
    MAX_AUTO_ELEMENTS, MAX_REFINED_ELEMENTS,
};
pub use plan::{FingerBuilder, Plan, PlannedFinger, Solved, DEFAULT_PLAN_ELEMENTS};
pub use sensitivity::{
    EnvelopeSensitivities, EnvelopeSensitivity, GeometrySensitivity, GraspKind, GraspSensitivities,
    GraspSensitivity, GripperParam, Param, Sensitivities, Sensitivity, SizeSensitivity,
    ENVELOPE_STATIONARITY, EQUILIBRIUM_TOLERANCE, TARGET_TOLERANCE,
};
pub use solve_error::SolveError;
pub use validity::{
    CONTACT_SPACING, MAX_CONTACT_SAMPLES, MIDPLANE_STRAIN_LIMIT, PRESTRESSED_STRAIN_RANGE,
    SLOPE_LIMIT_DEG, THICKNESS_TO_LENGTH_LIMIT, THICKNESS_TO_WIDTH_LIMIT,
};
pub mod gripper;
pub mod report;
pub mod studies;
pub use gripper::{
    contact_force_to_finger, contact_force_to_gripper, design_space,
    finger_displacement_to_gripper, finger_point_to_gripper, grasping_angle_range,
    gripper_force_to_contact, gripper_force_to_finger, lifting_force, AngleSample, Grasp, Gripper,
    GripperParams, Invalid, PalmSpec, PathRecord, SphereContact, SphereGrasp, SphereLift,
    Stability, Verdict, ViableAngles, GRIPPER_SAMPLES_PER_ELEMENT,
};
pub use studies::{
    run_all, section5_gripper, study1_prestrain_angle, study2_overlap, study3_cuboid_region,
    study4_force_control, study5_sphere_region, study6_viable_angles, study7_curvature,
    study8_force_at_displacement, tip_force_for_displacement, Axis, CuboidRegion, CurvatureCurve,
    CurvatureRow, DisplacementForce, DisplacementForceRow, ForceControl, ForceControlRow,
    LiftCurve, LiftPoint, SpherePoint, SphereRegion, Studies, StudyInfo, StudyOptions, StudyOutput,
    SweepStop, PAPER_ANGLES, PAPER_EPS0, PAPER_OVERLAPS, STUDIES, STUDY8_PRESSURES_KPA,
};
pub mod scene;
pub use scene::{
    GraspOutcome, GraspSpec, GripperScene, PartitionPlan, Scene, SceneError, SceneFile,
    SceneReadError, SceneSolution,
};

/// The README's Rust examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

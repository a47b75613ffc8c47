//! The soft gripper built from identical, synchronised fingers (docs/model.md
//! section 5): the geometry fixed by the unloaded finger, grasp measures and
//! direct target solves.
//!
//! - `setup.rs`: the design ([`GripperParams`]), the reference state and
//!   the geometry it fixes ([`Gripper`]), a grasp's record ([`Grasp`]);
//! - [`frames`]: transforms between the finger and gripper frames, contact
//!   forces;
//! - [`contact`]: where the finger's mid-plane meets an object;
//! - `closing.rs`: closing on an object along the target path, the verdict,
//!   the size and force-control solves;
//! - `tail.rs`: size sweeps run to their end;
//! - [`rules`]: when a grasp is valid;
//! - [`sphere`]: spheres touching the tip, the best lifting force and the
//!   viable grasping angles.
//!
//! Grasps. Every grasp here is the equilibrium the gripper reaches closing
//! on the object from rest: the tip load is affine in one unknown `lambda`
//! (the normal force, or a horizontal force), the target fixes the tip's
//! Xg, and the target is traced from the rest state at the grasp's
//! pressure (`lambda = 0`) to its value ([`Solver::trace_target`](crate::finger::Solver::trace_target)), each
//! step a bordered solve that must stay on the curve. A target beyond a
//! fold of that path is refused ([`SolveError::NotOnPath`](crate::SolveError::NotOnPath)) rather than
//! answered from another branch. A warm solve continues the path of a
//! previous [`Grasp`] of the same load family (a sweep's previous point).

mod closing;
pub mod contact;
mod envelope;
pub mod frames;
pub mod rules;
mod setup;
pub mod sphere;
mod tail;

pub(crate) use closing::for_target;
pub(crate) use setup::Object;
pub use setup::{
    Grasp, Gripper, GripperParams, PalmSpec, CONTACT_TOL_MM, GRIPPER_SAMPLES_PER_ELEMENT,
    MAX_FINGERS,
};

pub(crate) use envelope::EnvelopeSeed;
pub use envelope::{EnvelopeCounts, SphereEnvelope};
pub use frames::{
    contact_force_to_finger, contact_force_to_gripper, design_space,
    finger_displacement_to_gripper, finger_point_to_gripper, grasping_angle_range,
    gripper_force_to_contact, gripper_force_to_finger, lifting_force,
};
pub use rules::{Invalid, PathRecord, Stability, Verdict};
pub use sphere::{AngleSample, SphereContact, SphereGrasp, SphereLift, ViableAngles};
pub use tail::{SizeTail, SweepEnd, MAX_GRASP_FORCE_N};

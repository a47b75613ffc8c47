//! fpc: the chained composite model (CCM) of fluidic prestressed composite
//! (FPC) fingers, and the analysis of soft grippers built from them: how a
//! finger bends under pressure and tip loads, which objects a gripper of
//! such fingers holds, with which forces, and which gripper to build.
//!
//! The model is stated in `docs/model.md` (its source of truth; section
//! numbers below refer to it). Units everywhere: millimetres, newtons,
//! N/mm^2 = MPa for moduli, and radians; the scene files and the CLI take
//! pressures in kPa and angles in degrees, the library converts once.
//!
//! # How the pieces fit
//!
//! - An [`Actuator`] is the laminate: geometry, layers, channel, ribs and
//!   the prestrain (`fpc::actuator` holds its parts).
//! - A [`Finger`] is an actuator on a [`Partition`] into elements, solved by
//!   Newton on generated element kernels ([`model`]; section 3): a
//!   [`Load`] (pressure, tip force) and [`SolveOptions`] give a
//!   [`Solution`] (coefficients, tip, mid-plane samples, stability, the
//!   [`Warning`]s that say where the answer leaves the model).
//! - The front door for a finger is [`PlannedFinger`]: an actuator with a
//!   solve [`Plan`] (fixed elements, automatic partition, a tip tolerance,
//!   refinement levels), built once by a [`FingerBuilder`] and solved by
//!   one method into one result, [`Solved`] ([`plan`]).
//! - A [`Gripper`] is a finger mounted on a palm ([`GripperParams`],
//!   [`PalmSpec`]); its grasps ([`Grasp`], [`GraspSpec`]) are the equilibria
//!   reached by closing the gripper on the object from rest, each with one
//!   [`Verdict`] (the paper's rules, the model's limits, stability, the
//!   path; section 5).
//! - A [`Scene`] is a TOML file's finger or gripper, solved into a
//!   [`SceneSolution`] ([`scene`]); [`studies`] runs the paper's eight
//!   studies ([`StudyOptions`]); [`design`] searches for the gripper that
//!   holds a set of objects; [`sensitivity`] gives exact derivatives of
//!   every answer; [`report`] is the data model of every table and figure.
//! - [`measure`] reads measurements of real fingers (a manifest of
//!   specimens with marker, radius and force tests in CSV files), and
//!   [`compare`] holds the model against them with no fitting
//!   (docs/measurements.md).
//! - Bad input is an [`InputError`] naming the field; a failed solve a
//!   [`SolveError`] saying why. Nothing panics on user input.
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
//!
//! The element models are generated at build time from the specs in
//! `energy-spec/` by the in-house symbolic crate; see [`model`].

pub mod actuator;
mod brent;
pub mod calibrate;
pub mod cancel;
pub mod circle_fit;
mod coefficients;
pub mod design;
mod element;
pub mod error;
pub mod field;
pub mod finger;
pub mod gripper;
pub mod lanes;
pub mod measure;
pub mod model;
pub mod num;
pub mod partition;
pub mod plan;
mod progress;
pub mod report;
pub mod scene;
pub mod sensitivity;
mod solve_error;
pub mod studies;
pub mod validity;

pub use actuator::{Actuator, ActuatorParams};
pub use coefficients::Coefficients;
pub use error::{InputError, Warning};
pub use field::Field;
pub use finger::{Finger, Load, Solution, SolveOptions};
pub use fpc_newton::Termination;
pub use gripper::{Grasp, Gripper, GripperParams, PalmSpec, Verdict};
pub use measure::compare;
pub use model::ModelId;
pub use partition::Partition;
pub use plan::{FingerBuilder, Plan, PlannedFinger, Solved};
pub use scene::{GraspSpec, Scene, SceneSolution};
pub use solve_error::SolveError;
pub use studies::StudyOptions;

/// The README's Rust examples, compiled and run as doctests.
#[cfg(doctest)]
#[doc = include_str!("../README.md")]
struct ReadmeDoctests;

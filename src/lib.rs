//! fpc: the chained composite model (CCM) of fluidic prestressed composite
//! fingers, and the analysis of soft grippers built from them.
//!
//! The element energy kernels are generated at build time from
//! `energy-spec/ccm.spec` by the in-house symbolic crate; see [`kernels`].

mod actuator;
mod blocks;
mod element;
mod error;
mod finger;
mod fit;
pub mod kernels;

pub use actuator::{
    Actuator, ActuatorParams, Channel, Geometry, Isotropic, Layer, Material, Orthotropic,
    PlaneStress, Prestressed, PsiLaw, Rib, RibLayout, EPS0_FIT_RANGE, MAX_GENERATED_RIBS,
};
pub use blocks::{
    distinct_elements, element_blocks, ElementBlocks, GasBlock, LinearBlock, Partition,
    PrestressedBlock, LENGTH_SUM_TOLERANCE, MIN_ELEMENT_FRACTION,
};
pub use element::{Coeffs, Element, UpperHessian};
pub use error::{InputError, SolveError, Warning};
pub use finger::{Finger, Load, Solution, SolveOptions, SolveReport, Solver, Strategy};
pub use fit::{fit_circle, Circle};
pub use fpc_newton::Termination;

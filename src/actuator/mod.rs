//! The actuator: laminate materials, dimensions, channel and ribs
//! (docs/model.md section 3), with the paper's defaults, and their validation.
//!
//! [`ActuatorParams`] is plain data anyone can edit; [`Actuator::new`]
//! checks it once and returns an [`Actuator`] whose content can no longer
//! change (private fields, read through getters). Units: mm, MPa.
//!
//! The z coordinate is measured from the laminate's mid-plane, +Z towards
//! the constraining layer. Top to bottom:
//!
//! | lamina | z range |
//! |---|---|
//! | constraining layer (CL) | [h1, H/2] |
//! | regular EMC | [h2, h1] |
//! | fluidic layer (FL), with the channel z in [-h3b, h3a] | [-h3, h2] |
//! | prestressed EMC (PEMC) | [-H/2, -h3] |
//!
//! - `laminate.rs`: materials, the prestressed law, dimensions, channel,
//!   ribs (in the channel and on the constraining layer) and the validated [`Actuator`];
//! - `param.rs`: the actuator's parameters by their scene keys;
//! - `blocks.rs`: the actuator cut into integration blocks per element, and
//!   the partition on its material changes;
//! - `tangent.rs`: the tangent of the actuator and of its blocks along one
//!   parameter (the design sensitivities' right-hand sides).

mod blocks;
mod laminate;
mod material;
mod param;
mod tangent;

pub use crate::element::ElementBlocks;
pub use crate::field::{ClRibKey, Elastic, Lamina, ShearLayer};
pub use blocks::element_blocks;
pub use laminate::{
    Actuator, ActuatorParams, Channel, ClRib, Geometry, Layer, Rib, RibLayout, EPS0_FIT_RANGE,
    EPS0_RANGE, MAX_CL_RIBS, MAX_DIMENSION_MM, MAX_GENERATED_RIBS, MAX_LISTED_RIBS,
};
pub use material::{
    Isotropic, Material, Orthotropic, PlaneStress, Prestressed, PsiLaw, TransverseShear,
    MODULUS_RANGE_MPA,
};
pub use param::ActuatorParam;
pub(crate) use tangent::{element_block_tangent_into, ActuatorTangent};

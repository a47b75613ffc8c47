//! The design variables `x = (eps0, mounting angle in degrees, overlap in
//! mm)`: the gripper a design builds, the variables as gripper
//! parameters, and a margin's gradient over them.

use crate::actuator::{Actuator, ActuatorParam};
use crate::finger::Finger;
use crate::gripper::{Gripper, GripperParams, PalmSpec};
use crate::partition::Partition;
use crate::sensitivity::GripperParam;
use crate::solve_error::SolveError;

use super::requirements::Requirements;

/// The actuator of a design with prestrain `eps0`: the base scene's, else
/// the paper's.
pub(super) fn actuator(req: &Requirements, eps0: f64) -> Result<Actuator, crate::InputError> {
    match &req.base {
        Some(b) => b.actuator.with_eps0(eps0),
        None => Actuator::paper(eps0),
    }
}

/// The gripper of a design.
pub fn gripper(req: &Requirements, x: [f64; 3]) -> Result<Gripper, SolveError> {
    let act = actuator(req, x[0])?;
    let part = Partition::equal(act.geometry().lx, req.elements)?;
    let model = req.base.as_ref().map(|b| b.model).unwrap_or_default();
    Gripper::new(
        Finger::with_model(model, &act, &part, true),
        GripperParams {
            mounting_angle: x[1].to_radians(),
            geometry: PalmSpec::Overlap(x[2]),
            fingers: req.fingers,
            mu: req.mu,
            strict: req.strict,
        },
    )
}

/// d margin / d (eps0, mounting angle in degrees, overlap in mm) of one
/// margin, from the exact sensitivities of the gripper's outputs
/// (`Gripper::geometry_sensitivities`, `grasp_sensitivities`,
/// `size_sensitivities`, `max_sphere_lift_sensitivities`); `None` where
/// they do not cover the margin (the caller falls back to central
/// differences for that variable).
pub(crate) type MarginGradient = [Option<f64>; 3];

/// The design variables as gripper parameters.
pub(super) const DESIGN_PARAMS: [GripperParam; 3] = [
    GripperParam::Actuator(ActuatorParam::Eps0),
    GripperParam::MountingAngle,
    GripperParam::Overlap,
];

/// A gradient over [`DESIGN_PARAMS`] (per rad of the angle) as one over the
/// design variables (per degree), scaled by `factor`.
pub(super) fn design_gradient(rows: [f64; 3], factor: f64) -> MarginGradient {
    let per = [1.0, std::f64::consts::PI / 180.0, 1.0];
    let mut g = [None; 3];
    for i in 0..3 {
        let v = rows[i] * per[i] * factor;
        g[i] = v.is_finite().then_some(v);
    }
    g
}

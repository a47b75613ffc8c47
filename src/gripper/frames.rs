//! Frames and contact forces of the gripper (docs/model.md section 5):
//! pure functions, no state.
//!
//! The gripper frame (Xg, Zg) has its origin at the palm centre, Xg out
//! towards this finger's root and Zg down. The finger's root sits at
//! `(l/2, 0)`, its X axis is `(cos a, sin a)` and its Z axis
//! `(sin a, -cos a)`. The object pushes on the tip with a normal force `F`
//! along `n = (cos b, sin b)` and friction `f` along `t = (-sin b, cos b)`.

use std::f64::consts::FRAC_PI_2;

use crate::error::{finite, InputError};
use crate::field::Field;
use crate::finger::Affine2;

/// A finger-frame point `(X, Z)` in the gripper frame, for mounting angle
/// `a` and palm diameter `palm`: `Xg = l/2 + X cos a + Z sin a`,
/// `Zg = X sin a - Z cos a`.
pub fn finger_point_to_gripper(p: [f64; 2], a: f64, palm: f64) -> [f64; 2] {
    let (s, c) = a.sin_cos();
    [0.5 * palm + p[0] * c + p[1] * s, p[0] * s - p[1] * c]
}

/// The map of (M15) from the finger frame to the gripper frame for
/// mounting angle `a` and palm diameter `palm`, as an affine map (for
/// [`PolyCurve::map`](crate::finger::PolyCurve::map): the mid-plane curves in the
/// gripper frame); point by point the same as [`finger_point_to_gripper`].
pub fn finger_to_gripper_map(a: f64, palm: f64) -> Result<Affine2, InputError> {
    finite(Field::key("mounting_angle"), a)?;
    finite(Field::key("palm"), palm)?;
    let (s, c) = a.sin_cos();
    Affine2::new([[c, s], [s, -c]], [0.5 * palm, 0.0])
}

/// A finger-frame displacement `(dX, dZ)` in the gripper frame (Eq. 25):
/// `dXg = cos a dX + sin a dZ`, `dZg = sin a dX - cos a dZ`.
pub fn finger_displacement_to_gripper(d: [f64; 2], a: f64) -> [f64; 2] {
    let (s, c) = a.sin_cos();
    [c * d[0] + s * d[1], s * d[0] - c * d[1]]
}

/// A gripper-frame force `(F_Xg, F_Zg)` in the finger frame (the inverse
/// of [`finger_displacement_to_gripper`], which is its own inverse).
pub fn gripper_force_to_finger(force: [f64; 2], a: f64) -> [f64; 2] {
    finger_displacement_to_gripper(force, a)
}

/// The contact force on the finger in the gripper frame: `F n + f t` with
/// `n = (cos b, sin b)`, `t = (-sin b, cos b)`.
pub fn contact_force_to_gripper(normal: f64, friction: f64, beta: f64) -> [f64; 2] {
    let (s, c) = beta.sin_cos();
    [normal * c - friction * s, normal * s + friction * c]
}

/// Normal force `F` and friction `f` of a gripper-frame contact force at
/// grasping angle `beta` (the inverse of [`contact_force_to_gripper`]).
pub fn gripper_force_to_contact(force: [f64; 2], beta: f64) -> (f64, f64) {
    let (s, c) = beta.sin_cos();
    (force[0] * c + force[1] * s, -force[0] * s + force[1] * c)
}

/// The tip load `(F_x, F_z)` in the finger frame of a contact with normal
/// force `F`, friction `f`, grasping angle `b`, mounting angle `a`
/// (docs/model.md section 5, decision D3):
/// `F_x = F cos(a - b) + f sin(a - b)`, `F_z = F sin(a - b) - f cos(a - b)`.
pub fn contact_force_to_finger(normal: f64, friction: f64, beta: f64, a: f64) -> [f64; 2] {
    let (s, c) = (a - beta).sin_cos();
    [normal * c + friction * s, normal * s - friction * c]
}

/// Vertical lifting force of one finger, `f_v = f cos b + F sin b`.
pub fn lifting_force(normal: f64, friction: f64, beta: f64) -> f64 {
    let (s, c) = beta.sin_cos();
    friction * c + normal * s
}

/// The design space of mounting angles, `[arccot mu, pi/2]`.
pub fn design_space(mu: f64) -> [f64; 2] {
    [(1.0 / mu).atan(), FRAC_PI_2]
}

/// The range of grasping angles with a non-negative lifting force for
/// `f <= mu F`: `[-arctan mu, pi/2]`.
pub fn grasping_angle_range(mu: f64) -> [f64; 2] {
    [-mu.atan(), FRAC_PI_2]
}

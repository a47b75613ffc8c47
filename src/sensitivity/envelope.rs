//! The sensitivities of the best lifting force of a sphere, `f_v^max(r) =
//! max_b f_v(r, b)` ([`Gripper::max_sphere_lift`]): by the envelope
//! theorem at an interior optimum, along the second-contact boundary
//! otherwise (docs/model.md, "Sensitivities").

use crate::actuator::Actuator;
use crate::coefficients::Coefficients;
use crate::field::Field;
use crate::gripper::{Grasp, Gripper, SphereLift, CONTACT_TOL_MM};
use crate::solve_error::SolveError;

use super::gripper::{inconsistent, GraspKind, GraspSensitivities, GripperParam};

/// Largest `|d f_v / d b|` at the best grasping angle, relative to the
/// lift (per rad), for the envelope theorem to apply
/// ([`Gripper::max_sphere_lift_sensitivities`]).
pub const ENVELOPE_STATIONARITY: f64 = 1e-5;

/// How close (mm) the deepest mid-plane point must be to the contact
/// tolerance for the best angle to count as lying on the second-contact
/// boundary: the angle is located to 1e-9 rad, and the depth moves by at
/// most a few hundred mm per rad.
const BOUNDARY_DEPTH_MM: f64 = 1e-6;

/// How close (as the cosine `n . t`) the tip's tangent must be to the
/// sphere's surface for the best angle to count as lying on the tip's
/// boundary (the angle is located to 1e-9 rad).
const BOUNDARY_TANGENT: f64 = 1e-6;

/// One parameter's derivative of the best lifting force of a sphere.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EnvelopeSensitivity {
    /// The parameter.
    pub param: GripperParam,
    /// Its value.
    pub value: f64,
    /// d f_v^max / dp (N per unit).
    #[serde(rename = "lift_n")]
    pub lift: f64,
    /// d F / dp at the best angle held fixed (N per unit).
    #[serde(rename = "normal_force_n")]
    pub normal: f64,
}

/// The sensitivities of the best lifting force of a sphere
/// ([`Gripper::max_sphere_lift_sensitivities`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct EnvelopeSensitivities {
    /// The best grasping angle (rad).
    #[serde(rename = "beta_rad")]
    pub beta: f64,
    /// The best lifting force (N), re-solved at that angle.
    #[serde(rename = "lift_n")]
    pub lift: f64,
    /// d f_v / d b at that angle (N per rad): about 0 at an interior optimum.
    #[serde(rename = "d_lift_d_beta")]
    pub d_lift_d_beta: f64,
    /// True when the best angle lies on the second-contact boundary (the
    /// sphere touches the finger a second time just beyond it), so that
    /// the angle moves with the parameters along that boundary.
    pub boundary: bool,
    /// One row per parameter.
    pub rows: Vec<EnvelopeSensitivity>,
}

impl EnvelopeSensitivities {
    /// The row of a parameter.
    pub fn get(&self, param: GripperParam) -> Option<&EnvelopeSensitivity> {
        self.rows.iter().find(|r| r.param == param)
    }
}

impl Gripper {
    /// The derivatives of the best lifting force of a sphere
    /// ([`Gripper::max_sphere_lift`] returned `best` at `pressure_kpa`)
    /// with respect to `params`. The grasp at the best angle `b*` is
    /// re-solved (one target solve, checked against `best.lift`) and
    /// differentiated at fixed `b*`:
    ///
    /// - at an interior optimum (`|d f_v / d b|` within
    ///   [`ENVELOPE_STATIONARITY`] of the lift per rad) the lift is
    ///   stationary in `b`, so `d f_v^max / dp` is that partial derivative
    ///   (the envelope theorem);
    /// - on the second-contact boundary (the usual case: the lift grows
    ///   with `b` until the sphere touches the finger a second time) the
    ///   angle moves with the boundary `phi(b, p) = 0`, `phi` the deepest
    ///   mid-plane sample's depth in the sphere less the tolerance, and
    ///   `d f_v^max / dp = f_p - f_b phi_p / phi_b`. The sample's
    ///   derivative along dK/dp is a Richardson directional difference of
    ///   the explicit shape map (no re-solve); the rest is exact. The
    ///   envelope is smooth only while the same sample meets the sphere
    ///   first.
    ///
    /// A maximum on another boundary is an error. [`GripperParam::Beta`]
    /// and [`GripperParam::Size`] are not parameters here.
    pub fn max_sphere_lift_sensitivities(
        &self,
        actuator: &Actuator,
        pressure_kpa: f64,
        best: &SphereLift,
        params: &[GripperParam],
    ) -> Result<EnvelopeSensitivities, SolveError> {
        for &p in params {
            if matches!(p, GripperParam::Beta | GripperParam::Size) {
                return Err(inconsistent(
                    p.name(),
                    "is not a parameter of the best lifting force (the angle is optimised out; the size belongs to cuboid grasps)".into(),
                ));
            }
        }
        let sg = self.sphere_grasp_at_friction_limit(pressure_kpa, best.radius, best.beta, None)?;
        let lift = sg.grasp.lift;
        if (lift - best.lift).abs() > 1e-6 * (lift.abs().max(best.lift.abs()) + 1e-9) {
            return Err(inconsistent(
                Field::key("best"),
                format!(
                    "is not this gripper's best lift at {} kPa: the grasp re-solved at its angle lifts {lift:.9} N, not {:.9} N",
                    pressure_kpa, best.lift
                ),
            ));
        }
        let mut all = params.to_vec();
        all.push(GripperParam::Beta);
        let kind = GraspKind::SphereAtFrictionLimit {
            radius: best.radius,
        };
        let (gs, dks) = self.grasp_chain(actuator, &sg.grasp, kind, &all)?;
        let nb = params.len();
        let fb = &gs.rows[nb];
        let d_lift_d_beta = fb.lift;
        let interior = d_lift_d_beta.abs() <= ENVELOPE_STATIONARITY * lift.abs().max(1e-9);
        // at a boundary: the constraint phi(b, p) = 0 that holds the
        // angle, d b*/dp = -phi_p / phi_b
        let db = if interior {
            vec![0.0; nb]
        } else {
            let phi = self.second_contact_derivatives(actuator, &all, &sg.grasp, &gs, &dks)?;
            let phi_b = phi[nb];
            if phi_b == 0.0 || !phi_b.is_finite() {
                return Err(inconsistent(
                    Field::key("best"),
                    "lies on the second-contact boundary, but the contact depth does not move with the angle there".into(),
                ));
            }
            phi[..nb].iter().map(|p| -p / phi_b).collect()
        };
        let rows = gs
            .rows
            .iter()
            .take(nb)
            .zip(&db)
            .map(|(r, db)| EnvelopeSensitivity {
                param: r.param,
                value: r.value,
                lift: r.lift + d_lift_d_beta * db,
                normal: r.normal + fb.normal * db,
            })
            .collect();
        Ok(EnvelopeSensitivities {
            beta: best.beta,
            lift,
            d_lift_d_beta,
            boundary: !interior,
            rows,
        })
    }

    /// At a sphere grasp whose best angle lies on the contact boundary: the
    /// derivatives, one per row of `gs` (with `dks`, the rows' dK/dp), of the
    /// function `phi` that holds the angle there, `phi <= 0` on the valid
    /// side ([`Gripper::sphere_contact`]). Two boundaries can hold it, and
    /// the one whose zero is nearest in `b` is taken:
    ///
    /// - the finger reaching its tip from inside the sphere: `phi = n . t`,
    ///   the outward normal at the contact against the tip's tangent,
    ///   `cos(a - theta - b)` with `theta` the finger's end angle;
    /// - a second contact: `phi = depth(q) - CONTACT_TOL_MM` at the point
    ///   `q` of the continuous mid-plane that reaches deepest into the
    ///   sphere apart from the tip's own contact. By the envelope theorem
    ///   the point's own motion along the curve does not count: it is
    ///   differentiated at its fixed element and coordinate.
    ///
    /// The end angle's and the point's derivatives along dK/dp are
    /// directional differences of the explicit maps (Richardson, no
    /// re-solve). An error when neither function is at its zero (the
    /// maximum lies on another boundary).
    fn second_contact_derivatives(
        &self,
        actuator: &Actuator,
        params: &[GripperParam],
        grasp: &Grasp,
        gs: &GraspSensitivities,
        dks: &[Vec<f64>],
    ) -> Result<Vec<f64>, SolveError> {
        let a = self.mounting_angle();
        let (s, c) = a.sin_cos();
        let b = grasp.beta;
        let (sb, cb) = b.sin_cos();
        let sol = &grasp.solution;
        let finger = self.finger();
        let tip = self.to_gripper(sol.tip);
        let r_s = tip[0] / cb;
        let center = [tip[0] - r_s * cb, tip[1] - r_s * sb];
        let tol = CONTACT_TOL_MM;
        let geos = self.geometry_derivatives(actuator, params)?;
        let k = sol.coefficients.as_slice();
        let kmax = k.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
        // d f(K)/dp along dK/dp for an explicit map f of the state:
        // Richardson-extrapolated central differences
        let along = |dk: &[f64], f: &dyn Fn(&Coefficients) -> Result<[f64; 2], SolveError>| {
            let dmax = dk.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            if dmax == 0.0 {
                return Ok([0.0, 0.0]);
            }
            let t = 1e-4 * kmax / dmax;
            let at = |h: f64| -> Result<[f64; 2], SolveError> {
                let kk: Vec<f64> = k.iter().zip(dk).map(|(k, d)| k + h * d).collect();
                f(&Coefficients::new(sol.coefficients.per_element(), kk)?)
            };
            let (a1, b1) = (at(t)?, at(-t)?);
            let (a2, b2) = (at(0.5 * t)?, at(-0.5 * t)?);
            let mut d = [0.0; 2];
            for m in 0..2 {
                let d1 = (a1[m] - b1[m]) / (2.0 * t);
                let d2 = (a2[m] - b2[m]) / t;
                d[m] = (4.0 * d2 - d1) / 3.0;
            }
            Ok::<[f64; 2], SolveError>(d)
        };
        let is_beta = |row: &crate::sensitivity::GraspSensitivity| {
            f64::from(u8::from(row.param == GripperParam::Beta))
        };
        // the tip's tangent against the outward normal
        let psi = a - sol.end_angle - b;
        let phi_tip = psi.cos();
        let mut tip_rows = Vec::with_capacity(gs.rows.len());
        for ((row, dk), geo) in gs.rows.iter().zip(dks).zip(&geos) {
            let dtheta = along(dk, &|kk| Ok([finger.tip(kk)?.1, 0.0]))?[0];
            tip_rows.push(-psi.sin() * (geo.da - dtheta - is_beta(row)));
        }
        // the deepest point apart from the tip's own contact
        let curves = finger.midplane_curves(&sol.coefficients)?;
        let last = curves.len() - 1;
        let map = crate::gripper::frames::finger_to_gripper_map(a, self.palm())?;
        let mapped: Vec<_> = curves.iter().map(|k| k.map(map)).collect();
        let disc = crate::gripper::contact::Obstacle::disc(center, r_s)?;
        let lx_last = mapped[last].length();
        let deep = crate::gripper::contact::deepest_apart_from(&mapped, &disc, last, lx_last)?;
        let mut second: Option<(f64, Vec<f64>)> = None;
        if let Some(deep) = deep.filter(|d| (d.depth - tol).abs() <= BOUNDARY_DEPTH_MM) {
            let (el, xl) = (deep.element, deep.x);
            let pf = curves[el].point(xl);
            let q = self.to_gripper(pf);
            let dist = (q[0] - center[0]).hypot(q[1] - center[1]);
            let e = [(q[0] - center[0]) / dist, (q[1] - center[1]) / dist];
            let mut rows = Vec::with_capacity(gs.rows.len());
            for ((row, dk), geo) in gs.rows.iter().zip(dks).zip(&geos) {
                let da = geo.da;
                let db = is_beta(row);
                let dp = along(dk, &|kk| Ok(finger.midplane_curves(kk)?[el].point(xl)))?;
                let dq = [
                    0.5 * geo.dpalm + da * (-s * pf[0] + c * pf[1]) + c * dp[0] + s * dp[1],
                    da * (c * pf[0] + s * pf[1]) + s * dp[0] - c * dp[1],
                ];
                let dr_s = row.tip[0] / cb + tip[0] * sb * db / (cb * cb);
                let dc = [
                    row.tip[0] - dr_s * cb + r_s * sb * db,
                    row.tip[1] - dr_s * sb - r_s * cb * db,
                ];
                let d_dist = e[0] * (dq[0] - dc[0]) + e[1] * (dq[1] - dc[1]);
                rows.push(dr_s - d_dist);
            }
            second = Some((deep.depth - tol, rows));
        }
        // the boundary whose zero lies nearest in b (the last row is b's)
        let reach = |phi: f64, rows: &[f64]| (phi / rows[rows.len() - 1]).abs();
        let tip_near = phi_tip.abs() <= BOUNDARY_TANGENT;
        match (tip_near, second) {
            (true, Some((phi, rows))) if reach(phi, &rows) < reach(phi_tip, &tip_rows) => Ok(rows),
            (true, _) => Ok(tip_rows),
            (false, Some((_, rows))) => Ok(rows),
            (false, None) => Err(inconsistent(
                Field::key("best"),
                format!(
                    "lies on a validity boundary other than a contact (the tip's tangent is {:.3e} rad from the sphere's surface, and nothing else of the finger reaches it): not covered",
                    phi_tip.asin()
                ),
            )),
        }
    }
}

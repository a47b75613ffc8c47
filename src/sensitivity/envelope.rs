//! The sensitivities of the best lifting force of a sphere, `f_v^max(r) =
//! max_b f_v(r, b)` ([`Gripper::max_sphere_lift`]): by the envelope
//! theorem at an interior optimum, along the second-contact boundary
//! otherwise (docs/model.md, "Sensitivities").

use crate::actuator::Actuator;
use crate::error::SolveError;
use crate::finger::Coefficients;
use crate::gripper::{Grasp, Gripper, SphereLift, GRIPPER_SAMPLES_PER_ELEMENT};

use super::gripper::{inconsistent, GraspKind, GraspSensitivities, GripperParam};

/// Largest `|d f_v / d b|` at the best grasping angle, relative to the
/// lift (per rad), for the envelope theorem to apply
/// ([`Gripper::max_sphere_lift_sensitivities`]).
pub const ENVELOPE_STATIONARITY: f64 = 1e-5;

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
                "best",
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
                    "best",
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

    /// At a sphere grasp whose best angle lies on the second-contact
    /// boundary: the derivatives, one per row of `gs` (with `dks`, the
    /// rows' dK/dp), of `phi = depth(q) - 1e-6 (r + Lx)` at the mid-plane
    /// sample `q` that reaches deepest into the sphere, the constraint that
    /// holds the angle ([`Gripper::sphere_contact`]). The sample's
    /// finger-frame derivative along dK/dp is a directional difference of
    /// the explicit shape map (Richardson, no re-solve). An error when no
    /// sample is at the tolerance (the maximum lies on another boundary).
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
        let (sb, cb) = grasp.beta.sin_cos();
        let sol = &grasp.solution;
        let finger = self.finger();
        let per = GRIPPER_SAMPLES_PER_ELEMENT;
        let points = finger.shape(&sol.coefficients, per)?;
        let tip = self.to_gripper(sol.tip);
        let r_s = tip[0] / cb;
        let center = [tip[0] - r_s * cb, tip[1] - r_s * sb];
        let tol = 1e-6 * (r_s + self.length());
        let depth = |q: [f64; 2]| r_s - (q[0] - center[0]).hypot(q[1] - center[1]);
        // the deepest sample but the tip (which is on the sphere)
        let Some((i, d)) = points
            .iter()
            .enumerate()
            .take(points.len().saturating_sub(1))
            .map(|(i, p)| (i, depth(self.to_gripper(*p))))
            .max_by(|x, y| x.1.total_cmp(&y.1))
        else {
            return Err(inconsistent("best", "has no mid-plane samples".into()));
        };
        if (d - tol).abs().is_nan() || (d - tol).abs() > 1e-3 * tol {
            return Err(inconsistent(
                "best",
                format!(
                    "lies on a validity boundary other than a second contact (the deepest sample reaches {d:.3e} mm into the sphere, the tolerance is {tol:.3e} mm): not covered"
                ),
            ));
        }
        let pf = points[i];
        let q = self.to_gripper(pf);
        let dist = (q[0] - center[0]).hypot(q[1] - center[1]);
        let e = [(q[0] - center[0]) / dist, (q[1] - center[1]) / dist];
        let geos = self.geometry_derivatives(actuator, params)?;
        let k = sol.coefficients.as_slice();
        let kmax = k.iter().fold(0.0f64, |m, v| m.max(v.abs())).max(1e-12);
        let mut out = Vec::with_capacity(gs.rows.len());
        for ((row, dk), geo) in gs.rows.iter().zip(dks).zip(geos) {
            let da = geo.da;
            let db = f64::from(u8::from(row.param == GripperParam::Beta));
            // d(sample)/dp in the finger frame along dK/dp
            let dmax = dk.iter().fold(0.0f64, |m, v| m.max(v.abs()));
            let dp = if dmax == 0.0 {
                [0.0, 0.0]
            } else {
                let t = 1e-4 * kmax / dmax;
                let at = |h: f64| -> Result<[f64; 2], SolveError> {
                    let kk: Vec<f64> = k.iter().zip(dk).map(|(k, d)| k + h * d).collect();
                    let kk = Coefficients::new(sol.coefficients.per_element(), kk)?;
                    Ok(finger.shape(&kk, per)?[i])
                };
                let mut d1 = [0.0; 2];
                let mut d2 = [0.0; 2];
                let (a1, b1) = (at(t)?, at(-t)?);
                let (a2, b2) = (at(0.5 * t)?, at(-0.5 * t)?);
                for m in 0..2 {
                    d1[m] = (a1[m] - b1[m]) / (2.0 * t);
                    d2[m] = (a2[m] - b2[m]) / t;
                }
                [(4.0 * d2[0] - d1[0]) / 3.0, (4.0 * d2[1] - d1[1]) / 3.0]
            };
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
            out.push((1.0 - 1e-6) * dr_s - d_dist);
        }
        Ok(out)
    }
}

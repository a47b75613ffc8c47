//! Spheres held by the gripper: a sphere centred on the gripper axis
//! touching the tip, its validity, the best lifting force and the viable
//! grasping angles.
//!
//! The sphere touches the tip with its surface normal `n`, so its centre is
//! `tip - r n`; on the gripper axis (`Xg = 0`) that gives `r cos b = tip
//! Xg`, i.e. `2 r cos b` = the gap between the tips. The paper writes
//! `2 r cos b = d`; the two agree whenever the tip is the finger's
//! innermost point at rest (every `eps0 <= 0.25` finger of the paper; not
//! the `eps0 = 0.4` one, whose curl passes its innermost point). The
//! physical contact is used here, so the centre is always on the axis.

use std::f64::consts::FRAC_PI_2;

use crate::error::{finite, positive, require, InputError};
use crate::field::Field;
use crate::num::Num;

use crate::finger::{Solution, Solver};
use crate::solve_error::SolveError;

use super::closing::check_beta;
use super::frames::{contact_force_to_gripper, finger_to_gripper_map, grasping_angle_range};
use super::rules::Invalid;
use super::setup::{Grasp, GraspLoad, Gripper, Object, CONTACT_TOL_MM};

/// Tolerance (rad) on the best grasping angle of [`Gripper::max_sphere_lift`].
pub const ENVELOPE_BETA_TOL: f64 = 1e-9;

/// Tolerance (rad) on the bounds of [`Gripper::viable_angle_range`].
pub const VIABLE_BETA_TOL: f64 = 1e-9;

/// How close (rad) a best grasping angle must lie to the turn of closing
/// from rest ([`Gripper::closing_turn`]) to be taken for an edge there: a
/// search locates an edge to [`ENVELOPE_BETA_TOL`], a corrector that starts
/// from the turn to 1e-11 rad.
pub(crate) const TURN_NEAR: f64 = 1e-7;

/// Of the turns of closing from rest `zero + k pi`
/// ([`Gripper::closing_turn`]), the one nearest `near`.
pub(crate) fn nearest_turn(zero: f64, near: f64) -> f64 {
    zero + ((near - zero) / std::f64::consts::PI).round() * std::f64::consts::PI
}

/// The turn of closing from rest `zero + k pi` that lies within
/// [`TURN_NEAR`] of `beta`, if one does: `beta` is taken for an edge there.
pub(crate) fn turn_within(zero: f64, beta: f64) -> Option<f64> {
    Some(nearest_turn(zero, beta)).filter(|t| (t - beta).abs() <= TURN_NEAR)
}

/// Target solves the search for the best grasping angle may spend beyond
/// the scan.
const ENVELOPE_MAX_EVALUATIONS: usize = 60;

/// A sphere centred on the gripper axis touching the tip.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SphereContact {
    /// Radius `r = tip Xg / cos b` (mm); 0 when the fingers are not open.
    #[serde(rename = "radius_mm")]
    pub radius: f64,
    /// Centre in the gripper frame, `tip - r n` (mm).
    #[serde(rename = "center_gripper_mm")]
    pub center: [f64; 2],
    /// The first geometric violation (not open, second contact), if any.
    pub invalid: Option<Invalid>,
}

/// A sphere grasp: the sphere and the equilibrium holding it (its verdict
/// includes the sphere's contact: a second contact is one of its rules).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SphereGrasp {
    /// Radius (mm).
    #[serde(rename = "radius_mm")]
    pub radius: f64,
    /// Sphere centre in the gripper frame (mm).
    #[serde(rename = "center_gripper_mm")]
    pub center: [f64; 2],
    /// The equilibrium.
    pub grasp: Grasp,
}

impl SphereGrasp {
    /// True when the grasp is valid ([`Grasp::is_valid`]).
    pub fn is_valid(&self) -> bool {
        self.grasp.is_valid()
    }

    /// The first reason the grasp is not valid (`None`: valid).
    pub fn invalid(&self) -> Option<Invalid> {
        self.grasp.invalid()
    }
}

/// The largest lifting force that holds a sphere (full friction, best
/// grasping angle).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SphereLift {
    /// Sphere radius (mm).
    #[serde(rename = "radius_mm")]
    pub radius: f64,
    /// The grasping angle that gives it (rad).
    #[serde(rename = "beta_rad")]
    pub beta: f64,
    /// Lifting force per finger (N).
    #[serde(rename = "lift_n")]
    pub lift: f64,
    /// Normal force there (N).
    #[serde(rename = "normal_force_n")]
    pub normal: f64,
    /// An element is bent backwards there.
    pub reversed: bool,
    /// The grasp's validity findings.
    pub warnings: Vec<crate::Warning>,
}

/// One grasping angle of a [`ViableAngles`] scan.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct AngleSample {
    /// Grasping angle (rad).
    #[serde(rename = "beta_rad")]
    pub beta: f64,
    /// Normal force `F` (N); 0 when the solve failed or was skipped.
    #[serde(rename = "normal_force_n")]
    pub normal: f64,
    /// Friction `f` (N); 0 when the solve failed or was skipped.
    #[serde(rename = "friction_n")]
    pub friction: f64,
    /// True for a valid grasp with `0 <= f <= mu F`.
    pub viable: bool,
    /// Why not viable (`None` when viable, or when the solve failed).
    pub invalid: Option<Invalid>,
    /// The solve failure, if any.
    pub failure: Option<String>,
    /// An element is bent backwards (false when the solve failed).
    pub reversed: bool,
    /// The grasp's validity findings (empty when the solve failed).
    pub warnings: Vec<crate::Warning>,
}

/// The grasping angles that hold a sphere of radius `r` with lifting force
/// `f_v` per finger.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct ViableAngles {
    /// Sphere radius (mm).
    #[serde(rename = "radius_mm")]
    pub radius: f64,
    /// Lifting force per finger (N).
    #[serde(rename = "lift_n")]
    pub lift: f64,
    /// Viable intervals `[lo, hi]` (rad), boundaries refined by bisection.
    #[serde(rename = "intervals_rad")]
    pub intervals: Vec<[f64; 2]>,
    /// The scan the intervals come from.
    pub scan: Vec<AngleSample>,
}

impl ViableAngles {
    /// The hull `[lo, hi]` of the viable intervals (`None`: no viable angle).
    pub fn range(&self) -> Option<[f64; 2]> {
        let lo = self.intervals.first()?[0];
        let hi = self.intervals.last()?[1];
        Some([lo, hi])
    }
}

impl Gripper {
    /// (c) A sphere of radius `r` held with lifting force `lift` per finger
    /// at grasping angle `beta`: the tip sits at `Xg = r cos b`, the
    /// vertical force is `lift`, and the horizontal force is solved for;
    /// `F` and `f` follow. The result says whether the grasp is valid
    /// (open, `F >= 0`, `0 <= f <= mu F`, no second contact).
    pub fn sphere_grasp(
        &self,
        pressure_kpa: f64,
        r: f64,
        lift: f64,
        beta: f64,
        warm: Option<&Grasp>,
    ) -> Result<SphereGrasp, SolveError> {
        self.sphere_lifted(pressure_kpa, r, lift, beta, warm, true)
    }

    /// [`Gripper::sphere_grasp`], with the answer's mid-plane sampled or
    /// not (`shape`: a scan needs the verdict and the forces only).
    fn sphere_lifted(
        &self,
        pressure_kpa: f64,
        r: f64,
        lift: f64,
        beta: f64,
        warm: Option<&Grasp>,
        shape: bool,
    ) -> Result<SphereGrasp, SolveError> {
        self.check_sphere(r, beta)?;
        finite(Field::SphereLift, lift)?;
        let grasp = self.solve_scene(
            &GraspLoad {
                pressure_kpa,
                beta,
                base: [0.0, lift],
                direction: [1.0, 0.0],
                tip_xg: r * beta.cos(),
                target: (Field::SphereLift, lift),
                object: Object::Sphere,
                shape,
            },
            warm,
        )?;
        Ok(self.sphere_result(grasp))
    }

    /// A sphere of radius `r` held at grasping angle `beta` with full
    /// friction `f = mu F`: the tip sits at `Xg = r cos b` and the normal
    /// force is solved for; the lifting force `F (sin b + mu cos b)` is the
    /// largest this contact can carry. The result says whether the grasp
    /// is valid.
    pub fn sphere_grasp_at_friction_limit(
        &self,
        pressure_kpa: f64,
        r: f64,
        beta: f64,
        warm: Option<&Grasp>,
    ) -> Result<SphereGrasp, SolveError> {
        self.sphere_at_limit(pressure_kpa, r, beta, warm, true)
    }

    /// [`Gripper::sphere_grasp_at_friction_limit`], with the answer's
    /// mid-plane sampled or not (`shape`: a search needs the verdict and
    /// the forces only).
    pub(crate) fn sphere_at_limit(
        &self,
        pressure_kpa: f64,
        r: f64,
        beta: f64,
        warm: Option<&Grasp>,
        shape: bool,
    ) -> Result<SphereGrasp, SolveError> {
        self.check_sphere(r, beta)?;
        let grasp = self.solve_scene(&self.sphere_load(pressure_kpa, r, beta, shape), warm)?;
        Ok(self.sphere_result(grasp))
    }

    /// [`Gripper::sphere_at_limit`] without its mid-plane, solved by
    /// Newton's method from the neighbouring grasp `near` instead of traced
    /// from rest ([`Gripper::probe_scene`]: a search's probe).
    pub(crate) fn sphere_probe(
        &self,
        pressure_kpa: f64,
        r: f64,
        beta: f64,
        near: &Grasp,
    ) -> Result<SphereGrasp, SolveError> {
        self.check_sphere(r, beta)?;
        let grasp = self.probe_scene(&self.sphere_load(pressure_kpa, r, beta, false), near)?;
        Ok(self.sphere_result(grasp))
    }

    /// Where closing on a sphere from rest at `pressure_kpa` turns round:
    /// the grasping angles at which the contact force's first push (full
    /// friction) moves the tip neither towards nor away from the gripper's
    /// axis (`dT / dlambda = 0` at rest, [`Solver::target_slope_at`]), so
    /// that on one side of them the trace from rest starts away from the
    /// object. The rate is linear in the force's direction, `e0 cos b + e1
    /// sin b`, so its values at 0 and pi/2 give it at every angle; its
    /// zeros are the returned angle plus any multiple of pi. A prediction
    /// for a search, which traces the angles around it; `None` where a
    /// tangent is singular.
    pub(crate) fn closing_turn(&self, pressure_kpa: f64) -> Option<f64> {
        let rate = |beta: f64| {
            let problem = self.problem(&self.sphere_load(pressure_kpa, 1.0, beta, false));
            let rest = self
                .rest_state(&problem.base, &(Field::SphereRadius, 1.0))
                .ok()?;
            Solver::new(&self.finger)
                .target_slope_at(&problem, &rest, 0.0)
                .filter(|s| s.is_finite())
        };
        let (e0, e1) = (rate(0.0)?, rate(FRAC_PI_2)?);
        Some((-e0).atan2(e1)).filter(|b| b.is_finite())
    }

    /// The load family of a sphere of radius `r` held at angle `beta` with
    /// full friction.
    fn sphere_load(&self, pressure_kpa: f64, r: f64, beta: f64, shape: bool) -> GraspLoad {
        GraspLoad {
            pressure_kpa,
            beta,
            base: [0.0, 0.0],
            direction: contact_force_to_gripper(1.0, self.params.mu, beta),
            tip_xg: r * beta.cos(),
            target: (Field::SphereRadius, r),
            object: Object::Sphere,
            shape,
        }
    }

    fn sphere_result(&self, grasp: Grasp) -> SphereGrasp {
        let contact = self.sphere_contact(&grasp.solution, grasp.beta);
        SphereGrasp {
            radius: contact.radius,
            center: contact.center,
            grasp,
        }
    }

    /// The largest lifting force per finger that holds a sphere of radius
    /// `r` validly, over the grasping angles in `[-arctan mu, pi/2)`: a scan
    /// of `samples` angles (at least 4) with full friction, each warm-started
    /// from the previous and stopped where that branch of equilibria is
    /// lost, then Brent's method between the best valid angle's neighbours
    /// to [`ENVELOPE_BETA_TOL`] (the optimality condition d f_v / d b = 0,
    /// or the validity boundary where the maximum lies on one). `None` when
    /// no scanned angle gives a valid grasp.
    pub fn max_sphere_lift(
        &self,
        pressure_kpa: f64,
        r: f64,
        samples: usize,
    ) -> Result<Option<SphereLift>, SolveError> {
        check_scan(pressure_kpa, r, samples)?;
        let [lo, hi] = grasping_angle_range(self.params.mu);
        let mut best: Option<(SphereLift, Grasp)> = None;
        let consider = |sg: SphereGrasp, best: &mut Option<(SphereLift, Grasp)>| {
            if sg.is_valid() && best.as_ref().is_none_or(|(b, _)| sg.grasp.lift > b.lift) {
                *best = Some((
                    SphereLift {
                        radius: r,
                        beta: sg.grasp.beta,
                        lift: sg.grasp.lift,
                        normal: sg.grasp.normal,
                        reversed: sg.grasp.is_reversed(),
                        warnings: sg.grasp.warnings.clone(),
                    },
                    sg.grasp,
                ));
            }
        };
        let step = (hi - lo) / samples as f64;
        let mut warm: Option<Grasp> = None;
        for i in 0..samples {
            let beta = lo + step * i as f64;
            if self.check_sphere(r, beta).is_err() {
                // the fingers cannot reach this contact: the branch breaks here
                warm = None;
                continue;
            }
            match self.sphere_at_limit(pressure_kpa, r, beta, warm.as_ref(), false) {
                Ok(sg) => {
                    warm = Some(sg.grasp.clone());
                    consider(sg, &mut best);
                }
                // the branch followed from the lowest angle is lost (a fold
                // or a load growing without bound): stop rather than jump
                // to another branch
                Err(_) if warm.is_some() => break,
                Err(_) => {}
            }
        }
        // the optimum between the scan's neighbours: Brent's method on the
        // lift (an invalid or failed grasp counts as -inf, so a maximum on
        // a validity boundary is found as that boundary)
        if let Some((b, g)) = &best {
            let (centre, start, fb) = (b.beta, g.clone(), b.lift);
            let (a, z) = ((centre - step).max(lo), (centre + step).min(hi - 1e-9));
            let mut eval = |beta: f64| -> Result<Option<f64>, SolveError> {
                if self.check_sphere(r, beta).is_err() {
                    return Ok(None);
                }
                let Ok(sg) = self.sphere_at_limit(pressure_kpa, r, beta, Some(&start), false)
                else {
                    return Ok(None);
                };
                let lift = sg.is_valid().then_some(sg.grasp.lift);
                consider(sg, &mut best);
                Ok(lift)
            };
            crate::brent::brent_max(
                &mut eval,
                a,
                centre,
                z,
                fb,
                ENVELOPE_BETA_TOL,
                ENVELOPE_MAX_EVALUATIONS,
            )?;
        }
        Ok(best.map(|(b, _)| b))
    }

    /// The sphere centred on the gripper axis that touches the tip of
    /// `solution` with contact normal `n = (cos b, sin b)`, and its
    /// geometric validity: not open when `d <= 0` or the tip gap is not
    /// positive (or `cos b <= 0`); a second contact when the sphere reaches
    /// into the finger's mid-plane anywhere by more than
    /// [`super::CONTACT_TOL_MM`].
    pub fn sphere_contact(&self, solution: &Solution, beta: f64) -> SphereContact {
        let tip = self.to_gripper(solution.tip);
        let size = self.size_of(solution.tip);
        let tip_gap = 2.0 * tip[0];
        let open = size > 0.0 && tip_gap > 0.0 && beta.is_finite() && beta.cos() > 0.0;
        let (sphere, second) = if open {
            self.object_contact(solution, beta, Object::Sphere)
        } else {
            (None, None)
        };
        match sphere {
            Some((radius, center)) => SphereContact {
                radius,
                center,
                invalid: second,
            },
            None => SphereContact {
                radius: 0.0,
                center: tip,
                invalid: Some(Invalid::NotOpen { size, tip_gap }),
            },
        }
    }

    /// The contact function of a sphere grasp: the larger of the cosine
    /// between the finger's tangent at the tip and the sphere's outward
    /// normal there (positive: the finger reaches its tip from inside the
    /// sphere) and the depth (mm) of the deepest point of the mid-plane in
    /// the sphere apart from the tip's own contact, less
    /// [`CONTACT_TOL_MM`] (positive: a second contact). Non-positive where
    /// both contact rules hold; continuous in the grasping angle while the
    /// same point meets the sphere first. `None` where the sphere or its
    /// contact cannot be computed.
    pub(crate) fn contact_function(&self, grasp: &Grasp) -> Option<f64> {
        let sol = &grasp.solution;
        let a = self.mounting_angle();
        let tangent = (a - sol.end_angle - grasp.beta).cos();
        let (sb, cb) = grasp.beta.sin_cos();
        let tip = self.to_gripper(sol.tip);
        let r = tip[0] / cb;
        if !(r > 0.0 && r.is_finite()) {
            return None;
        }
        let map = finger_to_gripper_map(a, self.palm()).ok()?;
        let curves: Vec<_> = self
            .finger()
            .midplane_curves(&sol.coefficients)
            .ok()?
            .iter()
            .map(|k| k.map(map))
            .collect();
        let last = curves.len().checked_sub(1)?;
        let disc = super::contact::Obstacle::disc([tip[0] - r * cb, tip[1] - r * sb], r).ok()?;
        let deep =
            super::contact::deepest_apart_from(&curves, &disc, last, curves[last].length()).ok()?;
        // nothing apart from the tip: the whole finger falls away from it
        let second = deep.map_or(-r, |d| d.depth - CONTACT_TOL_MM);
        Some(tangent.max(second))
    }

    /// (c) The grasping angles in `[-arctan mu, pi/2)` at which a sphere of
    /// radius `r` is held validly with lifting force `lift` per finger
    /// (some `F` with `0 <= f <= mu F`). Scans `samples` angles (at least
    /// 4), then bisects each boundary to [`VIABLE_BETA_TOL`]. Failed solves count as
    /// not viable and are recorded in the scan.
    pub fn viable_angle_range(
        &self,
        pressure_kpa: f64,
        r: f64,
        lift: f64,
        samples: usize,
    ) -> Result<ViableAngles, SolveError> {
        finite(Field::SphereLift, lift)?;
        check_scan(pressure_kpa, r, samples)?;
        let [lo, hi] = grasping_angle_range(self.params.mu);
        let mut scan = Vec::with_capacity(samples);
        let mut grasps: Vec<Option<Grasp>> = Vec::with_capacity(samples);
        let mut warm: Option<Grasp> = None;
        for i in 0..samples {
            let beta = lo + (hi - lo) * i as f64 / samples as f64;
            let (sample, grasp) = self.angle_sample(pressure_kpa, r, lift, beta, warm.as_ref());
            if grasp.is_some() {
                warm.clone_from(&grasp);
            }
            scan.push(sample);
            grasps.push(grasp);
        }
        // b = pi/2 closes the scan: the tips meet on the axis (not open)
        let mut intervals = Vec::new();
        let mut start: Option<f64> = None;
        for i in 0..samples {
            let here = scan[i].viable;
            let prev = i > 0 && scan[i - 1].viable;
            if here && !prev {
                start = Some(if i == 0 {
                    lo
                } else {
                    let (g, b) = (scan[i].beta, scan[i - 1].beta);
                    self.bisect_to(pressure_kpa, r, lift, g, b, grasps[i].as_ref())
                });
            }
            let next = i + 1 < samples && scan[i + 1].viable;
            if here && !next {
                let bad = if i + 1 < samples {
                    scan[i + 1].beta
                } else {
                    hi
                };
                let end =
                    self.bisect_to(pressure_kpa, r, lift, scan[i].beta, bad, grasps[i].as_ref());
                if let Some(s) = start.take() {
                    intervals.push([s, end]);
                }
            }
        }
        Ok(ViableAngles {
            radius: r,
            lift,
            intervals,
            scan,
        })
    }

    fn angle_sample(
        &self,
        pressure_kpa: f64,
        r: f64,
        lift: f64,
        beta: f64,
        warm: Option<&Grasp>,
    ) -> (AngleSample, Option<Grasp>) {
        match self.sphere_lifted(pressure_kpa, r, lift, beta, warm, false) {
            Ok(sg) => (
                AngleSample {
                    beta,
                    normal: sg.grasp.normal,
                    friction: sg.grasp.friction,
                    viable: sg.is_valid(),
                    invalid: sg.invalid(),
                    failure: None,
                    reversed: sg.grasp.is_reversed(),
                    warnings: sg.grasp.warnings.clone(),
                },
                Some(sg.grasp),
            ),
            Err(e) => (
                AngleSample {
                    beta,
                    normal: 0.0,
                    friction: 0.0,
                    viable: false,
                    invalid: None,
                    failure: Some(e.to_string()),
                    reversed: false,
                    warnings: Vec::new(),
                },
                None,
            ),
        }
    }

    /// Bisects between a viable angle and a non-viable one; returns the
    /// last viable angle found.
    fn bisect_to(
        &self,
        pressure_kpa: f64,
        r: f64,
        lift: f64,
        mut good: f64,
        mut bad: f64,
        warm: Option<&Grasp>,
    ) -> f64 {
        let mut warm = warm.cloned();
        while (bad - good).abs() > VIABLE_BETA_TOL {
            let mid = 0.5 * (good + bad);
            let (sample, grasp) = self.angle_sample(pressure_kpa, r, lift, mid, warm.as_ref());
            if sample.viable {
                good = mid;
                warm = grasp;
            } else {
                bad = mid;
            }
        }
        good
    }
}

impl Gripper {
    /// A sphere's radius and grasping angle: positive radius, angle strictly
    /// inside (-pi/2, pi/2) (the contact must not be at a pole), and a
    /// contact the fingers reach without being pressed past flat (the tip at
    /// `Xg = r cos b <= d_max / 2`).
    pub(crate) fn check_sphere(&self, r: f64, beta: f64) -> Result<(), InputError> {
        positive(Field::SphereRadius, r)?;
        check_beta(beta)?;
        require(beta.abs() < FRAC_PI_2, Field::SphereBeta, beta, || {
            "must lie in (-pi/2, pi/2)".into()
        })?;
        let xg = r * beta.cos();
        let reach = 0.5 * self.d_max();
        require(xg <= reach * (1.0 + 1e-12), Field::SphereRadius, r, || {
            format!(
                "touched at {:.3} degrees puts the tip at Xg = {:.3} mm, beyond the flat fingers' reach d_max / 2 = {reach:.3} mm",
                beta.to_degrees(),
                Num(xg)
            )
        })
    }
}

/// The inputs of an angle scan over a sphere: pressure, radius, samples.
fn check_scan(pressure_kpa: f64, r: f64, samples: usize) -> Result<(), InputError> {
    positive(Field::SphereRadius, r)?;
    finite(Field::GraspPressureKpa, pressure_kpa)?;
    require(samples >= 4, Field::SphereSamples, samples as f64, || {
        "must be at least 4".into()
    })
}

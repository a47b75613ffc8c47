//! Predictions with error bars: a scene whose `[calibration]` table holds
//! a covariance `C` of its fitted keys gets 1-sigma uncertainties on what
//! it reports, by first-order propagation through the exact sensitivities
//! (src/sensitivity/): `sigma_y^2 = g^T C g` with `g = dy/dp` at the
//! solved equilibrium. A finger scene: the tip (X, Z) and the end angle
//! ([`Finger::sensitivities`](crate::Finger::sensitivities)), and the
//! mid-plane's circle-fit radius (its derivative through the shape samples
//! and the fit's own, `crate::circle_fit`). A gripper
//! scene: d_max ([`Gripper::geometry_sensitivities`]) and the grasp's
//! normal force, friction, lifting force, size, tip gap and height
//! ([`Gripper::grasp_sensitivities`]). The assumption is that the outputs
//! are linear in the parameters over a few standard deviations
//! (docs/calibration.md, "Predictions with error bars").

use serde::Serialize;

use crate::actuator::Actuator;
use crate::gripper::Gripper;
use crate::plan::Solved;
use crate::sensitivity::{
    radius_rows, Covariance, GraspKind, GraspSensitivity, GripperParam, Param, Sensitivities,
};
use crate::solve_error::SolveError;

use super::resolve::{GraspSpec, Scene};
use super::solve::{GraspOutcome, SceneSolution};

/// 1-sigma uncertainties of a solved scene's outputs ([`Scene::uncertainty`]).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Uncertainty {
    /// The keys the covariance is over.
    pub parameters: Vec<String>,
    /// Method: `"first_order"` (linear propagation of the covariance).
    pub method: &'static str,
    /// A finger scene: the tip's (X, Z) standard deviations (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tip_mm: Option<[f64; 2]>,
    /// A finger scene: the end angle's standard deviation (rad).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub end_angle_rad: Option<f64>,
    /// A finger scene: the standard deviation of the mid-plane's
    /// circle-fit radius (mm; the `radius_mm` of the solution, the fit
    /// `fpc compare` and study 7 make), when the solution has one.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius_mm: Option<f64>,
    /// Why a finger scene has no `radius_mm`: its shape was not sampled
    /// (`solve.shape = false`), no circle fits a straight mid-plane, or
    /// the fit has no derivative there. The other error bars stand.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub radius_unavailable: Option<String>,
    /// A gripper scene: d_max's standard deviation (mm).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub d_max_mm: Option<f64>,
    /// A gripper scene with a grasp: its outputs' standard deviations.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub grasp: Option<GraspUncertainty>,
    /// Why a gripper scene has no error bars (`d_max_mm` and `grasp`
    /// absent): its sensitivities do not cover the case, e.g. a rest
    /// shape whose innermost point is not the tip. The solve stands.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub unavailable: Option<String>,
}

/// 1-sigma uncertainties of a grasp's outputs (per finger).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GraspUncertainty {
    /// The normal force F (N).
    pub normal_force_n: f64,
    /// The friction f (N).
    pub friction_n: f64,
    /// The lifting force f_v (N).
    pub lift_n: f64,
    /// The grasping size d (mm).
    pub size_mm: f64,
    /// The tip gap (mm).
    pub tip_gap_mm: f64,
    /// The tip's height h (mm).
    pub height_mm: f64,
}

/// The sensitivities' name of a grasp as the scene asked it.
fn grasp_kind(spec: GraspSpec) -> GraspKind {
    match spec {
        GraspSpec::Size { d_mm, .. } => GraspKind::Size { d: d_mm },
        GraspSpec::Cuboid {
            d_mm, friction_n, ..
        } => GraspKind::ForceControl {
            d: d_mm,
            friction: friction_n,
        },
        GraspSpec::Sphere { r_mm, lift_n, .. } => GraspKind::Sphere {
            radius: r_mm,
            lift: lift_n,
        },
    }
}

fn gripper_params(cov: &Covariance) -> Vec<GripperParam> {
    cov.params()
        .iter()
        .filter_map(|p| match p {
            Param::Actuator(a) => Some(GripperParam::Actuator(*a)),
            // rejected when the scene was read
            _ => None,
        })
        .collect()
}

impl Scene {
    /// The covariance of the scene's `[calibration]` table, if it has one.
    pub fn covariance(&self) -> Option<&Covariance> {
        self.covariance.as_ref()
    }

    /// The 1-sigma uncertainties of `solved` (this scene's
    /// [`Scene::solve`]) from the `[calibration]` covariance by
    /// first-order propagation; `None` when the scene has none.
    pub fn uncertainty(&self, solved: &SceneSolution) -> Result<Option<Uncertainty>, SolveError> {
        let Some(cov) = &self.covariance else {
            return Ok(None);
        };
        let mut u = Uncertainty {
            parameters: cov.params().iter().map(|p| p.name()).collect(),
            method: "first_order",
            tip_mm: None,
            end_angle_rad: None,
            radius_mm: None,
            radius_unavailable: None,
            d_max_mm: None,
            grasp: None,
            unavailable: None,
        };
        match solved {
            SceneSolution::Finger(s) => {
                let sens = s.finger.sensitivities(
                    &self.actuator,
                    &s.solution,
                    &self.load,
                    cov.params(),
                )?;
                let col = |f: &dyn Fn(usize) -> f64| -> Vec<f64> {
                    (0..sens.rows.len()).map(f).collect()
                };
                u.tip_mm = Some([
                    cov.sigma(&col(&|k| sens.rows[k].tip[0])),
                    cov.sigma(&col(&|k| sens.rows[k].tip[1])),
                ]);
                u.end_angle_rad = Some(cov.sigma(&col(&|k| sens.rows[k].end_angle)));
                match radius_sigma(s, &sens, cov, self.options.samples_per_element)? {
                    Ok(r) => u.radius_mm = Some(r),
                    Err(why) => u.radius_unavailable = Some(why.into()),
                }
            }
            SceneSolution::Gripper { gripper, grasp } => {
                match gripper_sigmas(gripper, &self.actuator, cov, grasp.as_deref()) {
                    Ok((d_max, g)) => {
                        u.d_max_mm = Some(d_max);
                        u.grasp = g;
                    }
                    // the gripper's chaining does not cover every rest
                    // shape: the solve stands, without error bars
                    Err(e) => u.unavailable = Some(e.to_string()),
                }
            }
        }
        Ok(Some(u))
    }
}

/// The standard deviation of a finger scene's circle-fit radius, or why
/// it has none.
fn radius_sigma(
    s: &Solved,
    sens: &Sensitivities,
    cov: &Covariance,
    per: usize,
) -> Result<Result<f64, &'static str>, SolveError> {
    if s.solution.points.is_empty() {
        return Ok(Err("the shape is not sampled (solve.shape = false)"));
    }
    if s.solution.radius.is_none() {
        return Ok(Err("the mid-plane is straight: no circle fits it"));
    }
    Ok(
        match radius_rows(&s.finger, &s.solution.coefficients, sens, per)? {
            Some((_, d)) => Ok(cov.sigma(&d)),
            None => Err("the circle fit has no derivative at this shape"),
        },
    )
}

/// The standard deviations of a gripper's d_max and of its grasp's outputs.
fn gripper_sigmas(
    gripper: &Gripper,
    actuator: &Actuator,
    cov: &Covariance,
    grasp: Option<&GraspOutcome>,
) -> Result<(f64, Option<GraspUncertainty>), SolveError> {
    let params = gripper_params(cov);
    let geo = gripper.geometry_sensitivities(actuator, &params)?;
    let d_max = cov.sigma(&geo.iter().map(|r| r.d_max).collect::<Vec<_>>());
    let Some(o) = grasp else {
        return Ok((d_max, None));
    };
    let rows = gripper
        .grasp_sensitivities(actuator, &o.grasp, grasp_kind(o.spec), &params)?
        .rows;
    let s = |f: fn(&GraspSensitivity) -> f64| cov.sigma(&rows.iter().map(f).collect::<Vec<_>>());
    Ok((
        d_max,
        Some(GraspUncertainty {
            normal_force_n: s(|r| r.normal),
            friction_n: s(|r| r.friction),
            lift_n: s(|r| r.lift),
            size_mm: s(|r| r.size),
            tip_gap_mm: s(|r| r.tip_gap),
            height_mm: s(|r| r.height),
        }),
    ))
}

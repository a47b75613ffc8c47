//! Sensitivities of the gripper's outputs (docs/model.md, "Sensitivities",
//! "Gripper outputs"): the finger's exact sensitivities chained through the
//! way the gripper builds its geometry and its target solves.
//!
//! A grasp is a finger target solve whose problem the gripper builds from
//! its design: weights `w = (cos a, sin a)`, a finger-frame fixed force
//! `R(a) F0_g` and load direction `u_f = R(a) u_g` (at the friction limit
//! `F0_g = 0` and `u_g = n + mu t`), and a target `T` that depends on the reference tip `r`, the
//! overlap or the palm, the grasp size or the sphere. A change `dw` of the
//! weights acts on the target equation `w . tip - T = 0` like a change
//! `-dw . tip` of the target, and a change `du_f` of the direction acts on
//! the equilibrium like a change `lambda du_f` of the fixed tip force, so
//! every parameter reduces to the finger's own [`Param::Target`],
//! [`Param::Fx`], [`Param::Fz`], [`Param::Pressure`] and actuator rows:
//!
//! ```text
//! dy/dp = S_y(p) + S_y(P) dP/dp + (S_y(Fx), S_y(Fz)) . (d(R(a) F0_g)/dp + lambda du_f/dp)
//!         + S_y(Target) (dT/dp - dw/dp . tip)          y = tip X, tip Z, lambda
//! ```
//!
//! The geometry (l0, the overlap or the palm, d_max) comes from the
//! reference state: `l0 = -w . p*` at the innermost rest sample `p*`, so
//! `dl0/dp = -(dw/dp . p* + w . dp*/dp)`; `dp*/dp` is the reference tip's
//! sensitivity when the tip is the innermost sample (the only case covered
//! for actuator parameters).
//!
//! The envelope `f_v^max(r) = max_b f_v(r, b)`: at an interior optimum
//! `b*`, `d f_v / d b = 0`, so `d f_v^max / dp` is the partial derivative at
//! fixed `b*` (the envelope theorem), one grasp sensitivity; where the
//! maximum sits on the second-contact boundary `phi(b, p) = 0`, the angle
//! follows the boundary and `d f_v^max / dp = f_p - f_b phi_p / phi_b`.

use std::fmt;

use crate::actuator::Actuator;
use crate::error::InputError;
use crate::field::Field;
use crate::finger::{Load, Solution};
use crate::gripper::{contact_force_to_gripper, gripper_force_to_finger, Grasp, Gripper, PalmSpec};
use crate::solve_error::SolveError;

use super::params::Param;
use super::record::{Sensitivities, Sensitivity};
use crate::actuator::ActuatorParam;

/// A parameter of a gripper-output sensitivity.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum GripperParam {
    /// An actuator parameter of the finger (moves the reference state and
    /// the grasp).
    Actuator(ActuatorParam),
    /// The grasp's channel pressure (per kPa); the reference state is at
    /// zero pressure and does not move.
    Pressure,
    /// The mounting angle `a` (per rad).
    MountingAngle,
    /// The overlap `g` (per mm) of a gripper specified by its overlap.
    Overlap,
    /// The palm diameter `l` (per mm) of a gripper specified by its palm.
    Palm,
    /// The grasping size `d` (per mm) of a size grasp.
    Size,
    /// The radius `r` (per mm) of a sphere grasp.
    Radius,
    /// The grasping angle `b` (per rad).
    Beta,
}

impl GripperParam {
    /// The name (`actuator.pemc.eps0`, `grasp.pressure_kpa`,
    /// `gripper.mounting_angle_rad`, `gripper.overlap_mm`,
    /// `gripper.palm_mm`, `grasp.d_mm`, `sphere.r_mm`, `grasp.beta_rad`).
    pub fn name(self) -> String {
        match self {
            GripperParam::Actuator(a) => a.name(),
            GripperParam::Pressure => "grasp.pressure_kpa".into(),
            GripperParam::MountingAngle => "gripper.mounting_angle_rad".into(),
            GripperParam::Overlap => "gripper.overlap_mm".into(),
            GripperParam::Palm => "gripper.palm_mm".into(),
            GripperParam::Size => "grasp.d_mm".into(),
            GripperParam::Radius => "sphere.r_mm".into(),
            GripperParam::Beta => "grasp.beta_rad".into(),
        }
    }

    /// The gripper's design parameters for `actuator`: its actuator
    /// parameters, the mounting angle and the overlap or the palm (as the
    /// gripper is specified).
    pub fn design(actuator: &Actuator, gripper: &Gripper) -> Vec<GripperParam> {
        let mut v: Vec<GripperParam> = ActuatorParam::for_actuator(actuator)
            .into_iter()
            .map(GripperParam::Actuator)
            .collect();
        v.push(GripperParam::MountingAngle);
        v.push(match gripper.params().geometry {
            PalmSpec::Overlap(_) => GripperParam::Overlap,
            PalmSpec::Palm(_) => GripperParam::Palm,
        });
        v
    }
}

impl fmt::Display for GripperParam {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.name())
    }
}

impl serde::Serialize for GripperParam {
    /// The name.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        s.serialize_str(&self.name())
    }
}

/// Which gripper solve a [`Grasp`] came from.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GraspKind {
    /// [`Gripper::grasp_load_for_size`] at grasping size `d` (mm).
    Size {
        /// The grasping size (mm).
        d: f64,
    },
    /// [`Gripper::sphere_grasp_at_friction_limit`] of a sphere of radius
    /// `radius` (mm).
    SphereAtFrictionLimit {
        /// The sphere's radius (mm).
        radius: f64,
    },
    /// [`Gripper::sphere_grasp`] of a sphere of radius `radius` (mm) with
    /// lifting force `lift` (N).
    Sphere {
        /// The sphere's radius (mm).
        radius: f64,
        /// The lifting force per finger (N).
        lift: f64,
    },
    /// [`Gripper::force_control`] at grasping size `d` (mm) with friction
    /// `friction` (N).
    ForceControl {
        /// The grasping size (mm).
        d: f64,
        /// The friction per finger (N).
        friction: f64,
    },
}

impl GraspKind {
    /// The load of the kind's scene in the gripper frame: the fixed force
    /// and the force per unit lambda at grasping angle `beta`, and the
    /// latter's derivative in `beta`.
    fn scene(self, mu: f64, beta: f64) -> ([f64; 2], [f64; 2], [f64; 2]) {
        let (sb, cb) = beta.sin_cos();
        match self {
            GraspKind::Size { .. } | GraspKind::SphereAtFrictionLimit { .. } => (
                [0.0, 0.0],
                contact_force_to_gripper(1.0, mu, beta),
                [-sb - mu * cb, cb - mu * sb],
            ),
            GraspKind::Sphere { lift, .. } => ([0.0, lift], [1.0, 0.0], [0.0, 0.0]),
            GraspKind::ForceControl { friction, .. } => ([0.0, friction], [1.0, 0.0], [0.0, 0.0]),
        }
    }

    /// The sphere's radius, for the sphere kinds.
    fn radius(self) -> Option<f64> {
        match self {
            GraspKind::SphereAtFrictionLimit { radius } | GraspKind::Sphere { radius, .. } => {
                Some(radius)
            }
            _ => None,
        }
    }

    /// The grasping size, for the size kinds.
    fn size(self) -> Option<f64> {
        match self {
            GraspKind::Size { d } | GraspKind::ForceControl { d, .. } => Some(d),
            _ => None,
        }
    }
}

/// The derivatives of the gripper's geometry with respect to one parameter.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GeometrySensitivity {
    /// The parameter.
    pub param: GripperParam,
    /// Its value.
    pub value: f64,
    /// d l0 / dp (mm per unit).
    #[serde(rename = "l0_mm")]
    pub l0: f64,
    /// d g / dp, the overlap (mm per unit).
    #[serde(rename = "overlap_mm")]
    pub overlap: f64,
    /// d l / dp, the palm diameter (mm per unit).
    #[serde(rename = "palm_mm")]
    pub palm: f64,
    /// d d_max / dp (mm per unit).
    #[serde(rename = "d_max_mm")]
    pub d_max: f64,
    /// d r_max / dp (mm per unit).
    #[serde(rename = "r_max_mm")]
    pub r_max: f64,
    /// d (rest size -2 g) / dp (mm per unit).
    #[serde(rename = "rest_size_mm")]
    pub rest_size: f64,
}

/// The derivatives of a finger equilibrium's grasp measures (size, tip gap,
/// height) with respect to one parameter ([`Gripper::size_sensitivities`]).
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct SizeSensitivity {
    /// The parameter.
    pub param: GripperParam,
    /// Its value.
    pub value: f64,
    /// d d / dp, the grasping size `2 (dXg - g)` (mm per unit).
    #[serde(rename = "size_mm")]
    pub size: f64,
    /// d (tip gap) / dp (mm per unit).
    #[serde(rename = "tip_gap_mm")]
    pub tip_gap: f64,
    /// d h / dp, the tip's Zg (mm per unit).
    #[serde(rename = "height_mm")]
    pub height: f64,
}

/// The derivatives of a grasp's outputs with respect to one parameter.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GraspSensitivity {
    /// The parameter.
    pub param: GripperParam,
    /// Its value.
    pub value: f64,
    /// d F / dp, the normal force (N per unit).
    #[serde(rename = "normal_force_n")]
    pub normal: f64,
    /// d f / dp, the friction (N per unit).
    #[serde(rename = "friction_n")]
    pub friction: f64,
    /// d f_v / dp, the lifting force (N per unit).
    #[serde(rename = "lift_n")]
    pub lift: f64,
    /// d lambda / dp, the target solve's load factor.
    pub lambda: f64,
    /// d d / dp, the grasping size (mm per unit).
    #[serde(rename = "size_mm")]
    pub size: f64,
    /// d (tip gap) / dp (mm per unit).
    #[serde(rename = "tip_gap_mm")]
    pub tip_gap: f64,
    /// d h / dp (mm per unit).
    #[serde(rename = "height_mm")]
    pub height: f64,
    /// d (tip Xg, tip Zg) / dp (mm per unit).
    #[serde(rename = "tip_gripper_mm")]
    pub tip: [f64; 2],
}

/// The sensitivities of a grasp ([`Gripper::grasp_sensitivities`]), one
/// row per parameter asked for, in that order.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct GraspSensitivities {
    /// One row per parameter.
    pub rows: Vec<GraspSensitivity>,
}

impl GraspSensitivities {
    /// The row of a parameter.
    pub fn get(&self, param: GripperParam) -> Option<&GraspSensitivity> {
        self.rows.iter().find(|r| r.param == param)
    }
}

pub(super) fn inconsistent(field: impl Into<Field>, rule: String) -> SolveError {
    SolveError::Input(InputError::Inconsistent {
        field: field.into(),
        rule,
    })
}

/// The geometry's derivatives for one parameter.
#[derive(Clone, Copy)]
pub(super) struct Geo {
    /// d a / dp.
    pub da: f64,
    /// d (reference tip) / dp, finger frame.
    pub dr: [f64; 2],
    /// d l0 / dp.
    pub dl0: f64,
    /// d g / dp, the overlap.
    pub dg: f64,
    /// d l / dp, the palm.
    pub dpalm: f64,
}

/// An error for the grasp parameters among `params` (and the pressure,
/// when `pressure`): they are not parameters of the geometry or of a free
/// equilibrium's measures.
fn reject_grasp_params(params: &[GripperParam], pressure: bool) -> Result<(), SolveError> {
    for &p in params {
        let grasp = matches!(
            p,
            GripperParam::Size | GripperParam::Radius | GripperParam::Beta
        ) || (pressure && p == GripperParam::Pressure);
        if grasp {
            return Err(inconsistent(
                p.name(),
                "is a parameter of a grasp, not of the gripper's geometry or of a free equilibrium (use Gripper::grasp_sensitivities)".into(),
            ));
        }
    }
    Ok(())
}

/// The finger row of a parameter.
fn finger_row(s: &Sensitivities, p: Param) -> Option<&Sensitivity> {
    s.rows.iter().find(|r| r.param == p)
}

impl Gripper {
    /// The actuator parameters among `params`, as finger parameters.
    fn actuator_params(params: &[GripperParam]) -> Vec<Param> {
        let mut v = Vec::new();
        for p in params {
            if let GripperParam::Actuator(a) = p {
                if !v.contains(&Param::Actuator(*a)) {
                    v.push(Param::Actuator(*a));
                }
            }
        }
        v
    }

    fn param_value(
        &self,
        actuator: &Actuator,
        p: GripperParam,
        pressure_kpa: f64,
        kind: Option<GraspKind>,
        beta: f64,
    ) -> f64 {
        match (p, kind) {
            (GripperParam::Actuator(a), _) => a.value(actuator).unwrap_or(f64::NAN),
            (GripperParam::Pressure, _) => pressure_kpa,
            (GripperParam::MountingAngle, _) => self.mounting_angle(),
            (GripperParam::Overlap, _) => self.overlap(),
            (GripperParam::Palm, _) => self.palm(),
            (GripperParam::Size, Some(k)) => k.size().unwrap_or(f64::NAN),
            (GripperParam::Radius, Some(k)) => k.radius().unwrap_or(f64::NAN),
            (GripperParam::Beta, _) => beta,
            _ => f64::NAN,
        }
    }

    /// The geometry's derivatives for each parameter (the reference state's
    /// sensitivities for the actuator parameters).
    pub(super) fn geometry_derivatives(
        &self,
        actuator: &Actuator,
        params: &[GripperParam],
    ) -> Result<Vec<Geo>, SolveError> {
        let aparams = Gripper::actuator_params(params);
        let reference = self.reference();
        let rs = if aparams.is_empty() {
            None
        } else {
            Some(
                self.finger()
                    .sensitivities(actuator, reference, &Load::unloaded(), &aparams)?,
            )
        };
        let a = self.mounting_angle();
        let (s, c) = a.sin_cos();
        let at_root = self.l0() <= 0.0;
        let inner = self.innermost_point();
        let tip_inner = inner + 1 == reference.points.len();
        let pin = reference.points.get(inner).copied().unwrap_or([0.0, 0.0]);
        let overlap_spec = matches!(self.params().geometry, PalmSpec::Overlap(_));
        let mut out = Vec::with_capacity(params.len());
        for &p in params {
            let mut geo = Geo {
                da: 0.0,
                dr: [0.0, 0.0],
                dl0: 0.0,
                dg: 0.0,
                dpalm: 0.0,
            };
            match p {
                GripperParam::Actuator(ap) => {
                    let row = rs
                        .as_ref()
                        .and_then(|rs| finger_row(rs, Param::Actuator(ap)))
                        .ok_or_else(|| inconsistent(p.name(), "has no reference row".into()))?;
                    geo.dr = row.tip;
                    if !at_root {
                        if !tip_inner {
                            return Err(inconsistent(
                                p.name(),
                                format!(
                                    "moves l0 through the rest shape's innermost point, sample {inner}, which is not the tip: only the tip's sensitivity is covered"
                                ),
                            ));
                        }
                        geo.dl0 = -(c * row.tip[0] + s * row.tip[1]);
                    }
                }
                GripperParam::MountingAngle => {
                    geo.da = 1.0;
                    if !at_root {
                        // l0 = -(X cos a + Z sin a) at the innermost sample
                        geo.dl0 = s * pin[0] - c * pin[1];
                    }
                }
                GripperParam::Overlap if !overlap_spec => {
                    return Err(inconsistent(
                        p.name(),
                        "is a parameter of a gripper specified by its overlap; this one is specified by its palm (use gripper.palm_mm)".into(),
                    ));
                }
                GripperParam::Palm if overlap_spec => {
                    return Err(inconsistent(
                        p.name(),
                        "is a parameter of a gripper specified by its palm; this one is specified by its overlap (use gripper.overlap_mm)".into(),
                    ));
                }
                _ => {}
            }
            // g = fixed, l = 2 (l0 - g); or l fixed, g = l0 - l/2
            if overlap_spec {
                geo.dg = f64::from(u8::from(p == GripperParam::Overlap));
                geo.dpalm = 2.0 * (geo.dl0 - geo.dg);
            } else {
                geo.dpalm = f64::from(u8::from(p == GripperParam::Palm));
                geo.dg = geo.dl0 - 0.5 * geo.dpalm;
            }
            out.push(geo);
        }
        Ok(out)
    }

    /// The derivatives of the gripper's geometry (l0, the overlap, the
    /// palm, d_max, r_max, the rest size) with respect to design
    /// parameters: actuator parameters (through the reference state's
    /// sensitivities; covered when the tip is the rest shape's innermost
    /// point, or l0 = 0), the mounting angle, and the overlap or the palm.
    /// The grasp parameters (pressure, size, radius, angle) do not move the
    /// geometry and are not parameters here. `actuator` must be the
    /// finger's.
    pub fn geometry_sensitivities(
        &self,
        actuator: &Actuator,
        params: &[GripperParam],
    ) -> Result<Vec<GeometrySensitivity>, SolveError> {
        reject_grasp_params(params, true)?;
        let geos = self.geometry_derivatives(actuator, params)?;
        let a = self.mounting_angle();
        let (s, c) = a.sin_cos();
        let lx = self.length();
        let num = 0.5 * self.palm() + lx * c;
        Ok(params
            .iter()
            .zip(geos)
            .map(|(&p, geo)| {
                let dnum = 0.5 * geo.dpalm - lx * s * geo.da;
                GeometrySensitivity {
                    param: p,
                    value: self.param_value(actuator, p, 0.0, None, 0.0),
                    l0: geo.dl0,
                    overlap: geo.dg,
                    palm: geo.dpalm,
                    d_max: geo.dpalm - 2.0 * lx * s * geo.da,
                    r_max: (dnum * s - num * c * geo.da) / (s * s),
                    rest_size: -2.0 * geo.dg,
                }
            })
            .collect())
    }

    /// The derivatives of the grasp measures (size `d`, tip gap, height) of
    /// a finger equilibrium `solution` under `load` (finger frame; e.g. the
    /// unloaded finger at a pressure, how far the gripper opens) with
    /// respect to actuator parameters, the pressure (`load`'s) and the
    /// gripper's geometry. `d = 2 (w . (tip - r) - g)` with `r` the
    /// reference tip, so both the equilibrium's and the reference state's
    /// sensitivities enter. [`GripperParam::Size`], [`GripperParam::Radius`]
    /// and [`GripperParam::Beta`] belong to grasps and are not parameters
    /// here.
    pub fn size_sensitivities(
        &self,
        actuator: &Actuator,
        solution: &Solution,
        load: &Load,
        params: &[GripperParam],
    ) -> Result<Vec<SizeSensitivity>, SolveError> {
        reject_grasp_params(params, false)?;
        let geos = self.geometry_derivatives(actuator, params)?;
        let mut fparams = Gripper::actuator_params(params);
        fparams.push(Param::Pressure);
        let fs = self
            .finger()
            .sensitivities(actuator, solution, load, &fparams)?;
        let a = self.mounting_angle();
        let (s, c) = a.sin_cos();
        let tip = solution.tip;
        let r = self.reference().tip;
        let mut rows = Vec::with_capacity(params.len());
        for (&p, geo) in params.iter().zip(geos) {
            let dtip = match p {
                GripperParam::Actuator(ap) => finger_row(&fs, Param::Actuator(ap)).map(|r| r.tip),
                GripperParam::Pressure => finger_row(&fs, Param::Pressure).map(|r| r.tip),
                _ => None,
            }
            .unwrap_or([0.0, 0.0]);
            let dw = [-s * geo.da, c * geo.da];
            let d_xg = dw[0] * (tip[0] - r[0])
                + dw[1] * (tip[1] - r[1])
                + c * (dtip[0] - geo.dr[0])
                + s * (dtip[1] - geo.dr[1]);
            let d_tip_xg =
                0.5 * geo.dpalm + dw[0] * tip[0] + dw[1] * tip[1] + c * dtip[0] + s * dtip[1];
            let d_tip_zg = c * geo.da * tip[0] + s * dtip[0] + s * geo.da * tip[1] - c * dtip[1];
            rows.push(SizeSensitivity {
                param: p,
                value: self.param_value(actuator, p, load.pressure * 1e3, None, 0.0),
                size: 2.0 * (d_xg - geo.dg),
                tip_gap: 2.0 * d_tip_xg,
                height: d_tip_zg,
            });
        }
        Ok(rows)
    }

    /// The exact derivatives of a grasp's outputs (normal force, friction,
    /// lifting force, load factor, size, tip gap, height, tip) with respect
    /// to `params`: the finger's target sensitivities at the grasp, chained
    /// through how the gripper builds the target problem from its design
    /// (module docs of `src/sensitivity/gripper.rs`, docs/model.md): size
    /// and sphere grasps at the friction limit, sphere grasps at a given
    /// lift, force control. `kind` says which solve gave `grasp` (checked
    /// against its problem);
    /// `actuator` must be the finger's. [`GripperParam::Size`] belongs to
    /// size grasps and force control, [`GripperParam::Radius`] to sphere
    /// grasps; force control has no [`GripperParam::Beta`].
    pub fn grasp_sensitivities(
        &self,
        actuator: &Actuator,
        grasp: &Grasp,
        kind: GraspKind,
        params: &[GripperParam],
    ) -> Result<GraspSensitivities, SolveError> {
        Ok(self.grasp_chain(actuator, grasp, kind, params)?.0)
    }

    /// [`Gripper::grasp_sensitivities`], with each row's chained dK/dp
    /// (raw coefficients).
    pub(super) fn grasp_chain(
        &self,
        actuator: &Actuator,
        grasp: &Grasp,
        kind: GraspKind,
        params: &[GripperParam],
    ) -> Result<(GraspSensitivities, Vec<Vec<f64>>), SolveError> {
        let a = self.mounting_angle();
        let (s, c) = a.sin_cos();
        let mu = self.mu();
        let b = grasp.beta;
        let (sb, cb) = b.sin_cos();
        let r = self.reference().tip;
        // the problem the gripper builds for this kind, checked
        let target = match kind {
            GraspKind::Size { d } | GraspKind::ForceControl { d, .. } => {
                crate::error::finite(Field::GraspSize, d)?;
                c * r[0] + s * r[1] + 0.5 * d + self.overlap()
            }
            GraspKind::SphereAtFrictionLimit { radius } | GraspKind::Sphere { radius, .. } => {
                crate::error::positive(Field::SphereRadius, radius)?;
                radius * cb - 0.5 * self.palm()
            }
        };
        if let GraspKind::Sphere { lift: f, .. } | GraspKind::ForceControl { friction: f, .. } =
            kind
        {
            crate::error::finite(Field::GraspForce, f)?;
        }
        let (base_g, u_g, du_g_db) = kind.scene(mu, b);
        let u_f = gripper_force_to_finger(u_g, a);
        let base_f = gripper_force_to_finger(base_g, a);
        let pb = &grasp.problem;
        let near = |x: f64, y: f64| (x - y).abs() <= 1e-9 * (1.0 + x.abs().max(y.abs()));
        let same = near(pb.target, target)
            && near(pb.weights[0], c)
            && near(pb.weights[1], s)
            && near(pb.direction[0], u_f[0])
            && near(pb.direction[1], u_f[1])
            && near(pb.base.fx, base_f[0])
            && near(pb.base.fz, base_f[1])
            && near(pb.base.pressure * 1e3, grasp.pressure_kpa);
        if !same {
            return Err(inconsistent(
                Field::key("grasp"),
                format!("is not a {kind:?} grasp of this gripper (its target problem differs)"),
            ));
        }
        for &p in params {
            let wrong = match p {
                GripperParam::Size if kind.size().is_none() => {
                    Some("is a parameter of size grasps")
                }
                GripperParam::Radius if kind.radius().is_none() => {
                    Some("is a parameter of sphere grasps")
                }
                GripperParam::Beta if matches!(kind, GraspKind::ForceControl { .. }) => {
                    Some("is not a parameter of force control (its grasping angle is 0)")
                }
                _ => None,
            };
            if let Some(rule) = wrong {
                return Err(inconsistent(p.name(), rule.into()));
            }
        }
        let geos = self.geometry_derivatives(actuator, params)?;
        let mut fparams = Gripper::actuator_params(params);
        fparams.extend([Param::Pressure, Param::Fx, Param::Fz, Param::Target]);
        let fs = self.finger().target_sensitivities(
            actuator,
            &grasp.solution,
            &grasp.problem,
            grasp.lambda,
            &fparams,
        )?;
        let row = |p: Param| {
            finger_row(&fs, p)
                .map(|r| [r.tip[0], r.tip[1], r.lambda.unwrap_or(0.0)])
                .ok_or_else(|| inconsistent(p.name(), "has no finger row".into()))
        };
        let dk_of = |p: Param| {
            finger_row(&fs, p)
                .map(|r| r.coefficients.as_slice())
                .ok_or_else(|| inconsistent(p.name(), "has no finger row".into()))
        };
        let (sp, sx, sz, st) = (
            row(Param::Pressure)?,
            row(Param::Fx)?,
            row(Param::Fz)?,
            row(Param::Target)?,
        );
        let (kp, kx, kz, kt) = (
            dk_of(Param::Pressure)?,
            dk_of(Param::Fx)?,
            dk_of(Param::Fz)?,
            dk_of(Param::Target)?,
        );
        let mut dks = Vec::with_capacity(params.len());
        let lambda = grasp.lambda;
        let tip = grasp.solution.tip;
        let mut rows = Vec::with_capacity(params.len());
        for (&p, geo) in params.iter().zip(geos) {
            let (sa, ka) = match p {
                GripperParam::Actuator(ap) => {
                    (row(Param::Actuator(ap))?, Some(dk_of(Param::Actuator(ap))?))
                }
                _ => ([0.0; 3], None),
            };
            let dp = f64::from(u8::from(p == GripperParam::Pressure));
            let db = f64::from(u8::from(p == GripperParam::Beta));
            let dd = f64::from(u8::from(p == GripperParam::Size));
            let d_radius = f64::from(u8::from(p == GripperParam::Radius));
            let da = geo.da;
            // the contact direction, gripper then finger frame
            let du_g = [du_g_db[0] * db, du_g_db[1] * db];
            let du_f = [
                (-s * u_g[0] + c * u_g[1]) * da + c * du_g[0] + s * du_g[1],
                (c * u_g[0] + s * u_g[1]) * da + s * du_g[0] - c * du_g[1],
            ];
            // the fixed force is constant in the gripper frame
            let dbase_f = [
                (-s * base_g[0] + c * base_g[1]) * da,
                (c * base_g[0] + s * base_g[1]) * da,
            ];
            let dw = [-s * da, c * da];
            let dt = match kind.radius() {
                None => {
                    dw[0] * r[0] + dw[1] * r[1] + c * geo.dr[0] + s * geo.dr[1] + 0.5 * dd + geo.dg
                }
                Some(radius) => d_radius * cb - radius * sb * db - 0.5 * geo.dpalm,
            };
            let dt_eff = dt - (dw[0] * tip[0] + dw[1] * tip[1]);
            let mut dy = [0.0; 3];
            for (k, v) in dy.iter_mut().enumerate() {
                *v = sa[k]
                    + sp[k] * dp
                    + sx[k] * (lambda * du_f[0] + dbase_f[0])
                    + sz[k] * (lambda * du_f[1] + dbase_f[1])
                    + st[k] * dt_eff;
            }
            let (dtip, dl) = ([dy[0], dy[1]], dy[2]);
            let dk: Vec<f64> = (0..kp.len())
                .map(|i| {
                    ka.map_or(0.0, |k| k[i])
                        + kp[i] * dp
                        + kx[i] * (lambda * du_f[0] + dbase_f[0])
                        + kz[i] * (lambda * du_f[1] + dbase_f[1])
                        + kt[i] * dt_eff
                })
                .collect();
            dks.push(dk);
            // the contact force base + lambda u_g and its components
            let force = [base_g[0] + lambda * u_g[0], base_g[1] + lambda * u_g[1]];
            let dforce = [
                dl * u_g[0] + lambda * du_g[0],
                dl * u_g[1] + lambda * du_g[1],
            ];
            let normal = force[0] * cb + force[1] * sb;
            let friction = -force[0] * sb + force[1] * cb;
            let d_normal = dforce[0] * cb + dforce[1] * sb + friction * db;
            let d_friction = -dforce[0] * sb + dforce[1] * cb - normal * db;
            let d_tip_xg =
                0.5 * geo.dpalm + dw[0] * tip[0] + dw[1] * tip[1] + c * dtip[0] + s * dtip[1];
            let d_tip_zg = c * da * tip[0] + s * dtip[0] + s * da * tip[1] - c * dtip[1];
            let d_xg = dw[0] * (tip[0] - r[0])
                + dw[1] * (tip[1] - r[1])
                + c * (dtip[0] - geo.dr[0])
                + s * (dtip[1] - geo.dr[1]);
            rows.push(GraspSensitivity {
                param: p,
                value: self.param_value(actuator, p, grasp.pressure_kpa, Some(kind), b),
                normal: d_normal,
                friction: d_friction,
                lift: dforce[1],
                lambda: dl,
                size: 2.0 * (d_xg - geo.dg),
                tip_gap: 2.0 * d_tip_xg,
                height: d_tip_zg,
                tip: [d_tip_xg, d_tip_zg],
            });
        }
        Ok((GraspSensitivities { rows }, dks))
    }
}

//! A gripper's design and set-up: its parameters, the reference state of
//! the unloaded finger and the geometry it fixes, and a grasp's record.

use std::any::Any;
use std::f64::consts::PI;
use std::sync::Arc;

use crate::actuator::{Actuator, MAX_DIMENSION_MM};
use crate::error::{finite, positive, require, InputError, Warning};
use crate::finger::{Finger, Load, Solution, SolveOptions, TargetProblem};
use crate::partition::Partition;
use crate::solve_error::SolveError;

use super::frames::{design_space, finger_displacement_to_gripper, finger_point_to_gripper};
use super::rules::{self, Invalid, Verdict};

/// Mid-plane samples per element for the reference state (l0 is the
/// largest inward reach over all of them) and for grasp shapes.
pub const GRIPPER_SAMPLES_PER_ELEMENT: usize = 32;

/// Most fingers a gripper may have: twelve already need a palm of about
/// 3.9 finger widths (docs/model.md Sec. 5.4); one finger is solved and
/// mirrored, so the count costs no work, and the bound keeps it a count.
pub const MAX_FINGERS: usize = 12;

/// Curvature samples per element for the reversal check.
pub(super) const CURVATURE_SAMPLES: usize = 4;

/// Target residual of the grasp solves (mm).
pub(super) const TARGET_TOL_MM: f64 = 1e-9;

/// How far (mm) the object may reach into the finger's mid-plane before it
/// counts as a second contact (rounding of the contact point itself, which
/// the target puts on the object to within 1e-9 mm).
pub const CONTACT_TOL_MM: f64 = 1e-9;

/// How the palm is specified.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PalmSpec {
    /// Overlap `g = l0 - l/2` (mm) between the fingers at rest; the palm
    /// diameter follows as `l = 2 (l0 - g)`.
    #[serde(rename = "overlap_mm")]
    Overlap(f64),
    /// Palm diameter `l` (mm); the overlap follows as `g = l0 - l/2`.
    #[serde(rename = "palm_mm")]
    Palm(f64),
}

/// A gripper's design.
#[derive(Debug, Clone, Copy, PartialEq, serde::Serialize)]
pub struct GripperParams {
    /// Mounting angle `a` between the palm plane and the finger's root
    /// tangent (rad), in (0, pi); the design space is `[arccot mu, pi/2]`.
    #[serde(rename = "mounting_angle_rad")]
    pub mounting_angle: f64,
    /// Palm diameter or overlap.
    pub geometry: PalmSpec,
    /// Number of fingers, 1 to [`MAX_FINGERS`] (informational: the fingers
    /// are synchronised, one is analysed).
    pub fingers: usize,
    /// Friction coefficient between object and finger tip.
    pub mu: f64,
    /// Strict mode: a grasp that bends an element backwards is invalid (the
    /// paper's assumption), not only flagged.
    pub strict: bool,
}

impl Default for GripperParams {
    /// The gripper of the paper's Sec. 5: `a = pi/3`, overlap 20 mm, three
    /// fingers, `mu = 0.6`, not strict.
    fn default() -> GripperParams {
        GripperParams {
            mounting_angle: std::f64::consts::FRAC_PI_3,
            geometry: PalmSpec::Overlap(20.0),
            fingers: 3,
            mu: 0.6,
            strict: false,
        }
    }
}

/// An equilibrium of a grasp with its load and measures.
#[derive(Debug, Clone, PartialEq, serde::Serialize)]
pub struct Grasp {
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Grasping angle `b` (rad).
    #[serde(rename = "beta_rad")]
    pub beta: f64,
    /// Normal force `F` on the finger (N).
    #[serde(rename = "normal_force_n")]
    pub normal: f64,
    /// Friction `f` on the finger, positive along `t` (N).
    #[serde(rename = "friction_n")]
    pub friction: f64,
    /// Lifting force `f_v = f cos b + F sin b` (N).
    #[serde(rename = "lift_n")]
    pub lift: f64,
    /// Grasping size `d = 2 (dXg - g)` (mm), the paper's measure.
    #[serde(rename = "size_mm")]
    pub size: f64,
    /// Gap between the tips, `2 tip Xg` (mm); equals `size` when the tip
    /// is the innermost point at rest.
    #[serde(rename = "tip_gap_mm")]
    pub tip_gap: f64,
    /// Finger height `h`: the tip's Zg (mm).
    #[serde(rename = "height_mm")]
    pub height: f64,
    /// Tip in the gripper frame (mm).
    #[serde(rename = "tip_gripper_mm")]
    pub tip: [f64; 2],
    /// The tip load in the finger frame.
    pub load: Load,
    /// The bordered problem solved (warm starts follow from it).
    pub problem: TargetProblem,
    /// Its load parameter at the solution.
    pub lambda: f64,
    /// The finger's equilibrium (mid-plane samples in the finger frame).
    pub solution: Solution,
    /// Every note and finding at the grasp: the finger's
    /// ([`Solution::warnings`]: the actuator's notes and where the answer
    /// leaves the model) and the grasp's own (`curvature_reversal`,
    /// `beyond_flat`).
    pub warnings: Vec<Warning>,
    /// The verdict: the rules, the findings, the stability and the path,
    /// apart ([`Verdict`]); valid only when all hold.
    pub verdict: Verdict,
    /// The object touched (a sweep continues with the same object).
    #[serde(skip)]
    pub(crate) object: Object,
}

impl Grasp {
    /// True when `F >= 0` and `0 <= f <= mu F` (to rounding).
    pub fn friction_ok(&self, mu: f64) -> bool {
        rules::friction_ok(self.normal, self.friction, mu)
    }

    /// True when the grasp is valid: the paper's rules hold, the finger is
    /// inside the model, the grasp is stable and on the loading path
    /// ([`Verdict`]).
    pub fn is_valid(&self) -> bool {
        self.verdict.is_valid()
    }

    /// The first reason the grasp is not valid (`None`: valid).
    pub fn invalid(&self) -> Option<Invalid> {
        self.verdict.first()
    }

    /// True when an element is bent backwards.
    pub fn is_reversed(&self) -> bool {
        self.warnings
            .iter()
            .any(|w| matches!(w, Warning::CurvatureReversal { .. }))
    }
}

// ------------------------------------------------------------ the gripper

/// A gripper: the finger, its reference (unloaded, zero-pressure) state,
/// and the geometry that state fixes.
#[derive(Debug, Clone)]
pub struct Gripper {
    pub(super) finger: Finger,
    pub(super) params: GripperParams,
    pub(super) lx: f64,
    pub(super) reference: Solution,
    /// The reference state's curvature samples (reversal checks).
    pub(super) reference_curvature: Vec<f64>,
    l0: f64,
    pub(super) innermost: usize,
    pub(super) palm: f64,
    pub(super) overlap: f64,
    pub(super) warnings: Vec<Warning>,
    pub(super) stability: bool,
    /// What a scene built this gripper from (the scene's own key, opaque
    /// here): a nearby scene with the same key (a sweep over the grasp)
    /// takes this gripper again instead of solving its reference anew.
    pub(crate) built_from: Option<Arc<dyn Any + Send + Sync>>,
}

/// How the tip load depends on `lambda`, in the gripper frame.
pub(super) struct GraspLoad {
    pub(super) pressure_kpa: f64,
    pub(super) beta: f64,
    /// Fixed gripper-frame force (N).
    pub(super) base: [f64; 2],
    /// Gripper-frame force per unit `lambda` (N).
    pub(super) direction: [f64; 2],
    /// Target tip Xg (mm).
    pub(super) tip_xg: f64,
    /// The target's field and value, for errors.
    pub(super) target: (crate::Field, f64),
    /// The object touched, for the contact check.
    pub(super) object: Object,
    /// Sample the mid-plane of the answer (off for the grasps of a search,
    /// which only need their verdict and forces: the contact is exact on
    /// the continuous mid-plane).
    pub(super) shape: bool,
}

/// The shape of the object a grasp touches at the tip, for the check that
/// it touches the finger nowhere else.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Object {
    /// A flat face through the tip, normal to the contact direction `n`
    /// (a cuboid's side at grasping angle 0), running from the contact
    /// along `t = (-sin b, cos b)` (down, at b = 0): the object is the
    /// region inside the face and below the contact, whose edge the tip
    /// holds; the fingers come from the palm above it.
    Face,
    /// A sphere centred on the gripper axis through the tip.
    Sphere,
}

impl Gripper {
    /// Builds a gripper from a finger: solves the unloaded finger at zero
    /// pressure (the reference state), computes `l0`, the palm and the
    /// overlap, and validates the design. A mounting angle outside (0, pi)
    /// is an error; outside the design space, a warning, as is a palm wider
    /// than `2 l0`. The finger's own warnings come first.
    pub fn new(finger: Finger, params: GripperParams) -> Result<Gripper, SolveError> {
        let a = finite(crate::Field::GripperMountingAngle, params.mounting_angle)?;
        require(
            a > 0.0 && a < PI,
            crate::Field::GripperMountingAngle,
            a,
            || {
                "must lie in (0, pi) rad, i.e. (0, 180) degrees: the finger points away from the palm"
                .into()
            },
        )?;
        positive(crate::Field::GripperMu, params.mu)?;
        require(
            (1..=MAX_FINGERS).contains(&params.fingers),
            crate::Field::GripperFingers,
            params.fingers as f64,
            || format!("must lie in [1, {MAX_FINGERS}]"),
        )?;
        if finger.is_empty() {
            return Err(InputError::Inconsistent {
                field: crate::Field::GripperFinger,
                rule: "the finger has no elements".into(),
            }
            .into());
        }
        let lx = finger.length();
        let opts = SolveOptions {
            samples_per_element: GRIPPER_SAMPLES_PER_ELEMENT,
            ..SolveOptions::default()
        };
        let reference = finger.solve(&Load::unloaded(), &opts)?;
        let reference_curvature = finger.curvatures(&reference.coefficients, CURVATURE_SAMPLES)?;
        // D6: the largest inward reach over the whole mid-plane (the root
        // itself reaches 0)
        let (s, c) = a.sin_cos();
        let (mut innermost, mut l0) = (0, 0.0);
        for (i, p) in reference.points.iter().enumerate() {
            let reach = -(p[0] * c + p[1] * s);
            if reach > l0 {
                (innermost, l0) = (i, reach);
            }
        }
        let (palm, overlap) = match params.geometry {
            PalmSpec::Overlap(g) => {
                finite(crate::Field::GripperOverlap, g)?;
                require(
                    g >= -MAX_DIMENSION_MM,
                    crate::Field::GripperOverlap,
                    g,
                    || {
                        format!("must be at least -{MAX_DIMENSION_MM} mm (below it the palm is over 200 m across and the grasp's scales overflow)")
                    },
                )?;
                require(g <= l0, crate::Field::GripperOverlap, g, || {
                    format!("must not exceed the finger's inward reach l0 = {l0:.6} mm (the palm diameter 2 (l0 - g) would be negative)")
                })?;
                (2.0 * (l0 - g), g)
            }
            PalmSpec::Palm(l) => {
                finite(crate::Field::GripperPalm, l)?;
                require(l >= 0.0, crate::Field::GripperPalm, l, || {
                    "must not be negative".into()
                })?;
                require(l <= MAX_DIMENSION_MM, crate::Field::GripperPalm, l, || {
                    format!("must be at most {MAX_DIMENSION_MM} mm (beyond it the grasp's scales overflow)")
                })?;
                (l, l0 - 0.5 * l)
            }
        };
        // the fingers' roots sit on the palm's circle, 2 pi / n apart: the
        // chord between neighbours must hold a finger's width
        let (n, width) = (params.fingers, finger.width());
        if n >= 3 {
            let chord = palm * (PI / n as f64).sin();
            require(
                chord >= width,
                crate::Field::GripperFingers,
                n as f64,
                || {
                    format!(
                    "do not fit around the palm: {n} fingers {width:.2} mm wide need a palm of at least {:.2} mm (neighbouring roots {chord:.2} mm apart on a palm of {palm:.2} mm)",
                    width / (PI / n as f64).sin()
                )
                },
            )?;
        }
        let mut warnings = finger.warnings().to_vec();
        let [lo, hi] = design_space(params.mu);
        if a < lo || a > hi {
            warnings.push(Warning::MountingAngleOutsideDesignSpace { angle: a, lo, hi });
        }
        if palm > 2.0 * l0 {
            warnings.push(Warning::PalmGapAtRest { palm, reach: l0 });
        }
        Ok(Gripper {
            finger,
            params,
            lx,
            reference,
            reference_curvature,
            l0,
            innermost,
            palm,
            overlap,
            warnings,
            stability: true,
            built_from: None,
        })
    }

    /// The same gripper, judging (or not) the stability of every grasp's
    /// equilibrium (on by default): `Solution::negative_eigenvalues` counts
    /// the negative eigenvalues of the Hessian restricted to the grasp
    /// constraint (the object holds the tip's position), from one extra
    /// O(N) factorisation, and a grasp with any is invalid
    /// ([`Invalid::Unstable`]). Off, grasps are not judged on stability.
    pub fn with_stability(mut self, on: bool) -> Gripper {
        self.stability = on;
        self
    }

    /// The paper's actuator at prestrain `eps0` in `n` equal elements.
    pub fn paper(eps0: f64, n: usize, params: GripperParams) -> Result<Gripper, SolveError> {
        let act = Actuator::paper(eps0)?;
        Gripper::from_actuator(&act, &Partition::equal(act.geometry().lx, n)?, params)
    }

    /// An actuator split by a partition (ribs on, the default element model).
    pub fn from_actuator(
        actuator: &Actuator,
        partition: &Partition,
        params: GripperParams,
    ) -> Result<Gripper, SolveError> {
        Gripper::new(Finger::new(actuator, partition, true), params)
    }
    /// The finger.
    pub fn finger(&self) -> &Finger {
        &self.finger
    }

    /// The design.
    pub fn params(&self) -> &GripperParams {
        &self.params
    }

    /// Mounting angle `a` (rad).
    pub fn mounting_angle(&self) -> f64 {
        self.params.mounting_angle
    }

    /// Friction coefficient.
    pub fn mu(&self) -> f64 {
        self.params.mu
    }

    /// Non-fatal notes about the finger and the design.
    pub fn warnings(&self) -> &[Warning] {
        &self.warnings
    }

    /// The unloaded finger at zero pressure (mid-plane sampled with
    /// [`GRIPPER_SAMPLES_PER_ELEMENT`] points per element).
    pub fn reference(&self) -> &Solution {
        &self.reference
    }

    /// The finger's modelled length `Lx` (mm).
    pub fn length(&self) -> f64 {
        self.lx
    }

    /// `l0`: the largest inward reach of the reference mid-plane from the
    /// root (mm, decision D6).
    pub fn l0(&self) -> f64 {
        self.l0
    }

    /// Index of the reference sample that reaches furthest inwards (the
    /// last sample is the tip).
    pub fn innermost_point(&self) -> usize {
        self.innermost
    }

    /// True when the tip is the innermost reference point (then the
    /// grasping size `d` is the gap between the tips).
    pub fn tip_is_innermost(&self) -> bool {
        let tip_reach = self.reach(self.reference.tip);
        tip_reach >= self.l0 - 1e-9 * (1.0 + self.l0)
    }

    /// Palm diameter `l` (mm).
    pub fn palm(&self) -> f64 {
        self.palm
    }

    /// Overlap `g = l0 - l/2` (mm).
    pub fn overlap(&self) -> f64 {
        self.overlap
    }

    /// `d_min = max(0, l - 2 l0)` (mm).
    pub fn d_min(&self) -> f64 {
        (self.palm - 2.0 * self.l0).max(0.0)
    }

    /// `d_max = l + 2 Lx cos a`: the fingers pressed flat (mm).
    pub fn d_max(&self) -> f64 {
        self.palm + 2.0 * self.lx * self.params.mounting_angle.cos()
    }

    /// Largest sphere radius, `(l/2 + Lx cos a) / sin a` (mm).
    pub fn r_max(&self) -> f64 {
        (0.5 * self.palm + self.lx * self.params.mounting_angle.cos())
            / self.params.mounting_angle.sin()
    }

    /// The grasping size at rest, `-2 g = l - 2 l0` (mm).
    pub fn rest_size(&self) -> f64 {
        -2.0 * self.overlap
    }

    /// Inward reach of a finger-frame point from the root (mm).
    pub(super) fn reach(&self, p: [f64; 2]) -> f64 {
        let (s, c) = self.params.mounting_angle.sin_cos();
        -(p[0] * c + p[1] * s)
    }

    /// A finger-frame point in the gripper frame.
    pub fn to_gripper(&self, p: [f64; 2]) -> [f64; 2] {
        finger_point_to_gripper(p, self.params.mounting_angle, self.palm)
    }

    /// The reference mid-plane in the gripper frame.
    pub fn rest_shape(&self) -> Vec<[f64; 2]> {
        self.reference
            .points
            .iter()
            .map(|&p| self.to_gripper(p))
            .collect()
    }

    /// Grasping size `d = 2 (dXg - g)` of a finger-frame tip position.
    pub fn size_of(&self, tip: [f64; 2]) -> f64 {
        let r = self.reference.tip;
        let d = finger_displacement_to_gripper(
            [tip[0] - r[0], tip[1] - r[1]],
            self.params.mounting_angle,
        );
        2.0 * (d[0] - self.overlap)
    }

    /// The tip Xg that gives grasping size `d`.
    pub(super) fn tip_xg_for_size(&self, d: f64) -> f64 {
        self.to_gripper(self.reference.tip)[0] + 0.5 * d + self.overlap
    }

    /// True in strict mode (reversed grasps are invalid).
    pub fn is_strict(&self) -> bool {
        self.params.strict
    }
}

impl serde::Serialize for Gripper {
    /// The design and the geometry its reference state fixes.
    fn serialize<S: serde::Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        use serde::ser::SerializeMap;
        let mut m = s.serialize_map(None)?;
        m.serialize_entry("params", &self.params)?;
        m.serialize_entry("model", self.finger.model().name())?;
        m.serialize_entry("elements", &self.finger.len())?;
        m.serialize_entry("l0_mm", &self.l0)?;
        m.serialize_entry("palm_mm", &self.palm)?;
        m.serialize_entry("overlap_mm", &self.overlap)?;
        m.serialize_entry("d_min_mm", &self.d_min())?;
        m.serialize_entry("d_max_mm", &self.d_max())?;
        m.serialize_entry("r_max_mm", &self.r_max())?;
        m.serialize_entry("tip_is_innermost", &self.tip_is_innermost())?;
        m.serialize_entry("rest_tip_gripper_mm", &self.to_gripper(self.reference.tip))?;
        m.serialize_entry("warnings", &self.warnings)?;
        m.end()
    }
}

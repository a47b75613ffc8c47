//! The soft gripper built from identical, synchronised fingers (docs/model.md
//! section 3): frames, the geometry fixed by the unloaded finger, grasp
//! measures, validity of sphere grasps, and direct target solves.
//!
//! Frames. The gripper frame (Xg, Zg) has its origin at the palm centre, Xg
//! out towards this finger's root and Zg down. The finger's root sits at
//! `(l/2, 0)`, its X axis is `(cos a, sin a)` and its Z axis
//! `(sin a, -cos a)`. The object pushes on the tip with a normal force `F`
//! along `n = (cos b, sin b)` and friction `f` along `t = (-sin b, cos b)`.
//!
//! Target solves. Every grasp here is one bordered solve
//! ([`Solver::solve_target`]): the tip load is affine in one unknown
//! `lambda`, the target fixes the tip's Xg. A cold solve starts from the
//! reference state (zero pressure, no load) and follows a homotopy from the
//! reference problem to the requested one; a warm solve follows from the
//! problem of a previous [`Grasp`]. Along a sweep, pass the previous point.
//!
//! Sphere contact. The sphere touches the tip with its surface normal `n`,
//! so its centre is `tip - r n`; on the gripper axis (`Xg = 0`) that gives
//! `r cos b = tip Xg`, i.e. `2 r cos b` = the gap between the tips. The
//! paper writes `2 r cos b = d`; the two agree whenever the tip is the
//! finger's innermost point at rest (every `eps0 <= 0.25` finger of the
//! paper; not the `eps0 = 0.4` one, whose curl passes its innermost point).
//! The physical contact is used here, so the centre is always on the axis.

use std::f64::consts::FRAC_PI_2;

use crate::actuator::Actuator;
use crate::blocks::Partition;
use crate::error::{finite, positive, require, InputError, SolveError, Warning};
use crate::finger::{Coefficients, Finger, Load, Solution, SolveOptions, Solver, TargetProblem};

/// Mid-plane samples per element for the reference state (l0 is the
/// largest inward reach over all of them) and for grasp shapes.
pub const GRIPPER_SAMPLES_PER_ELEMENT: usize = 32;

/// Target residual of the grasp solves (mm).
const TARGET_TOL_MM: f64 = 1e-9;

/// The smallest homotopy step (as a fraction of the whole path) before a
/// target solve gives up.
const MIN_HOMOTOPY_STEP: f64 = 1.0 / 512.0;

/// Solves a homotopy may attempt before it gives up (a target beyond the
/// reachable set, approached asymptotically, would otherwise cost many
/// ever smaller steps).
const MAX_HOMOTOPY_ATTEMPTS: usize = 16;

/// Newton iteration budget of the intermediate homotopy solves.
const MAX_INTERMEDIATE_ITERATIONS: usize = 30;

/// How the palm is specified.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum PalmSpec {
    /// Overlap `g = l0 - l/2` (mm) between the fingers at rest; the palm
    /// diameter follows as `l = 2 (l0 - g)`.
    Overlap(f64),
    /// Palm diameter `l` (mm); the overlap follows as `g = l0 - l/2`.
    Palm(f64),
}

/// A gripper's design.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GripperParams {
    /// Mounting angle `a` between the palm plane and the finger's root
    /// tangent (rad); the design space is `[arccot mu, pi/2]`.
    pub mounting_angle: f64,
    /// Palm diameter or overlap.
    pub geometry: PalmSpec,
    /// Number of fingers (informational: the fingers are synchronised,
    /// one is analysed).
    pub fingers: usize,
    /// Friction coefficient between object and finger tip.
    pub mu: f64,
}

impl Default for GripperParams {
    /// The gripper of the paper's Sec. 5: `a = pi/3`, overlap 20 mm, three
    /// fingers, `mu = 0.6`.
    fn default() -> GripperParams {
        GripperParams {
            mounting_angle: std::f64::consts::FRAC_PI_3,
            geometry: PalmSpec::Overlap(20.0),
            fingers: 3,
            mu: 0.6,
        }
    }
}

// ------------------------------------------------------------ transforms

/// A finger-frame point `(X, Z)` in the gripper frame, for mounting angle
/// `a` and palm diameter `palm`: `Xg = l/2 + X cos a + Z sin a`,
/// `Zg = X sin a - Z cos a`.
pub fn finger_point_to_gripper(p: [f64; 2], a: f64, palm: f64) -> [f64; 2] {
    let (s, c) = a.sin_cos();
    [0.5 * palm + p[0] * c + p[1] * s, p[0] * s - p[1] * c]
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

// ------------------------------------------------------------ results

/// An equilibrium of a grasp with its load and measures.
#[derive(Debug, Clone, PartialEq)]
pub struct Grasp {
    /// Channel pressure (kPa).
    pub pressure_kpa: f64,
    /// Grasping angle `b` (rad).
    pub beta: f64,
    /// Normal force `F` on the finger (N).
    pub normal: f64,
    /// Friction `f` on the finger, positive along `t` (N).
    pub friction: f64,
    /// Lifting force `f_v = f cos b + F sin b` (N).
    pub lift: f64,
    /// Grasping size `d = 2 (dXg - g)` (mm), the paper's measure.
    pub size: f64,
    /// Gap between the tips, `2 tip Xg` (mm); equals `size` when the tip
    /// is the innermost point at rest.
    pub tip_gap: f64,
    /// Finger height `h`: the tip's Zg (mm).
    pub height: f64,
    /// Tip in the gripper frame (mm).
    pub tip: [f64; 2],
    /// The tip load in the finger frame.
    pub load: Load,
    /// The bordered problem solved (warm starts follow from it).
    pub problem: TargetProblem,
    /// Its load parameter at the solution.
    pub lambda: f64,
    /// The finger's equilibrium (mid-plane samples in the finger frame).
    pub solution: Solution,
}

impl Grasp {
    /// True when `F >= 0` and `0 <= f <= mu F` (to rounding).
    pub fn friction_ok(&self, mu: f64) -> bool {
        let tol = 1e-12 * (1.0 + self.normal.abs());
        self.normal >= -tol && self.friction >= -tol && self.friction <= mu * self.normal + tol
    }
}

/// Why a sphere grasp is not valid.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Invalid {
    /// The fingers are not open: the grasping size or the tip gap is not
    /// positive.
    NotOpen { size: f64, tip_gap: f64 },
    /// The object would pull on the finger (`F < 0`).
    NegativeNormal { normal: f64 },
    /// The friction needed lies outside `[0, mu F]`.
    FrictionCone { friction: f64, limit: f64 },
    /// The sphere crosses the finger's mid-plane at sample `point` (root =
    /// 0), `depth` mm inside its surface: a second contact.
    SecondContact { point: usize, depth: f64 },
}

/// A sphere centred on the gripper axis touching the tip.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereContact {
    /// Radius `r = tip Xg / cos b` (mm); 0 when the fingers are not open.
    pub radius: f64,
    /// Centre in the gripper frame, `tip - r n` (mm).
    pub center: [f64; 2],
    /// The first geometric violation (not open, second contact), if any.
    pub invalid: Option<Invalid>,
}

/// A sphere grasp: the equilibrium and its validity.
#[derive(Debug, Clone, PartialEq)]
pub struct SphereGrasp {
    /// Radius (mm).
    pub radius: f64,
    /// Sphere centre in the gripper frame (mm).
    pub center: [f64; 2],
    /// The equilibrium.
    pub grasp: Grasp,
    /// The first violation found (geometry, then `F >= 0`, then friction).
    pub invalid: Option<Invalid>,
}

impl SphereGrasp {
    /// True when no rule is violated.
    pub fn is_valid(&self) -> bool {
        self.invalid.is_none()
    }
}

/// The largest lifting force that holds a sphere (full friction, best
/// grasping angle).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SphereLift {
    /// Sphere radius (mm).
    pub radius: f64,
    /// The grasping angle that gives it (rad).
    pub beta: f64,
    /// Lifting force per finger (N).
    pub lift: f64,
    /// Normal force there (N).
    pub normal: f64,
}

/// One grasping angle of a [`ViableAngles`] scan.
#[derive(Debug, Clone, PartialEq)]
pub struct AngleSample {
    /// Grasping angle (rad).
    pub beta: f64,
    /// Normal force `F` (N); 0 when the solve failed or was skipped.
    pub normal: f64,
    /// Friction `f` (N); 0 when the solve failed or was skipped.
    pub friction: f64,
    /// True for a valid grasp with `0 <= f <= mu F`.
    pub viable: bool,
    /// Why not viable (`None` when viable, or when the solve failed).
    pub invalid: Option<Invalid>,
    /// The solve failure, if any.
    pub failure: Option<String>,
}

/// The grasping angles that hold a sphere of radius `r` with lifting force
/// `f_v` per finger.
#[derive(Debug, Clone, PartialEq)]
pub struct ViableAngles {
    /// Sphere radius (mm).
    pub radius: f64,
    /// Lifting force per finger (N).
    pub lift: f64,
    /// Viable intervals `[lo, hi]` (rad), boundaries refined by bisection.
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

// ------------------------------------------------------------ the gripper

/// A gripper: the finger, its reference (unloaded, zero-pressure) state,
/// and the geometry that state fixes.
#[derive(Debug, Clone)]
pub struct Gripper {
    finger: Finger,
    params: GripperParams,
    lx: f64,
    reference: Solution,
    l0: f64,
    innermost: usize,
    palm: f64,
    overlap: f64,
    warnings: Vec<Warning>,
    stability: bool,
}

/// How the tip load depends on `lambda`, in the gripper frame.
struct Scene {
    pressure_kpa: f64,
    beta: f64,
    /// Fixed gripper-frame force (N).
    base: [f64; 2],
    /// Gripper-frame force per unit `lambda` (N).
    direction: [f64; 2],
    /// Target tip Xg (mm).
    tip_xg: f64,
}

impl Gripper {
    /// Builds a gripper from a finger: solves the unloaded finger at zero
    /// pressure (the reference state), computes `l0`, the palm and the
    /// overlap, and validates the design. A mounting angle outside the
    /// design space and a palm wider than `2 l0` are warnings.
    pub fn new(finger: Finger, params: GripperParams) -> Result<Gripper, SolveError> {
        let a = finite("gripper.mounting_angle", params.mounting_angle)?;
        positive("gripper.mu", params.mu)?;
        require(
            params.fingers >= 1,
            "gripper.fingers",
            params.fingers as f64,
            "must be at least 1".into(),
        )?;
        if finger.is_empty() {
            return Err(InputError::Inconsistent {
                field: "gripper.finger".into(),
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
                finite("gripper.overlap", g)?;
                require(
                    g <= l0,
                    "gripper.overlap",
                    g,
                    format!("must not exceed the finger's inward reach l0 = {l0} mm (the palm diameter 2 (l0 - g) would be negative)"),
                )?;
                (2.0 * (l0 - g), g)
            }
            PalmSpec::Palm(l) => {
                finite("gripper.palm", l)?;
                require(l >= 0.0, "gripper.palm", l, "must not be negative".into())?;
                (l, l0 - 0.5 * l)
            }
        };
        let mut warnings = Vec::new();
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
            l0,
            innermost,
            palm,
            overlap,
            warnings,
            stability: false,
        })
    }

    /// The same gripper, computing (or not) the smallest Hessian
    /// eigenvalue of every grasp's equilibrium (`Solution::min_hessian_eig`;
    /// off by default: it costs more than the solve itself). The Hessian is
    /// that of the finger under the fixed load; a grasp holds the tip's
    /// position, so an indefinite Hessian does not by itself make a grasp
    /// unstable.
    pub fn with_stability(mut self, on: bool) -> Gripper {
        self.stability = on;
        self
    }

    /// The paper's actuator at prestrain `eps0` in `n` equal elements (the
    /// actuator's warnings come first in [`Gripper::warnings`]).
    pub fn paper(eps0: f64, n: usize, params: GripperParams) -> Result<Gripper, SolveError> {
        let act = Actuator::paper(eps0)?;
        Gripper::from_actuator(&act, &Partition::equal(act.geometry().lx, n)?, params)
    }

    /// An actuator split by a partition (ribs on). The actuator's warnings
    /// (a prestrain outside the fitted range, ...) come first in
    /// [`Gripper::warnings`].
    pub fn from_actuator(
        actuator: &Actuator,
        partition: &Partition,
        params: GripperParams,
    ) -> Result<Gripper, SolveError> {
        let mut g = Gripper::new(Finger::new(actuator, partition, true), params)?;
        g.warnings.splice(0..0, actuator.warnings().iter().cloned());
        Ok(g)
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

    /// Non-fatal notes about the design (and, for a gripper built by
    /// [`Gripper::paper`] or [`Gripper::from_actuator`], the actuator).
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
    fn reach(&self, p: [f64; 2]) -> f64 {
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
    fn tip_xg_for_size(&self, d: f64) -> f64 {
        self.to_gripper(self.reference.tip)[0] + 0.5 * d + self.overlap
    }

    /// The grasp measures of `solution`, the equilibrium of `problem` (built
    /// from `scene`) at load parameter `lambda`.
    fn grasp_from(
        &self,
        solution: Solution,
        scene: &Scene,
        problem: TargetProblem,
        lambda: f64,
    ) -> Grasp {
        let force = [
            scene.base[0] + lambda * scene.direction[0],
            scene.base[1] + lambda * scene.direction[1],
        ];
        let (normal, friction) = gripper_force_to_contact(force, scene.beta);
        let tip = self.to_gripper(solution.tip);
        Grasp {
            pressure_kpa: scene.pressure_kpa,
            beta: scene.beta,
            normal,
            friction,
            lift: force[1],
            size: self.size_of(solution.tip),
            tip_gap: 2.0 * tip[0],
            height: tip[1],
            tip,
            load: problem.load_at(lambda),
            problem,
            lambda,
            solution,
        }
    }

    fn problem(&self, scene: &Scene) -> TargetProblem {
        let a = self.params.mounting_angle;
        let base = gripper_force_to_finger(scene.base, a);
        let (s, c) = a.sin_cos();
        TargetProblem {
            base: Load::unloaded()
                .with_pressure_kpa(scene.pressure_kpa)
                .with_tip_force(base[0], base[1]),
            direction: gripper_force_to_finger(scene.direction, a),
            // tip Xg = l/2 + X cos a + Z sin a
            weights: [c, s],
            target: scene.tip_xg - 0.5 * self.palm,
        }
    }

    fn solve_scene(&self, scene: &Scene, warm: Option<&Grasp>) -> Result<Grasp, SolveError> {
        finite("grasp.pressure_kpa", scene.pressure_kpa)?;
        let problem = self.problem(scene);
        let mut solver = Solver::new(&self.finger);
        let opts = SolveOptions {
            samples_per_element: GRIPPER_SAMPLES_PER_ELEMENT,
            stability: self.stability,
            ..SolveOptions::default()
        };
        let (sol, lambda) = match warm {
            Some(w) => follow(
                &mut solver,
                &w.solution.coefficients,
                w.lambda,
                &w.problem,
                &problem,
                &opts,
            )?,
            None => {
                let start = TargetProblem {
                    base: Load::unloaded(),
                    target: problem.weights[0] * self.reference.tip[0]
                        + problem.weights[1] * self.reference.tip[1],
                    ..problem
                };
                follow(
                    &mut solver,
                    &self.reference.coefficients,
                    0.0,
                    &start,
                    &problem,
                    &opts,
                )?
            }
        };
        Ok(self.grasp_from(sol, scene, problem, lambda))
    }

    /// (a) The normal force `F` that gives grasping size `d` at grasping
    /// angle `beta` with full friction `f = mu F`, at a channel pressure.
    /// `warm`: a nearby grasp to start from (the previous point of a sweep).
    pub fn grasp_load_for_size(
        &self,
        pressure_kpa: f64,
        d: f64,
        beta: f64,
        warm: Option<&Grasp>,
    ) -> Result<Grasp, SolveError> {
        finite("grasp.size", d)?;
        check_beta(beta)?;
        let direction = contact_force_to_gripper(1.0, self.params.mu, beta);
        self.solve_scene(
            &Scene {
                pressure_kpa,
                beta,
                base: [0.0, 0.0],
                direction,
                tip_xg: self.tip_xg_for_size(d),
            },
            warm,
        )
    }

    /// (b) Force control by pressure: at `pressure_kpa`, the normal force
    /// `F` (grasping angle 0, friction `f` given) that holds a cuboid of
    /// size `d`; the grasp's `height` is the finger height `h`.
    pub fn force_control(
        &self,
        pressure_kpa: f64,
        d: f64,
        friction: f64,
        warm: Option<&Grasp>,
    ) -> Result<Grasp, SolveError> {
        finite("grasp.size", d)?;
        finite("grasp.friction", friction)?;
        self.solve_scene(
            &Scene {
                pressure_kpa,
                beta: 0.0,
                base: [0.0, friction],
                direction: [1.0, 0.0],
                tip_xg: self.tip_xg_for_size(d),
            },
            warm,
        )
    }

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
        check_sphere(r, beta)?;
        finite("sphere.lift", lift)?;
        let grasp = self.solve_scene(
            &Scene {
                pressure_kpa,
                beta,
                base: [0.0, lift],
                direction: [1.0, 0.0],
                tip_xg: r * beta.cos(),
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
        check_sphere(r, beta)?;
        let grasp = self.solve_scene(
            &Scene {
                pressure_kpa,
                beta,
                base: [0.0, 0.0],
                direction: contact_force_to_gripper(1.0, self.params.mu, beta),
                tip_xg: r * beta.cos(),
            },
            warm,
        )?;
        Ok(self.sphere_result(grasp))
    }

    fn sphere_result(&self, grasp: Grasp) -> SphereGrasp {
        let contact = self.sphere_contact(&grasp.solution, grasp.beta);
        let invalid = contact.invalid.or_else(|| self.force_violation(&grasp));
        SphereGrasp {
            radius: contact.radius,
            center: contact.center,
            grasp,
            invalid,
        }
    }

    /// The largest lifting force per finger that holds a sphere of radius
    /// `r` validly, over the grasping angles in `[-arctan mu, pi/2)`: a scan
    /// of `samples` angles (at least 4) with full friction, each warm-started
    /// from the previous and stopped where that branch of equilibria is
    /// lost, then two rounds of refinement around the best valid angle. `None` when no scanned
    /// angle gives a valid grasp.
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
                    },
                    sg.grasp,
                ));
            }
        };
        let step = (hi - lo) / samples as f64;
        let mut warm: Option<Grasp> = None;
        for i in 0..samples {
            let beta = lo + step * i as f64;
            match self.sphere_grasp_at_friction_limit(pressure_kpa, r, beta, warm.as_ref()) {
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
        // refine: subdivide the bracket around the best angle twice
        let mut width = step;
        for _ in 0..2 {
            let Some((b, g)) = &best else { break };
            let (centre, start) = (b.beta, g.clone());
            let (a, z) = ((centre - width).max(lo), (centre + width).min(hi - 1e-9));
            const SUB: usize = 8;
            for j in 1..SUB {
                let beta = a + (z - a) * j as f64 / SUB as f64;
                if let Ok(sg) =
                    self.sphere_grasp_at_friction_limit(pressure_kpa, r, beta, Some(&start))
                {
                    consider(sg, &mut best);
                }
            }
            width = (z - a) / SUB as f64;
        }
        Ok(best.map(|(b, _)| b))
    }

    fn force_violation(&self, g: &Grasp) -> Option<Invalid> {
        let tol = 1e-12 * (1.0 + g.normal.abs());
        if g.normal < -tol {
            return Some(Invalid::NegativeNormal { normal: g.normal });
        }
        if !g.friction_ok(self.params.mu) {
            return Some(Invalid::FrictionCone {
                friction: g.friction,
                limit: self.params.mu * g.normal,
            });
        }
        None
    }

    /// The sphere centred on the gripper axis that touches the tip of
    /// `solution` with contact normal `n = (cos b, sin b)`, and its
    /// geometric validity: not open when `d <= 0` or the tip gap is not
    /// positive (or `cos b <= 0`); a second contact when any mid-plane
    /// sample lies inside the sphere by more than a tolerance (`1e-6 (r +
    /// Lx)`). A tip-only solution is sampled here from its coefficients
    /// ([`GRIPPER_SAMPLES_PER_ELEMENT`] per element).
    pub fn sphere_contact(&self, solution: &Solution, beta: f64) -> SphereContact {
        let tip = self.to_gripper(solution.tip);
        let size = self.size_of(solution.tip);
        let tip_gap = 2.0 * tip[0];
        let (s, c) = beta.sin_cos();
        if !(size > 0.0 && tip_gap > 0.0 && c > 0.0 && beta.is_finite()) {
            return SphereContact {
                radius: 0.0,
                center: tip,
                invalid: Some(Invalid::NotOpen { size, tip_gap }),
            };
        }
        let r = tip[0] / c;
        let center = [tip[0] - r * c, tip[1] - r * s];
        let tol = 1e-6 * (r + self.lx);
        let sampled;
        let points = if solution.points.is_empty() {
            sampled = self
                .finger
                .shape(&solution.coefficients, GRIPPER_SAMPLES_PER_ELEMENT)
                .unwrap_or_default();
            &sampled
        } else {
            &solution.points
        };
        let mut worst: Option<(usize, f64)> = None;
        for (i, p) in points.iter().enumerate() {
            let q = self.to_gripper(*p);
            let depth = r - (q[0] - center[0]).hypot(q[1] - center[1]);
            if depth > tol && worst.is_none_or(|(_, w)| depth > w) {
                worst = Some((i, depth));
            }
        }
        SphereContact {
            radius: r,
            center,
            invalid: worst.map(|(point, depth)| Invalid::SecondContact { point, depth }),
        }
    }

    /// (c) The grasping angles in `[-arctan mu, pi/2)` at which a sphere of
    /// radius `r` is held validly with lifting force `lift` per finger
    /// (some `F` with `0 <= f <= mu F`). Scans `samples` angles (at least
    /// 4), then bisects each boundary to `1e-6` rad. Failed solves count as
    /// not viable and are recorded in the scan.
    pub fn viable_angle_range(
        &self,
        pressure_kpa: f64,
        r: f64,
        lift: f64,
        samples: usize,
    ) -> Result<ViableAngles, SolveError> {
        finite("sphere.lift", lift)?;
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
        match self.sphere_grasp(pressure_kpa, r, lift, beta, warm) {
            Ok(sg) => (
                AngleSample {
                    beta,
                    normal: sg.grasp.normal,
                    friction: sg.grasp.friction,
                    viable: sg.is_valid(),
                    invalid: sg.invalid,
                    failure: None,
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
        while (bad - good).abs() > 1e-6 {
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

fn check_beta(beta: f64) -> Result<(), InputError> {
    finite("grasp.beta", beta)?;
    require(
        beta.abs() <= FRAC_PI_2,
        "grasp.beta",
        beta,
        "must lie in [-pi/2, pi/2]".into(),
    )
}

/// A sphere's radius and grasping angle: positive radius, angle strictly
/// inside (-pi/2, pi/2) (the contact must not be at a pole).
fn check_sphere(r: f64, beta: f64) -> Result<(), InputError> {
    positive("sphere.radius", r)?;
    check_beta(beta)?;
    require(
        beta.abs() < FRAC_PI_2,
        "sphere.beta",
        beta,
        "must lie in (-pi/2, pi/2)".into(),
    )
}

/// The inputs of an angle scan over a sphere: pressure, radius, samples.
fn check_scan(pressure_kpa: f64, r: f64, samples: usize) -> Result<(), InputError> {
    positive("sphere.radius", r)?;
    finite("grasp.pressure_kpa", pressure_kpa)?;
    require(
        samples >= 4,
        "sphere.samples",
        samples as f64,
        "must be at least 4".into(),
    )
}

/// Solves `p1` from a state `(k0, lambda0)` that solves `p0`, following the
/// straight homotopy between the two problems with adaptive steps
/// (halved on failure, doubled after success) and a secant predictor
/// through the last two accepted states. Intermediate states are
/// tip-only; the final solve uses `opts`. Gives up after
/// [`MAX_HOMOTOPY_ATTEMPTS`] solves or below [`MIN_HOMOTOPY_STEP`].
pub(crate) fn follow(
    solver: &mut Solver<'_>,
    k0: &Coefficients,
    lambda0: f64,
    p0: &TargetProblem,
    p1: &TargetProblem,
    opts: &SolveOptions,
) -> Result<(Solution, f64), SolveError> {
    // intermediate states: tip only, and a tighter iteration budget (from
    // a nearby state Newton converges in a handful of iterations)
    let tip_only = SolveOptions {
        max_iter: opts.max_iter.min(MAX_INTERMEDIATE_ITERATIONS),
        ..opts.tip_only()
    };
    // the last accepted state (t1, k1, l1) and the one before it (t0, k0, l0)
    let mut k1 = k0.clone();
    let mut l1 = lambda0;
    let mut t1 = 0.0;
    let mut prev: Option<(f64, Coefficients, f64)> = None;
    let mut guess = k1.clone();
    let mut h = 1.0;
    let mut attempt = 0;
    loop {
        attempt += 1;
        let tn = if t1 + h >= 1.0 - 1e-12 { 1.0 } else { t1 + h };
        let last = tn == 1.0;
        let p = if last { *p1 } else { p0.lerp(p1, tn) };
        // secant predictor through the last two accepted states
        let mut lguess = l1;
        guess.clone_from(&k1);
        if let Some((t0, k0, l0)) = &prev {
            let w = (tn - t1) / (t1 - t0);
            lguess = l1 + w * (l1 - l0);
            for ((g, a), b) in guess
                .as_mut_slice()
                .iter_mut()
                .zip(k1.as_slice())
                .zip(k0.as_slice())
            {
                *g = a + w * (a - b);
            }
            if !lguess.is_finite() || guess.as_slice().iter().any(|v| !v.is_finite()) {
                lguess = l1;
                guess.clone_from(&k1);
            }
        }
        let o = if last { opts } else { &tip_only };
        match solver.solve_target(&p, &guess, lguess, TARGET_TOL_MM, o) {
            Ok((sol, l)) => {
                if last {
                    return Ok((sol, l));
                }
                let old = std::mem::replace(&mut k1, sol.coefficients);
                prev = Some((t1, old, l1));
                l1 = l;
                t1 = tn;
                h *= 2.0;
            }
            Err(e) => {
                // an input error of the final problem will not go away
                if last && matches!(e, SolveError::Input(_)) {
                    return Err(e);
                }
                h *= 0.5;
                if h < MIN_HOMOTOPY_STEP || attempt >= MAX_HOMOTOPY_ATTEMPTS {
                    return Err(e);
                }
            }
        }
    }
}

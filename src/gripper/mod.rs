//! The soft gripper built from identical, synchronised fingers (docs/model.md
//! section 5): the geometry fixed by the unloaded finger, grasp measures and
//! direct target solves.
//!
//! - [`frames`]: transforms between the finger and gripper frames, contact
//!   forces;
//! - [`rules`]: when a grasp is valid;
//! - [`sphere`]: spheres touching the tip, the best lifting force and the
//!   viable grasping angles.
//!
//! Target solves. Every grasp here is one bordered solve
//! ([`Solver::solve_target`]): the tip load is affine in one unknown
//! `lambda`, the target fixes the tip's Xg. A cold solve starts from the
//! reference state (zero pressure, no load) and follows a homotopy from the
//! reference problem to the requested one; a warm solve follows from the
//! problem of a previous [`Grasp`]. Along a sweep, pass the previous point.

pub mod frames;
pub mod rules;
pub mod sphere;
mod tail;

use std::f64::consts::{FRAC_PI_2, PI};

use crate::actuator::Actuator;
use crate::blocks::Partition;
use crate::error::{finite, positive, require, InputError, SolveError, Warning};
use crate::finger::{Coefficients, Finger, Load, Solution, SolveOptions, Solver, TargetProblem};

pub use frames::{
    contact_force_to_finger, contact_force_to_gripper, design_space,
    finger_displacement_to_gripper, finger_point_to_gripper, grasping_angle_range,
    gripper_force_to_contact, gripper_force_to_finger, lifting_force,
};
pub use rules::Invalid;
pub use sphere::{AngleSample, SphereContact, SphereGrasp, SphereLift, ViableAngles};
pub use tail::{SizeTail, SweepEnd, MAX_GRASP_FORCE_N};

/// Mid-plane samples per element for the reference state (l0 is the
/// largest inward reach over all of them) and for grasp shapes.
pub const GRIPPER_SAMPLES_PER_ELEMENT: usize = 32;

/// Curvature samples per element for the reversal check.
const CURVATURE_SAMPLES: usize = 4;

/// Target residual of the grasp solves (mm).
const TARGET_TOL_MM: f64 = 1e-9;

/// The smallest homotopy step (as a fraction of the whole path) before a
/// target solve gives up.
const MIN_HOMOTOPY_STEP: f64 = 1.0 / 512.0;

/// Solves a homotopy may attempt before it gives up (a target beyond the
/// reachable set, approached asymptotically, would otherwise cost many
/// ever smaller steps).
const MAX_HOMOTOPY_ATTEMPTS: usize = 16;

/// The largest homotopy step when a grasp is followed along its path from
/// the rest state (after a direct step landed on an unstable equilibrium).
const PATH_STEP: f64 = 1.0 / 32.0;

/// Newton iteration budget of the intermediate homotopy solves.
const MAX_INTERMEDIATE_ITERATIONS: usize = 30;

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
    /// Number of fingers (informational: the fingers are synchronised,
    /// one is analysed).
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
    /// Where the grasp leaves the model: the finger's findings
    /// ([`Solution::warnings`]) and the grasp's own (`curvature_reversal`,
    /// `beyond_flat`).
    pub warnings: Vec<Warning>,
    /// The first rule the grasp breaks (`None`: valid); see [`rules`].
    pub invalid: Option<Invalid>,
}

impl Grasp {
    /// True when `F >= 0` and `0 <= f <= mu F` (to rounding).
    pub fn friction_ok(&self, mu: f64) -> bool {
        rules::friction_ok(self.normal, self.friction, mu)
    }

    /// True when the grasp breaks no rule.
    pub fn is_valid(&self) -> bool {
        self.invalid.is_none()
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
    finger: Finger,
    params: GripperParams,
    lx: f64,
    reference: Solution,
    /// The reference state's curvature samples (reversal checks).
    reference_curvature: Vec<f64>,
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
    /// The target's field and value, for errors.
    target: (&'static str, f64),
}

impl Gripper {
    /// Builds a gripper from a finger: solves the unloaded finger at zero
    /// pressure (the reference state), computes `l0`, the palm and the
    /// overlap, and validates the design. A mounting angle outside (0, pi)
    /// is an error; outside the design space, a warning, as is a palm wider
    /// than `2 l0`. The finger's own warnings come first.
    pub fn new(finger: Finger, params: GripperParams) -> Result<Gripper, SolveError> {
        let a = finite("gripper.mounting_angle", params.mounting_angle)?;
        require(
            a > 0.0 && a < PI,
            "gripper.mounting_angle",
            a,
            "must lie in (0, pi) rad, i.e. (0, 180) degrees: the finger points away from the palm"
                .into(),
        )?;
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
                finite("gripper.overlap", g)?;
                require(
                    g <= l0,
                    "gripper.overlap",
                    g,
                    format!("must not exceed the finger's inward reach l0 = {l0:.6} mm (the palm diameter 2 (l0 - g) would be negative)"),
                )?;
                (2.0 * (l0 - g), g)
            }
            PalmSpec::Palm(l) => {
                finite("gripper.palm", l)?;
                require(l >= 0.0, "gripper.palm", l, "must not be negative".into())?;
                (l, l0 - 0.5 * l)
            }
        };
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

    /// True in strict mode (reversed grasps are invalid).
    pub fn is_strict(&self) -> bool {
        self.params.strict
    }

    /// The grasp-level findings and the first rule a grasp breaks
    /// (sphere geometry is checked in [`sphere`]).
    fn judge(
        &self,
        solution: &Solution,
        normal: f64,
        friction: f64,
        size: f64,
        tip_gap: f64,
        open: bool,
    ) -> (Vec<Warning>, Option<Invalid>) {
        let mut warnings = solution.warnings.clone();
        let d_max = self.d_max();
        let beyond = rules::flat_rule(size, d_max);
        if beyond.is_some() {
            warnings.push(Warning::BeyondFlat { size, d_max });
        }
        let reversal = self
            .finger
            .curvatures(&solution.coefficients, CURVATURE_SAMPLES)
            .ok()
            .and_then(|k| {
                rules::curvature_reversal(&k, &self.reference_curvature, CURVATURE_SAMPLES)
            });
        let strict_invalid = match (&reversal, self.params.strict) {
            (Some(Warning::CurvatureReversal { element, curvature }), true) => {
                Some(Invalid::CurvatureReversal {
                    element: *element,
                    curvature: *curvature,
                })
            }
            _ => None,
        };
        warnings.extend(reversal);
        let unstable = match solution.negative_eigenvalues {
            Some(negative) if negative > 0 => Some(Invalid::Unstable { negative }),
            _ => None,
        };
        let invalid = open
            .then(|| rules::open_rule(size, tip_gap))
            .flatten()
            .or_else(|| rules::force_rule(normal, friction, self.params.mu))
            .or(beyond)
            .or(unstable)
            .or(strict_invalid);
        (warnings, invalid)
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
        let size = self.size_of(solution.tip);
        let tip_gap = 2.0 * tip[0];
        let (warnings, invalid) = self.judge(&solution, normal, friction, size, tip_gap, true);
        Grasp {
            pressure_kpa: scene.pressure_kpa,
            beta: scene.beta,
            normal,
            friction,
            lift: force[1],
            size,
            tip_gap,
            height: tip[1],
            tip,
            load: problem.load_at(lambda),
            problem,
            lambda,
            solution,
            warnings,
            invalid,
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

    /// A grasp size the fingers can reach: finite and at most `d_max` (a
    /// wider object would need the fingers pressed past flat).
    fn check_size(&self, d: f64) -> Result<(), InputError> {
        finite("grasp.size", d)?;
        let d_max = self.d_max();
        require(
            rules::flat_rule(d, d_max).is_none(),
            "grasp.size",
            d,
            format!("exceeds d_max = {d_max:.3} mm: the fingers would be pressed past flat"),
        )
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
        let followed = match warm {
            Some(w) => follow(
                &mut solver,
                &w.solution.coefficients,
                w.lambda,
                &w.problem,
                &problem,
                &opts,
            ),
            None => {
                let start = TargetProblem {
                    base: Load::unloaded(),
                    target: problem.weights[0] * self.reference.tip[0]
                        + problem.weights[1] * self.reference.tip[1],
                    ..problem
                };
                let direct = follow(
                    &mut solver,
                    &self.reference.coefficients,
                    0.0,
                    &start,
                    &problem,
                    &opts,
                );
                match direct {
                    // a direct step may jump to another branch: follow the
                    // target's path from the rest state in small steps, and
                    // keep the direct answer (reported unstable) only if the
                    // path cannot be followed
                    Ok((ref sol, _)) if sol.negative_eigenvalues.is_some_and(|n| n > 0) => {
                        follow_steps(
                            &mut solver,
                            &self.reference.coefficients,
                            0.0,
                            &start,
                            &problem,
                            &opts,
                            PATH_STEP,
                        )
                        .or(direct)
                    }
                    other => other,
                }
            }
        };
        let (sol, lambda) = followed.map_err(|e| e.for_target(scene.target.0, scene.target.1))?;
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
        self.check_size(d)?;
        check_beta(beta)?;
        let direction = contact_force_to_gripper(1.0, self.params.mu, beta);
        self.solve_scene(
            &Scene {
                pressure_kpa,
                beta,
                base: [0.0, 0.0],
                direction,
                tip_xg: self.tip_xg_for_size(d),
                target: ("grasp.size", d),
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
        self.check_size(d)?;
        finite("grasp.friction", friction)?;
        self.solve_scene(
            &Scene {
                pressure_kpa,
                beta: 0.0,
                base: [0.0, friction],
                direction: [1.0, 0.0],
                tip_xg: self.tip_xg_for_size(d),
                target: ("grasp.friction", friction),
            },
            warm,
        )
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

/// Why a homotopy stopped: how far it got, and the last failure.
#[derive(Debug)]
pub(crate) struct FollowError {
    /// The last accepted homotopy parameter (0 to 1).
    pub reached: f64,
    /// The failure of the step that could not be taken.
    pub error: SolveError,
}

impl FollowError {
    /// The error in the target's terms: input errors stay as they are; a
    /// path that stopped short says which target it did not reach.
    pub fn for_target(self, target: &str, value: f64) -> SolveError {
        match self.error {
            SolveError::Input(_) => self.error,
            e => SolveError::TargetNotReached {
                target: target.to_string(),
                value,
                reached: self.reached,
                detail: e.to_string(),
            },
        }
    }
}

/// Solves `p1` from a state `(k0, lambda0)` that solves `p0`, following the
/// straight homotopy between the two problems with fpc-newton's
/// continuation driver (the state is the coefficients and `lambda`; steps
/// double after each success and halve after a failure, with a secant
/// predictor). Intermediate states are tip-only; the final solve uses
/// `opts`. Gives up after [`MAX_HOMOTOPY_ATTEMPTS`] solves or below
/// [`MIN_HOMOTOPY_STEP`].
pub(crate) fn follow(
    solver: &mut Solver<'_>,
    k0: &Coefficients,
    lambda0: f64,
    p0: &TargetProblem,
    p1: &TargetProblem,
    opts: &SolveOptions,
) -> Result<(Solution, f64), FollowError> {
    follow_steps(solver, k0, lambda0, p0, p1, opts, 1.0)
}

/// [`follow`] with steps of at most `max_step` of the path (and as many
/// more attempts as that takes): a path, where `follow` first tries the
/// whole way in one step.
fn follow_steps(
    solver: &mut Solver<'_>,
    k0: &Coefficients,
    lambda0: f64,
    p0: &TargetProblem,
    p1: &TargetProblem,
    opts: &SolveOptions,
    max_step: f64,
) -> Result<(Solution, f64), FollowError> {
    // intermediate states: tip only, and a tighter iteration budget (from
    // a nearby state Newton converges in a handful of iterations)
    let tip_only = SolveOptions {
        max_iter: opts.max_iter.min(MAX_INTERMEDIATE_ITERATIONS),
        ..opts.tip_only()
    };
    let copts = fpc_newton::ContinuationOptions {
        initial_step: max_step,
        min_step: MIN_HOMOTOPY_STEP,
        max_step,
        grow: 2.0,
        shrink: 0.5,
        // a path of small steps gets the steps it needs on top
        max_steps: MAX_HOMOTOPY_ATTEMPTS
            + if max_step < 1.0 {
                (1.0 / max_step).ceil() as usize
            } else {
                0
            },
        easy_iterations: usize::MAX,
        predictor: true,
    };
    let n = k0.as_slice().len();
    let per = k0.per_element();
    let mut state: Vec<f64> = k0.as_slice().to_vec();
    state.push(lambda0);
    let mut done: Option<Solution> = None;
    let mut last_error: Option<SolveError> = None;
    let mut abort = false;
    let report = fpc_newton::continuation(0.0, 1.0, &mut state, &copts, |t, x| {
        if abort {
            return fpc_newton::Report::empty(fpc_newton::Termination::InvalidInput);
        }
        let last = t == 1.0;
        let p = if last { *p1 } else { p0.lerp(p1, t) };
        let guess = match Coefficients::new(per, x[..n].to_vec()) {
            Ok(g) => g,
            Err(e) => {
                last_error = Some(e.into());
                return fpc_newton::Report::empty(fpc_newton::Termination::InvalidInput);
            }
        };
        let o = if last { opts } else { &tip_only };
        match solver.solve_target(&p, &guess, x[n], TARGET_TOL_MM, o) {
            Ok((sol, l)) => {
                x[..n].copy_from_slice(sol.coefficients.as_slice());
                x[n] = l;
                let mut r = fpc_newton::Report::empty(fpc_newton::Termination::Converged);
                r.iterations = sol.report.iterations;
                if last {
                    done = Some(sol);
                }
                r
            }
            Err(e) => {
                let reason = match &e {
                    SolveError::NotConverged { reason, .. } => *reason,
                    _ => fpc_newton::Termination::InvalidInput,
                };
                // an input error of the final problem will not go away
                abort = last && matches!(e, SolveError::Input(_));
                last_error = Some(e);
                fpc_newton::Report::empty(reason)
            }
        }
    });
    match done {
        Some(sol) if report.complete => {
            let lambda = state[n];
            Ok((sol, lambda))
        }
        _ => Err(FollowError {
            reached: report.reached,
            error: last_error.unwrap_or(SolveError::NotConverged {
                reason: report.last.reason,
                iterations: report.newton_iterations,
                relative_residual: f64::NAN,
                element: None,
                last: k0.clone(),
            }),
        }),
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

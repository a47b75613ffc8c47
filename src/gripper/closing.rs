//! Closing the gripper on an object: a grasp judged (the rules, the
//! finger's findings, stability, the path), the rest state with the fixed
//! tip load applied along its own path, the path in the normal force from
//! rest to the target, and the size and force-control solves built on it.

use fpc_newton::PathTermination;
use std::f64::consts::FRAC_PI_2;

use crate::coefficients::Coefficients;
use crate::error::{finite, require, InputError, Warning};
use crate::field::Field;
use crate::finger::{
    Load, LoadPathSpec, PolyCurve, Solution, SolveOptions, Solver, TargetProblem, Traced,
};
use crate::num::Num;
use crate::solve_error::SolveError;

use super::contact;
use super::frames::{
    self, contact_force_to_gripper, gripper_force_to_contact, gripper_force_to_finger,
};
use super::rules::{self, Invalid, PathRecord, Stability, Verdict};
use super::setup::{
    Grasp, GraspLoad, Gripper, Object, CONTACT_TOL_MM, CURVATURE_SAMPLES,
    GRIPPER_SAMPLES_PER_ELEMENT, TARGET_TOL_MM,
};

/// The path record of a probe ([`Gripper::probe_scene`]): solved from a
/// neighbouring grasp, not traced; never the path of a reported grasp.
pub(crate) const PROBE_PATH: &str = "probe";

/// Relative tolerance of [`Gripper::same_equilibrium`]: both solves end at
/// relative residuals near 1e-11 and a target within 1e-9 mm, while an
/// equilibrium of another branch differs in its coefficients at the
/// percent level.
const SAME_EQUILIBRIUM_TOL: f64 = 1e-7;

impl Gripper {
    /// The grasp-level notes and the verdict of an equilibrium holding
    /// `object` at grasping angle `beta`.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn judge(
        &self,
        solution: &Solution,
        normal: f64,
        friction: f64,
        size: f64,
        tip_gap: f64,
        beta: f64,
        object: Object,
        path: PathRecord,
    ) -> (Vec<Warning>, Verdict) {
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
        let rules = rules::open_rule(size, tip_gap)
            .or_else(|| rules::force_rule(normal, friction, self.params.mu))
            .or(beyond)
            .or_else(|| self.object_contact(solution, beta, object).1)
            .or(strict_invalid);
        // the model's own limits: the finger's findings (a reversal is the
        // paper's grasp assumption, a rule in strict mode only; past flat
        // is a rule)
        let findings = solution
            .warnings
            .iter()
            .filter(|w| w.is_validity() && !matches!(w, Warning::CurvatureReversal { .. }))
            .cloned()
            .collect();
        let stability = match (self.stability, solution.negative_eigenvalues) {
            (false, _) => Stability::NotJudged,
            (true, Some(0)) => Stability::Stable,
            (true, Some(negative)) => Stability::Unstable { negative },
            (true, None) => Stability::Unknown,
        };
        (
            warnings,
            Verdict {
                rules,
                findings,
                stability,
                path,
            },
        )
    }

    /// The grasp measures of `solution`, the equilibrium of `problem` (built
    /// from `scene`) at load parameter `lambda`, reached as `path` says.
    pub(super) fn grasp_from(
        &self,
        solution: Solution,
        scene: &GraspLoad,
        problem: TargetProblem,
        lambda: f64,
        path: PathRecord,
    ) -> Grasp {
        let force = [
            scene.base[0] + lambda * scene.direction[0],
            scene.base[1] + lambda * scene.direction[1],
        ];
        let (normal, friction) = gripper_force_to_contact(force, scene.beta);
        let tip = self.to_gripper(solution.tip);
        let size = self.size_of(solution.tip);
        let tip_gap = 2.0 * tip[0];
        let (warnings, verdict) = self.judge(
            &solution,
            normal,
            friction,
            size,
            tip_gap,
            scene.beta,
            scene.object,
            path,
        );
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
            verdict,
            object: scene.object,
        }
    }

    pub(super) fn problem(&self, scene: &GraspLoad) -> TargetProblem {
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
    pub(super) fn check_size(&self, d: f64) -> Result<(), InputError> {
        finite(Field::GraspSize, d)?;
        let d_max = self.d_max();
        require(
            rules::flat_rule(d, d_max).is_none(),
            Field::GraspSize,
            d,
            || format!("exceeds d_max = {d_max:.3} mm: the fingers would be pressed past flat"),
        )
    }

    pub(super) fn solve_scene(
        &self,
        scene: &GraspLoad,
        warm: Option<&Grasp>,
    ) -> Result<Grasp, SolveError> {
        finite(Field::GraspPressureKpa, scene.pressure_kpa)?;
        let problem = self.problem(scene);
        let opts = self.scene_options(scene);
        let (sol, lambda, path) = self.close(&problem, warm, &opts, &scene.target)?;
        Ok(self.grasp_from(sol, scene, problem, lambda, path))
    }

    /// The grasp of `scene` solved by Newton's method from `near`, a grasp
    /// of a neighbouring scene (another angle or radius), instead of traced
    /// from rest: a probe for a search, which may land on another branch
    /// than the loading path's. Its path is recorded as [`PROBE_PATH`]; a
    /// search traces the grasp it reports from rest again and checks that
    /// the two agree ([`Gripper::same_equilibrium`]).
    pub(super) fn probe_scene(&self, scene: &GraspLoad, near: &Grasp) -> Result<Grasp, SolveError> {
        finite(Field::GraspPressureKpa, scene.pressure_kpa)?;
        let problem = self.problem(scene);
        let opts = self.scene_options(scene);
        let (sol, lambda) = Solver::new(&self.finger).solve_target(
            &problem,
            &near.solution.coefficients,
            near.lambda,
            TARGET_TOL_MM,
            &opts,
        )?;
        let path = PathRecord {
            from: PROBE_PATH,
            steps: 0,
        };
        Ok(self.grasp_from(sol, scene, problem, lambda, path))
    }

    /// True when two grasps of the same scene are the same equilibrium (the
    /// finger's coefficients and the load parameter within
    /// [`SAME_EQUILIBRIUM_TOL`] relative): a probe and the grasp traced
    /// from rest agree, so the probe was on the loading path.
    pub(crate) fn same_equilibrium(a: &Grasp, b: &Grasp) -> bool {
        let (x, y) = (
            a.solution.coefficients.as_slice(),
            b.solution.coefficients.as_slice(),
        );
        let scale = x.iter().fold(1.0_f64, |m, v| m.max(v.abs()));
        let close = |u: f64, v: f64, s: f64| (u - v).abs() <= SAME_EQUILIBRIUM_TOL * s;
        x.len() == y.len()
            && x.iter().zip(y).all(|(u, v)| close(*u, *v, scale))
            && close(a.lambda, b.lambda, 1.0 + a.lambda.abs())
    }

    fn scene_options(&self, scene: &GraspLoad) -> SolveOptions {
        SolveOptions {
            samples_per_element: GRIPPER_SAMPLES_PER_ELEMENT,
            stability: self.stability,
            shape: scene.shape,
            ..SolveOptions::default()
        }
    }

    /// The object touching the tip of `solution` at grasping angle `beta`:
    /// for a sphere its radius and centre (gripper frame), and the second
    /// contact, if the object reaches into the finger anywhere by more than
    /// [`CONTACT_TOL_MM`], or the finger reaches its tip from inside the
    /// object ([`Invalid::TipEntry`]). Exact: the finger's mid-plane is a polynomial
    /// curve per element ([`Finger::midplane_curves`]), and the deepest
    /// point of the object in it is found on the continuous curves
    /// ([`contact`]), not on samples. A sphere is the disc centred on the
    /// gripper axis through the tip; a face (a cuboid's side) is the
    /// half-plane through the tip normal to the contact direction, below
    /// the contact along the face (the tip holds its edge).
    pub(crate) fn object_contact(
        &self,
        solution: &Solution,
        beta: f64,
        object: Object,
    ) -> (Option<(f64, [f64; 2])>, Option<Invalid>) {
        let tip = self.to_gripper(solution.tip);
        let (s, c) = beta.sin_cos();
        let n = [c, s];
        let sphere = match object {
            Object::Face => None,
            Object::Sphere => {
                let r = tip[0] / c;
                if !(r > 0.0 && r.is_finite()) {
                    return (None, None);
                }
                Some((r, [tip[0] - r * c, tip[1] - r * s]))
            }
        };
        // the finger must come to its tip from outside the object: its
        // tangent there (gripper frame, angle a - theta) against the
        // object's outward normal n at the contact, and for a face against
        // the face's direction t = (-sin b, cos b) (above the contact there
        // is no object)
        let (ts, tc) = (self.params.mounting_angle - solution.end_angle - beta).sin_cos();
        let enters = match object {
            Object::Sphere => tc > 0.0,
            Object::Face => tc > 0.0 && ts < 0.0,
        };
        if enters {
            return (sphere, Some(Invalid::TipEntry { angle: tc.asin() }));
        }
        let deepest = (|| -> Result<Option<contact::Deepest>, InputError> {
            let map = frames::finger_to_gripper_map(self.params.mounting_angle, self.palm)?;
            let curves: Vec<PolyCurve> = self
                .finger
                .midplane_curves(&solution.coefficients)?
                .iter()
                .map(|k| k.map(map))
                .collect();
            match sphere {
                None => contact::deepest_below(&curves, tip, n, [-s, c]),
                Some((r, centre)) => {
                    contact::deepest(&curves, &contact::Obstacle::disc(centre, r)?).map(Some)
                }
            }
        })();
        let second = match deepest {
            Ok(Some(d)) if d.depth > CONTACT_TOL_MM => Some(Invalid::SecondContact {
                element: d.element,
                x: d.x,
                depth: d.depth,
                point: d.point,
            }),
            Ok(_) => None,
            Err(_) => Some(Invalid::ContactUnknown),
        };
        (sphere, second)
    }

    /// The state a grasp of `problem`'s load family starts from when the
    /// gripper closes on the object: the finger at the grasp's pressure
    /// under the family's fixed load alone (`lambda = 0`: no normal force
    /// yet). The pressure alone is solved as any finger scene is (element
    /// by element, from the straight element at zero pressure); the fixed
    /// tip load (a friction or a lift given with the grasp) is then applied
    /// along its own path from zero, by pseudo-arclength continuation, so
    /// the start is the state that load reaches continuously. Where that
    /// path folds or the finger loses its stability under the fixed load
    /// before the load is whole, the grasp has no start on the path:
    /// [`SolveError::NotOnPath`]. At zero pressure and no fixed load the
    /// start is the reference state.
    pub(super) fn rest_state(
        &self,
        base: &Load,
        target: &(Field, f64),
    ) -> Result<Coefficients, SolveError> {
        let pressed = Load {
            fx: 0.0,
            fz: 0.0,
            ..*base
        };
        let at_pressure = if pressed.pressure == 0.0 {
            self.reference.coefficients.clone()
        } else {
            let opts = SolveOptions {
                stability: false,
                ..SolveOptions::default().tip_only()
            };
            self.finger.solve(&pressed, &opts)?.coefficients
        };
        let size = base.fx.hypot(base.fz);
        if size == 0.0 {
            return Ok(at_pressure);
        }
        let spec = LoadPathSpec {
            problem: TargetProblem {
                base: pressed,
                direction: [base.fx / size, base.fz / size],
                weights: [1.0, 0.0],
                target: 0.0,
            },
            lambda0: 0.0,
            increasing: true,
            lambda_end: Some(size),
            lambda_scale: 1.0,
            events: false,
        };
        // the first point past a fold or a loss of stability under the
        // fixed load: (load reached, what happened)
        let mut lost: Option<(f64, &str)> = None;
        let opts = SolveOptions {
            stability: true,
            ..SolveOptions::default().tip_only()
        };
        let path = Solver::new(&self.finger).follow_load(&spec, &at_pressure, &opts, &mut |p| {
            if p.lambda_slope < 0.0 {
                lost = Some((p.lambda, "turns back (a fold: the finger snaps)"));
            } else if p.negative_eigenvalues > 0 {
                lost = Some((p.lambda, "loses its stability"));
            }
            lost.is_none()
        })?;
        let detail = match (lost, path.termination) {
            (None, PathTermination::ReachedTarget) => return Ok(path.last.0),
            (Some((load, what)), _) => format!(
                "the finger under the grasp's fixed tip load of {:.4} N {what} at {:.4} N, before any normal force",
                Num(size),
                Num(load)
            ),
            (None, t) => format!(
                "the finger under the grasp's fixed tip load of {:.4} N could not be followed past {:.4} N ({t:?})",
                Num(size),
                Num(path.last.1)
            ),
        };
        Err(SolveError::NotOnPath {
            target: target.0.clone(),
            value: target.1,
            detail,
        })
    }

    /// The equilibrium the gripper reaches closing on the object: the path
    /// of `problem`'s load family traced in the target from the rest state
    /// at the grasp's pressure ([`Gripper::rest_state`], `lambda = 0`), or
    /// from `warm` when it is a grasp of the same family (a point of the
    /// same path, e.g. the previous point of a size sweep), to the target
    /// ([`Solver::trace_target`]). A path that turns back before the target
    /// (a fold: the fingers cannot be closed further on this branch) is
    /// [`SolveError::NotOnPath`], naming where.
    pub(crate) fn close(
        &self,
        problem: &TargetProblem,
        warm: Option<&Grasp>,
        opts: &SolveOptions,
        target: &(Field, f64),
    ) -> Result<(Solution, f64, PathRecord), SolveError> {
        let same_family = |w: &&Grasp| {
            w.problem.base == problem.base
                && w.problem.direction == problem.direction
                && w.problem.weights == problem.weights
                && w.solution.coefficients.elements() == self.finger.len()
        };
        let (start, lambda0, from) = match warm.filter(same_family) {
            Some(w) => (w.solution.coefficients.clone(), w.lambda, "previous"),
            None => (self.rest_state(&problem.base, target)?, 0.0, "rest"),
        };
        let mut solver = Solver::new(&self.finger);
        let traced = solver
            .trace_target(problem, &start, lambda0, TARGET_TOL_MM, opts)
            .map_err(|e| for_target(e, target.0.clone(), target.1))?;
        let fold = matches!(traced, Traced::Fold(_));
        match traced {
            Traced::Reached {
                solution,
                lambda,
                steps,
            } => Ok((solution, lambda, PathRecord { from, steps })),
            Traced::Fold(end) | Traced::Unstable(end) => {
                let (what, after) = if fold {
                    (
                        "the path turns back",
                        " (a fold: the finger snaps to another shape)",
                    )
                } else {
                    (
                        "the finger held by the object loses its stability",
                        ": past it the finger snaps off the path",
                    )
                };
                let force = problem.load_at(end.lambda);
                Err(SolveError::NotOnPath {
                    target: target.0.clone(),
                    value: target.1,
                    detail: format!(
                        "closing the gripper on the object from rest, {what} at grasp size {:.4} mm with a tip load of {:.4} N{after}",
                        Num(self.size_of(end.tip)),
                        Num(force.fx.hypot(force.fz))
                    ),
                })
            }
            Traced::Stalled { last, reached } => {
                let force = problem.load_at(last.lambda);
                Err(SolveError::TargetNotReached {
                    target: target.0.clone(),
                    value: target.1,
                    reached,
                    detail: format!(
                        "at grasp size {:.4} mm the tip load had grown to {:.4} N",
                        Num(self.size_of(last.tip)),
                        Num(force.fx.hypot(force.fz))
                    ),
                })
            }
        }
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
        self.size_grasp(pressure_kpa, d, beta, Object::Face, warm, true)
    }

    /// [`Gripper::grasp_load_for_size`] holding `object`, with the answer's
    /// mid-plane sampled or not (`shape`: sweeps and searches need the
    /// verdict and the forces only).
    pub(crate) fn size_grasp(
        &self,
        pressure_kpa: f64,
        d: f64,
        beta: f64,
        object: Object,
        warm: Option<&Grasp>,
        shape: bool,
    ) -> Result<Grasp, SolveError> {
        self.check_size(d)?;
        check_beta(beta)?;
        let direction = contact_force_to_gripper(1.0, self.params.mu, beta);
        self.solve_scene(
            &GraspLoad {
                pressure_kpa,
                beta,
                base: [0.0, 0.0],
                direction,
                tip_xg: self.tip_xg_for_size(d),
                target: (Field::GraspSize, d),
                object,
                shape,
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
        finite(Field::GraspFriction, friction)?;
        let scene = GraspLoad {
            pressure_kpa,
            beta: 0.0,
            base: [0.0, friction],
            direction: [1.0, 0.0],
            tip_xg: self.tip_xg_for_size(d),
            target: (Field::GraspFriction, friction),
            object: Object::Face,
            shape: true,
        };
        // a path that does not reach a cuboid narrower than the fingers
        // stand apart is no fault of the friction it carries
        self.solve_scene(&scene, warm).map_err(|e| match e {
            SolveError::NotOnPath { .. } | SolveError::TargetNotReached { .. } => {
                self.out_of_reach(&scene, d).map_or(e, SolveError::Input)
            }
            e => e,
        })
    }

    /// An object of size `d` narrower than the fingers stand apart at the
    /// start of `scene`'s grasp (its pressure and fixed load, before any
    /// normal force): it does not reach the fingers, which only a pull
    /// would close on it. `None` when it reaches them (or the start is not
    /// known).
    fn out_of_reach(&self, scene: &GraspLoad, d: f64) -> Option<InputError> {
        let problem = self.problem(scene);
        let start = self.rest_state(&problem.base, &scene.target).ok()?;
        let (tip, _) = self.finger.tip(&start).ok()?;
        let opening = self.size_of(tip);
        (d < opening).then(|| InputError::OutOfRange {
            field: Field::GraspSize,
            value: d,
            rule: format!(
                "the cuboid does not reach the fingers: at the grasp's pressure, before any normal force, they stand {opening:.4} mm apart"
            ),
        })
    }
}

pub(crate) fn check_beta(beta: f64) -> Result<(), InputError> {
    finite(Field::GraspBeta, beta)?;
    require(beta.abs() <= FRAC_PI_2, Field::GraspBeta, beta, || {
        "must lie in [-pi/2, pi/2]".into()
    })
}

/// A failed grasp solve in the target's terms: input errors stay as they
/// are; a solve that did not converge says which target it did not reach.
pub(crate) fn for_target(e: SolveError, target: Field, value: f64) -> SolveError {
    match e {
        SolveError::NotConverged { .. } => SolveError::TargetNotReached {
            target,
            value,
            reached: 0.0,
            detail: e.to_string(),
        },
        e => e,
    }
}

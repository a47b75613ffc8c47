//! Where a grasp-size sweep ends when the next size cannot be reached by a
//! target solve: the load path from the last grasp is followed by
//! pseudo-arclength continuation in the normal force (the contact
//! direction and the friction ratio fixed), and its natural end is
//! reported: the size reached after all (the sweep goes on), a fold (the
//! finger snaps through), the model's validity limit, or a normal force
//! beyond [`MAX_GRASP_FORCE_N`]. Only a path that cannot be continued at
//! all is a numerical stop.

use serde::Serialize;

use crate::coefficients::Coefficients;
use crate::finger::{LoadPathSpec, SolveOptions, Solver, Traced};
use crate::num::Num;
use crate::solve_error::SolveError;
use fpc_newton::PathTermination;

use super::frames::contact_force_to_gripper;
use super::rules::PathRecord;
use super::setup::{Grasp, GraspLoad, Gripper, Object, GRIPPER_SAMPLES_PER_ELEMENT, TARGET_TOL_MM};

/// The normal force (N) beyond which a sweep ends: forces far above what a
/// soft gripper exerts; the grasping size then approaches its limit for
/// the contact direction.
pub const MAX_GRASP_FORCE_N: f64 = 100.0;

/// The natural end of a grasp-size sweep.
#[derive(Debug, Clone, PartialEq, Serialize)]
#[serde(tag = "kind", rename_all = "snake_case")]
pub enum SweepEnd {
    /// The normal force needed grows without bound: beyond
    /// [`MAX_GRASP_FORCE_N`] the size reached is `size_mm`.
    ForceBound { force_n: f64, size_mm: f64 },
    /// The finger leaves the model's validity before the next size: the
    /// first finding, at this force and size.
    Validity {
        force_n: f64,
        size_mm: f64,
        finding: String,
    },
    /// A limit point of the load path: the finger snaps through at this
    /// normal force; `tip_mm` is the tip there (finger frame).
    Fold {
        force_n: f64,
        size_mm: f64,
        tip_mm: [f64; 2],
    },
    /// The next size is not reached on the path the grasps follow from
    /// rest: the grasp size turns back, or the held finger loses its
    /// stability (it would snap off the path), as `detail` says.
    Path { size_mm: f64, detail: String },
    /// The path could not be continued (a numerical end).
    Numerical {
        force_n: f64,
        size_mm: f64,
        reason: String,
    },
}

impl SweepEnd {
    /// Its JSON `kind`: `force_bound`, `validity`, `fold` or `numerical`.
    pub fn kind(&self) -> &'static str {
        match self {
            SweepEnd::ForceBound { .. } => "force_bound",
            SweepEnd::Validity { .. } => "validity",
            SweepEnd::Fold { .. } => "fold",
            SweepEnd::Path { .. } => "path",
            SweepEnd::Numerical { .. } => "numerical",
        }
    }

    /// True for a numerical end (not a property of the gripper).
    pub fn is_numerical(&self) -> bool {
        matches!(self, SweepEnd::Numerical { .. })
    }
}

impl std::fmt::Display for SweepEnd {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            SweepEnd::ForceBound { force_n, size_mm } => write!(
                f,
                "the normal force grows without bound: beyond F = {:.4} N (limit {MAX_GRASP_FORCE_N} N) the grasp size is {:.4} mm",
                Num(*force_n),
                Num(*size_mm)
            ),
            SweepEnd::Validity {
                force_n,
                size_mm,
                finding,
            } => write!(
                f,
                "the finger leaves the model at F = {:.4} N, grasp size {:.4} mm: {finding}",
                Num(*force_n),
                Num(*size_mm)
            ),
            SweepEnd::Fold {
                force_n, size_mm, ..
            } => write!(
                f,
                "the finger snaps through at F = {:.4} N (grasp size {:.4} mm)",
                Num(*force_n),
                Num(*size_mm)
            ),
            SweepEnd::Path { size_mm, detail } => write!(
                f,
                "grasp size {:.4} mm is not reached on the path from rest: {detail}",
                Num(*size_mm)
            ),
            SweepEnd::Numerical {
                force_n,
                size_mm,
                reason,
            } => write!(
                f,
                "the load path could not be continued past F = {:.4} N, grasp size {:.4} mm ({reason})",
                Num(*force_n),
                Num(*size_mm)
            ),
        }
    }
}

/// The outcome of [`Gripper::size_tail`].
#[derive(Debug, Clone, PartialEq)]
pub enum SizeTail {
    /// The size was reached along the path: its grasp.
    Reached(Box<Grasp>),
    /// The sweep ends here.
    End(SweepEnd),
}

impl Gripper {
    /// The start of a grasp-size sweep at grasping angle `beta`: the finger
    /// at `pressure_kpa` without contact force (`lambda = 0`), as a grasp of
    /// its own size, from which [`Gripper::size_tail`] can follow the load.
    pub fn size_sweep_start(&self, pressure_kpa: f64, beta: f64) -> Result<Grasp, SolveError> {
        self.sweep_start(pressure_kpa, beta, Object::Face)
    }

    /// [`Gripper::size_sweep_start`] holding `object`.
    pub(crate) fn sweep_start(
        &self,
        pressure_kpa: f64,
        beta: f64,
        object: Object,
    ) -> Result<Grasp, SolveError> {
        let opts = SolveOptions {
            samples_per_element: GRIPPER_SAMPLES_PER_ELEMENT,
            stability: self.stability,
            ..SolveOptions::default()
        };
        let load = crate::finger::Load::unloaded().with_pressure_kpa(pressure_kpa);
        let sol = self.finger.solve(&load, &opts)?;
        let size = self.size_of(sol.tip);
        let scene = GraspLoad {
            pressure_kpa,
            beta,
            base: [0.0, 0.0],
            direction: contact_force_to_gripper(1.0, self.params.mu, beta),
            tip_xg: self.tip_xg_for_size(size),
            target: (crate::Field::GraspSize, size),
            object,
            shape: true,
        };
        let problem = self.problem(&scene);
        let path = PathRecord {
            from: "rest",
            steps: 0,
        };
        Ok(self.grasp_from(sol, &scene, problem, 0.0, path))
    }

    /// From `last` (a grasp of a size sweep: [`Gripper::grasp_load_for_size`],
    /// zero fixed force, `f = mu F`), follows the load path in the normal
    /// force towards the grasping size `d_next`, which a target solve did
    /// not reach, and returns its grasp or the sweep's natural end (module
    /// docs).
    pub fn size_tail(&self, last: &Grasp, d_next: f64) -> Result<SizeTail, SolveError> {
        self.check_size(d_next)?;
        let opts = SolveOptions {
            samples_per_element: GRIPPER_SAMPLES_PER_ELEMENT,
            ..SolveOptions::default().tip_only()
        };
        let mut solver = Solver::new(&self.finger);
        let spec = LoadPathSpec {
            problem: last.problem,
            lambda0: last.lambda,
            // a larger size needs a larger normal force
            increasing: true,
            // land on the force bound exactly
            lambda_end: Some(MAX_GRASP_FORCE_N),
            lambda_scale: last.lambda.abs().max(0.1),
            events: true,
        };
        let per = self.finger.unknowns_per_element();
        let mut end: Option<SweepEnd> = None;
        let mut reached: Option<(Vec<f64>, f64)> = None;
        let mut at = (last.lambda, last.size);
        let path = solver.follow_load(&spec, &last.solution.coefficients, &opts, &mut |p| {
            let size = self.size_of(p.tip);
            // the object holds the size: the path ends where the size turns
            // back (a fold in the size) or the held finger loses stability
            if size < at.1 && p.lambda != last.lambda {
                end = Some(SweepEnd::Path {
                    size_mm: at.1,
                    detail: format!(
                        "the grasp size turns back at {:.4} mm (F = {:.4} N)",
                        Num(at.1),
                        Num(at.0)
                    ),
                });
                return false;
            }
            if p.restricted_negative.is_some_and(|k| k > 0) {
                end = Some(SweepEnd::Path {
                    size_mm: size,
                    detail: format!(
                        "the finger held by the object loses its stability at {:.4} mm (F = {:.4} N): past it the finger snaps off the path",
                        Num(size),
                        Num(p.lambda)
                    ),
                });
                return false;
            }
            at = (p.lambda, size);
            if size >= d_next {
                reached = Some((p.coefficients.to_vec(), p.lambda));
                return false;
            }
            if p.lambda >= MAX_GRASP_FORCE_N {
                end = Some(SweepEnd::ForceBound {
                    force_n: p.lambda,
                    size_mm: size,
                });
                return false;
            }
            let finding = Coefficients::new(per, p.coefficients.to_vec())
                .ok()
                .and_then(|k| self.finger.validity(&k, 4).ok())
                .and_then(|w| w.into_iter().find(|w| w.is_validity()));
            if let Some(w) = finding {
                end = Some(SweepEnd::Validity {
                    force_n: p.lambda,
                    size_mm: size,
                    finding: w.to_string(),
                });
                return false;
            }
            true
        })?;
        if let Some(fold) = path.folds.iter().find(|f| f.is_fold) {
            // the first limit point ends the sweep: past it the finger snaps
            return Ok(SizeTail::End(SweepEnd::Fold {
                force_n: fold.lambda,
                size_mm: self.size_of(fold.tip),
                tip_mm: fold.tip,
            }));
        }
        if let Some((k, lambda)) = reached {
            // the path reached the size: trace the target from that point
            // of the same path to the size itself
            let k = Coefficients::new(per, k)?;
            let scene = GraspLoad {
                pressure_kpa: last.pressure_kpa,
                beta: last.beta,
                base: [0.0, 0.0],
                direction: contact_force_to_gripper(1.0, self.params.mu, last.beta),
                tip_xg: self.tip_xg_for_size(d_next),
                target: (crate::Field::GraspSize, d_next),
                object: last.object,
                shape: true,
            };
            let p1 = self.problem(&scene);
            let full = SolveOptions {
                samples_per_element: GRIPPER_SAMPLES_PER_ELEMENT,
                stability: self.stability,
                ..SolveOptions::default()
            };
            let traced = solver.trace_target(&p1, &k, lambda, TARGET_TOL_MM, &full);
            return Ok(SizeTail::End(match traced {
                Ok(Traced::Reached {
                    solution,
                    lambda,
                    steps,
                }) => {
                    // on the path of the previous grasp, which was reached
                    // from rest
                    let path = PathRecord {
                        from: "previous",
                        steps: last.verdict.path.steps + steps,
                    };
                    return Ok(SizeTail::Reached(Box::new(
                        self.grasp_from(solution, &scene, p1, lambda, path),
                    )));
                }
                Ok(Traced::Fold(f) | Traced::Unstable(f) | Traced::Stalled { last: f, .. }) => {
                    SweepEnd::Numerical {
                        force_n: f.lambda,
                        size_mm: self.size_of(f.tip),
                        reason: "the grasp size turns back before it is reached".into(),
                    }
                }
                Err(e) => SweepEnd::Numerical {
                    force_n: lambda,
                    size_mm: at.1,
                    reason: e.to_string(),
                },
            }));
        }
        Ok(SizeTail::End(match (end, path.termination) {
            (Some(e), _) => e,
            (None, t) => SweepEnd::Numerical {
                force_n: at.0,
                size_mm: at.1,
                reason: termination_text(t),
            },
        }))
    }
}

fn termination_text(t: PathTermination) -> String {
    format!("{t:?}")
}

#[cfg(test)]
mod kind_tests {
    use super::*;

    #[test]
    fn the_kind_is_the_json_tag() {
        for e in [
            SweepEnd::ForceBound {
                force_n: 1.0,
                size_mm: 2.0,
            },
            SweepEnd::Validity {
                force_n: 1.0,
                size_mm: 2.0,
                finding: "f".into(),
            },
            SweepEnd::Fold {
                force_n: 1.0,
                size_mm: 2.0,
                tip_mm: [0.0, 0.0],
            },
            SweepEnd::Path {
                size_mm: 2.0,
                detail: "d".into(),
            },
            SweepEnd::Numerical {
                force_n: 1.0,
                size_mm: 2.0,
                reason: "r".into(),
            },
        ] {
            assert_eq!(serde_json::to_value(&e).unwrap()["kind"], e.kind());
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A sweep end's force near zero keeps a digit (`2e-6`, not `0.0000`);
    /// ordinary values read as fixed decimals.
    #[test]
    fn a_sweep_end_near_zero_keeps_its_digit() {
        let text = SweepEnd::Numerical {
            force_n: 2e-6,
            size_mm: 100.0,
            reason: "stalled".into(),
        }
        .to_string();
        assert_eq!(
            text,
            "the load path could not be continued past F = 2e-6 N, grasp size 100.0000 mm (stalled)"
        );
        let text = SweepEnd::ForceBound {
            force_n: 34.91234567,
            size_mm: 1e-7,
        }
        .to_string();
        assert!(text.contains("beyond F = 34.9123 N"), "{text}");
        assert!(text.ends_with("the grasp size is 1e-7 mm"), "{text}");
    }
}

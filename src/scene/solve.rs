//! The solve dispatch: a finger scene is solved at its load (on its
//! partition, or refined to a tip tolerance); a gripper scene builds the
//! gripper and solves its grasp. [`SceneSolution`] and [`GraspOutcome`]
//! hold the results.

use crate::blocks::Partition;
use crate::error::{SolveError, Warning};
use crate::finger::{Finger, Solution};
use crate::gripper::{Grasp, Gripper, Invalid, SphereContact};
use crate::refine::solve_to_tip_tolerance;

use super::fields::{inconsistent, scene_solve, PartitionKey};
use super::resolve::{GraspSpec, PartitionPlan};
use super::Scene;

impl Scene {
    /// Solves the finger, or builds the gripper and solves its grasp.
    /// Input errors name the scene's keys.
    pub fn solve(&self) -> Result<SceneSolution, SolveError> {
        // every error in here comes from the library, in its terms
        self.solve_inner().map_err(scene_solve)
    }

    fn solve_inner(&self) -> Result<SceneSolution, SolveError> {
        let finger = |part: &Partition| Finger::new(&self.actuator, part, true);
        let Some(g) = &self.gripper else {
            return Ok(match &self.partition {
                PartitionPlan::Fixed(part) => SceneSolution::Finger {
                    solution: finger(part).solve(&self.load, &self.options)?,
                    elements: part.len(),
                    tip_error_estimate_mm: None,
                },
                &PartitionPlan::TipTolerance { tip_tol_mm, start } => {
                    let r = solve_to_tip_tolerance(
                        &self.actuator,
                        true,
                        &self.load,
                        tip_tol_mm,
                        start,
                        &self.options,
                    )?;
                    SceneSolution::Finger {
                        solution: r.solution,
                        elements: r.elements,
                        tip_error_estimate_mm: Some(r.estimated_tip_error_mm),
                    }
                }
            });
        };
        let PartitionPlan::Fixed(part) = &self.partition else {
            // resolve() rejects tip_tol_mm with a gripper
            return Err(
                inconsistent(PartitionKey::TipTolMm, "not supported in a gripper scene").into(),
            );
        };
        let gripper = Gripper::new(finger(part), g.params)?.with_stability(g.stability);
        let grasp = match g.grasp {
            None => None,
            Some(spec) => Some(Box::new(solve_grasp(&gripper, spec)?)),
        };
        Ok(SceneSolution::Gripper {
            gripper: Box::new(gripper),
            grasp,
        })
    }
}

fn solve_grasp(gripper: &Gripper, spec: GraspSpec) -> Result<GraspOutcome, SolveError> {
    let (grasp, sphere) = match spec {
        GraspSpec::Size {
            pressure_kpa,
            d_mm,
            beta_deg,
        } => (
            gripper.grasp_load_for_size(pressure_kpa, d_mm, beta_deg.to_radians(), None)?,
            None,
        ),
        GraspSpec::Cuboid {
            pressure_kpa,
            d_mm,
            friction_n,
        } => (
            gripper.force_control(pressure_kpa, d_mm, friction_n, None)?,
            None,
        ),
        GraspSpec::Sphere {
            pressure_kpa,
            r_mm,
            lift_n,
            beta_deg,
        } => {
            let sg =
                gripper.sphere_grasp(pressure_kpa, r_mm, lift_n, beta_deg.to_radians(), None)?;
            let contact = SphereContact {
                radius: sg.radius,
                center: sg.center,
                invalid: sg.invalid,
            };
            (sg.grasp, Some(contact))
        }
    };
    let invalid = match &sphere {
        Some(c) => c.invalid,
        None => open_and_friction(&grasp, gripper.mu()),
    };
    Ok(GraspOutcome {
        spec,
        grasp,
        sphere,
        invalid,
    })
}

/// The validity of a cuboid or size grasp: the fingers open (`d > 0` and a
/// positive tip gap), `F >= 0` and `0 <= f <= mu F`.
fn open_and_friction(g: &Grasp, mu: f64) -> Option<Invalid> {
    if !(g.size > 0.0 && g.tip_gap > 0.0) {
        return Some(Invalid::NotOpen {
            size: g.size,
            tip_gap: g.tip_gap,
        });
    }
    let tol = 1e-12 * (1.0 + g.normal.abs());
    if g.normal < -tol {
        return Some(Invalid::NegativeNormal { normal: g.normal });
    }
    if !g.friction_ok(mu) {
        return Some(Invalid::FrictionCone {
            friction: g.friction,
            limit: mu * g.normal,
        });
    }
    None
}

/// A solved grasp.
#[derive(Debug, Clone, PartialEq)]
pub struct GraspOutcome {
    /// What was asked.
    pub spec: GraspSpec,
    /// The equilibrium and its measures (F, f, f_v, d, tip gap, h).
    pub grasp: Grasp,
    /// For a sphere: its radius, centre (gripper frame) and geometric validity.
    pub sphere: Option<SphereContact>,
    /// The first rule the grasp breaks (`None`: valid).
    pub invalid: Option<Invalid>,
}

impl GraspOutcome {
    /// True when the grasp breaks no rule.
    pub fn is_valid(&self) -> bool {
        self.invalid.is_none()
    }
}

/// The result of [`Scene::solve`].
#[derive(Debug, Clone)]
pub enum SceneSolution {
    /// A finger scene.
    Finger {
        solution: Solution,
        /// The number of elements used.
        elements: usize,
        /// With `tip_tol_mm`: the estimated tip error (mm).
        tip_error_estimate_mm: Option<f64>,
    },
    /// A gripper scene: the gripper (its reference state, l0, palm,
    /// overlap) and the grasp, if one was asked.
    Gripper {
        gripper: Box<Gripper>,
        grasp: Option<Box<GraspOutcome>>,
    },
}

impl SceneSolution {
    /// The finger's equilibrium: the grasp's, or the gripper's reference
    /// state when there is no grasp.
    pub fn solution(&self) -> &Solution {
        match self {
            SceneSolution::Finger { solution, .. } => solution,
            SceneSolution::Gripper { grasp: Some(g), .. } => &g.grasp.solution,
            SceneSolution::Gripper { gripper, .. } => gripper.reference(),
        }
    }

    /// The number of elements used.
    pub fn elements(&self) -> usize {
        match self {
            SceneSolution::Finger { elements, .. } => *elements,
            SceneSolution::Gripper { gripper, .. } => gripper.finger().len(),
        }
    }

    /// Non-fatal notes about the gripper's design.
    pub fn warnings(&self) -> &[Warning] {
        match self {
            SceneSolution::Finger { .. } => &[],
            SceneSolution::Gripper { gripper, .. } => gripper.warnings(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::error::SolveError;
    use crate::gripper::PalmSpec;
    use crate::scene::testing::SCENES;

    #[test]
    fn solve_errors_name_the_toml_path() {
        // an overlap larger than the finger's reach is found by the gripper
        let s = Scene::from_toml("[gripper]\noverlap_mm = 500\n").unwrap();
        match s.solve() {
            Err(SolveError::Input(e)) => assert_eq!(e.field(), "gripper.overlap_mm", "{e}"),
            other => panic!("{other:?}"),
        }
        // a tip tolerance that cannot be reached
        let s = Scene::from_toml("[partition]\ntip_tol_mm = 1e-30\nelements = 256\n").unwrap();
        match s.solve() {
            Err(SolveError::Input(e)) => assert_eq!(e.field(), "partition.tip_tol_mm", "{e}"),
            other => panic!("{other:?}"),
        }
    }

    #[test]
    fn example_scenes_parse_and_solve() {
        let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenes");
        let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| n.ends_with(".toml"))
            .collect();
        on_disk.sort();
        let mut listed: Vec<String> = SCENES.iter().map(|(n, _)| n.to_string()).collect();
        listed.sort();
        assert_eq!(on_disk, listed, "every scene in scenes/ is tested here");
        for (name, text) in SCENES {
            let scene = Scene::from_toml(text).unwrap_or_else(|e| panic!("{name}: {e}"));
            let sol = scene.solve().unwrap_or_else(|e| panic!("{name}: {e}"));
            let s = sol.solution();
            assert!(s.tip.iter().all(|v| v.is_finite()), "{name}");
            assert!(!s.points.is_empty(), "{name}");
            if let SceneSolution::Gripper { grasp: Some(g), .. } = &sol {
                assert!(g.is_valid(), "{name}: {:?}", g.invalid);
            }
        }
    }

    #[test]
    fn example_grasps_match_the_library() {
        // the cuboid example is the paper's force control scene
        let text = SCENES
            .iter()
            .find(|(n, _)| *n == "cuboid_grasp.toml")
            .unwrap()
            .1;
        let scene = Scene::from_toml(text).unwrap();
        let g = scene.gripper.unwrap();
        assert_eq!(g.params.mounting_angle, 60f64.to_radians());
        assert_eq!(g.params.geometry, PalmSpec::Overlap(20.0));
        let Some(GraspSpec::Cuboid {
            d_mm, friction_n, ..
        }) = g.grasp
        else {
            panic!()
        };
        let SceneSolution::Gripper {
            gripper,
            grasp: Some(out),
        } = scene.solve().unwrap()
        else {
            panic!()
        };
        let direct = gripper
            .force_control(out.grasp.pressure_kpa, d_mm, friction_n, None)
            .unwrap();
        assert_eq!(direct.normal, out.grasp.normal);
        assert!((out.grasp.size - d_mm).abs() < 1e-6);
        assert!((out.grasp.friction - friction_n).abs() < 1e-9);
    }
}

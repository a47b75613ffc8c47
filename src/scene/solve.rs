//! The solve dispatch: a finger scene is solved at its load (on its
//! partition, or refined to a tip tolerance); a gripper scene builds the
//! gripper and solves its grasp. [`SceneSolution`] and [`GraspOutcome`]
//! hold the results.

use std::any::Any;
use std::sync::Arc;

use crate::actuator::Actuator;
use crate::error::{InputError, Warning};
use crate::field::Field;
use crate::finger::{Finger, Load, Solution, SolveOptions};
use crate::gripper::GRIPPER_SAMPLES_PER_ELEMENT;
use crate::gripper::{Grasp, Gripper, Invalid, SphereContact};
use crate::gripper::{GripperParams, PalmSpec};
use crate::model::ModelId;
use crate::partition::Partition;
use crate::plan::{FingerBuilder, Plan, PlannedFinger, Solved};
use crate::solve_error::SolveError;

use super::fields::{
    inconsistent, name_written, say_default, scene_solve, GraspKey, PartitionKey, SceneKey,
};
use super::resolve::Scene;
use super::resolve::{GraspSpec, GripperScene, PartitionPlan};

impl PartitionPlan {
    /// The solve plan of a finger on this partition.
    pub fn plan(&self) -> Plan {
        match self {
            PartitionPlan::Fixed(part) => Plan::Fixed(part.clone()),
            PartitionPlan::Auto => Plan::Auto,
            &PartitionPlan::TipTolerance { tip_tol_mm, start } => {
                Plan::TipTolerance { tip_tol_mm, start }
            }
        }
    }
}

impl Scene {
    /// Solves the finger, or builds the gripper and solves its grasp.
    /// Input errors name the scene's keys.
    pub fn solve(&self) -> Result<SceneSolution, SolveError> {
        self.solve_warm(None)
    }

    /// [`Scene::solve`] started from the solution of a nearby scene (the
    /// previous point of a sweep): a finger on a fixed partition starts
    /// Newton from `warm`'s coefficients when the element counts match, a
    /// grasp follows the path from `warm`'s grasp when it is of the same
    /// kind (so a sweep stays on the branch it started on). What `warm`
    /// built serves again where it is this scene's: a finger scene with
    /// `warm`'s model, actuator and plan (only the load differs) solves on
    /// `warm`'s fingers, a gripper scene with `warm`'s finger and design
    /// (only the grasp differs) on `warm`'s gripper. Anything else solves
    /// as [`Scene::solve`] does.
    pub fn solve_warm(&self, warm: Option<&SceneSolution>) -> Result<SceneSolution, SolveError> {
        // every error in here comes from the library, in its terms
        self.solve_inner(warm)
            .map_err(|e| scene_solve(say_default(e, |k| self.written(k))))
    }

    /// The scene's finger on a given partition (ribs modelled).
    fn finger_on(&self, part: &Partition) -> Finger {
        Finger::with_model(self.model, &self.actuator, part, true)
    }

    /// The scene's finger under a solve plan, to build.
    fn planned(&self, plan: Plan) -> FingerBuilder {
        PlannedFinger::builder(&self.actuator)
            .model(self.model)
            .plan(plan)
    }

    fn solve_inner(&self, warm: Option<&SceneSolution>) -> Result<SceneSolution, SolveError> {
        let Some(g) = &self.gripper else {
            // a nearby scene's fingers serve again when they are this
            // scene's (a sweep over loads builds them once)
            let builder = self.planned(self.partition.plan());
            let kept = match warm {
                Some(SceneSolution::Finger(w)) => w.planned.clone(),
                _ => None,
            };
            let finger = match kept.and_then(|p| p.downcast::<PlannedFinger>().ok()) {
                Some(p) if builder.builds(&p) => p,
                _ => Arc::new(builder.build()?),
            };
            // a fixed partition starts from a nearby scene's solution when
            // the element counts match (a failed warm start solves cold)
            let warm = match (warm, finger.fixed()) {
                (Some(SceneSolution::Finger(w)), Some(f))
                    if w.solution.coefficients.elements() == f.len()
                        && w.solution.coefficients.per_element() == f.unknowns_per_element() =>
                {
                    Some(&w.solution.coefficients)
                }
                _ => None,
            };
            let mut solved = match warm {
                Some(w) => finger
                    .solve_from(&self.load, w, &self.options)
                    .or_else(|_| finger.solve(&self.load, &self.options))?,
                None => finger.solve(&self.load, &self.options)?,
            };
            solved.planned = Some(finger as Arc<dyn Any + Send + Sync>);
            return Ok(SceneSolution::Finger(solved));
        };
        // a nearby scene's gripper serves again when it was built from the
        // same finger and design (a sweep over the grasp builds it once)
        let key = GripperKey {
            model: self.model,
            actuator: self.actuator.clone(),
            partition: self.partition.clone(),
            params: g.params,
            stability: g.stability,
        };
        let kept = match warm {
            Some(SceneSolution::Gripper { gripper, .. }) => gripper
                .built_from
                .as_ref()
                .and_then(|k| k.downcast_ref::<GripperKey>())
                .filter(|&k| *k == key)
                .map(|_| gripper.clone()),
            _ => None,
        };
        let gripper = match kept {
            Some(g) => g,
            None => {
                let mut built = Box::new(self.gripper_of(g)?);
                built.built_from = Some(Arc::new(key));
                built
            }
        };
        let warm_grasp = match warm {
            Some(SceneSolution::Gripper { grasp: Some(w), .. }) => Some(&w.grasp),
            _ => None,
        };
        let grasp = match g.grasp {
            None => None,
            Some(spec) => {
                let mut outcome = spec
                    .solve(&gripper, warm_grasp)
                    .map_err(|e| self.cuboid_error(e, g))?;
                if let PartitionPlan::Fixed(part) = &self.partition {
                    if slope_finding(&outcome.grasp.warnings) {
                        let advice = partition_advice(part, spec, |p| {
                            Gripper::new(self.finger_on(p), g.params)
                                .map(|gr| gr.with_stability(g.stability))
                        });
                        outcome.grasp.warnings.push(advice);
                    }
                }
                Some(Box::new(outcome))
            }
        };
        Ok(SceneSolution::Gripper { gripper, grasp })
    }

    /// An error on a cuboid's size (wider than the fingers pressed flat,
    /// narrower than they stand apart) in the terms of what the scene
    /// wrote: a rule between the size and the gripper's palm and mounting
    /// angle, named as every such rule is ([`name_written`]); with none of
    /// them written, the grasp as a whole, in words.
    fn cuboid_error(&self, e: SolveError, g: &GripperScene) -> SolveError {
        let SolveError::Input(error) = e else {
            return e;
        };
        if !matches!(g.grasp, Some(GraspSpec::Cuboid { .. }))
            || !matches!(error.field(), Field::GraspSize)
        {
            return SolveError::Input(error);
        }
        let palm = match g.params.geometry {
            PalmSpec::Overlap(o) => (Field::GripperOverlap, o),
            PalmSpec::Palm(l) => (Field::GripperPalm, l),
        };
        let against = [palm, (Field::GripperMountingAngle, g.params.mounting_angle)];
        let size = SceneKey::Grasp(GraspKey::DMm);
        let named = name_written(error, &against, |k| self.written(k));
        if named.field() != &Field::from(size.to_string()) || self.written(size) {
            return SolveError::Input(named);
        }
        SolveError::Input(InputError::Inconsistent {
            field: Field::key("gripper.grasp"),
            rule: format!("the cuboid, of the default size, does not fit this gripper ({named})"),
        })
    }

    /// Builds the gripper of a gripper scene: its finger (on the fixed
    /// partition, or the automatic one chosen at the reference state) and
    /// the reference state.
    fn gripper_of(&self, g: &GripperScene) -> Result<Gripper, SolveError> {
        let finger = match &self.partition {
            PartitionPlan::Fixed(part) => self.finger_on(part),
            // chosen at the gripper's reference state, sampled as the
            // gripper samples it, so that state is within the slope limit
            PartitionPlan::Auto => {
                let opts = SolveOptions {
                    samples_per_element: GRIPPER_SAMPLES_PER_ELEMENT,
                    stability: false,
                    ..SolveOptions::default()
                };
                let unloaded = Load::unloaded();
                self.planned(Plan::Auto)
                    .build()?
                    .solve(&unloaded, &opts)?
                    .finger
            }
            PartitionPlan::TipTolerance { .. } => {
                // resolve() rejects tip_tol_mm with a gripper
                return Err(inconsistent(
                    PartitionKey::TipTolMm,
                    "not supported in a gripper scene",
                )
                .into());
            }
        };
        Ok(Gripper::new(finger, g.params)?.with_stability(g.stability))
    }
}

/// What a scene's gripper is built from ([`Gripper`]'s `built_from`).
#[derive(Debug, PartialEq)]
struct GripperKey {
    model: ModelId,
    actuator: Actuator,
    partition: PartitionPlan,
    params: GripperParams,
    stability: bool,
}

/// How many times [`partition_advice`] halves a scene's partition.
const ADVICE_HALVINGS: usize = 2;

fn slope_finding(warnings: &[Warning]) -> bool {
    warnings
        .iter()
        .any(|w| matches!(w, Warning::ElementSlope { .. }))
}

/// For a grasp whose fixed partition `part` turns an element beyond the
/// slope limit: solves the same grasp from rest on `part` halved, then
/// halved again (at most [`ADVICE_HALVINGS`] times, never past the
/// scene's 1000 elements), and says at which count the
/// finding clears, or that it does not. A refined solve that fails counts
/// as not clearing.
fn partition_advice(
    part: &Partition,
    spec: GraspSpec,
    gripper: impl Fn(&Partition) -> Result<Gripper, SolveError>,
) -> Warning {
    let mut refined = part.clone();
    for _ in 0..ADVICE_HALVINGS {
        if 2 * refined.len() > super::resolve::MAX_ELEMENTS {
            break;
        }
        refined = refined.halved();
        let clears = gripper(&refined)
            .and_then(|g| spec.solve(&g, None))
            .is_ok_and(|o| !slope_finding(&o.grasp.warnings));
        if clears {
            return Warning::PartitionAdvice {
                elements: part.len(),
                clears_with: Some(refined.len()),
                tried: refined.len(),
            };
        }
    }
    Warning::PartitionAdvice {
        elements: part.len(),
        clears_with: None,
        tried: refined.len(),
    }
}

impl GraspSpec {
    /// Solves this grasp on `gripper`: closing the gripper on the object
    /// from rest, or continuing the path of `warm` (a grasp of a nearby
    /// scene of the same load family). Its validity is the gripper's
    /// verdict ([`Grasp::verdict`]: for a sphere it includes the contact's
    /// geometry). Scenes and the Python module solve grasps here.
    pub fn solve(
        &self,
        gripper: &Gripper,
        warm: Option<&Grasp>,
    ) -> Result<GraspOutcome, SolveError> {
        solve_grasp(gripper, *self, warm)
    }
}

fn solve_grasp(
    gripper: &Gripper,
    spec: GraspSpec,
    warm: Option<&Grasp>,
) -> Result<GraspOutcome, SolveError> {
    // a warm grasp of another kind, or of another finger, starts nothing
    let warm = warm.filter(|w| {
        w.solution.coefficients.elements() == gripper.finger().len()
            && w.solution.coefficients.per_element() == gripper.finger().unknowns_per_element()
    });
    Ok(match spec {
        GraspSpec::Size {
            pressure_kpa,
            d_mm,
            beta_deg,
        } => {
            let grasp =
                gripper.grasp_load_for_size(pressure_kpa, d_mm, beta_deg.to_radians(), warm)?;
            GraspOutcome {
                spec,
                grasp,
                sphere: None,
            }
        }
        GraspSpec::Cuboid {
            pressure_kpa,
            d_mm,
            friction_n,
        } => {
            let grasp = gripper.force_control(pressure_kpa, d_mm, friction_n, warm)?;
            GraspOutcome {
                spec,
                grasp,
                sphere: None,
            }
        }
        GraspSpec::Sphere {
            pressure_kpa,
            r_mm,
            lift_n,
            beta_deg,
        } => {
            let sg =
                gripper.sphere_grasp(pressure_kpa, r_mm, lift_n, beta_deg.to_radians(), warm)?;
            // the contact's own (geometric) verdict, as the gripper judged it
            let contact = gripper.sphere_contact(&sg.grasp.solution, sg.grasp.beta);
            GraspOutcome {
                spec,
                grasp: sg.grasp,
                sphere: Some(contact),
            }
        }
    })
}

/// A solved grasp.
#[derive(Debug, Clone, PartialEq)]
pub struct GraspOutcome {
    /// What was asked.
    pub spec: GraspSpec,
    /// The equilibrium and its measures (F, f, f_v, d, tip gap, h).
    pub grasp: Grasp,
    /// For a sphere: its radius, centre (gripper frame) and geometric
    /// validity (not open, a second contact).
    pub sphere: Option<SphereContact>,
}

impl GraspOutcome {
    /// True when the grasp is valid: the gripper's one verdict
    /// ([`Grasp::verdict`]: the rules, the finger inside the model, stable,
    /// on the loading path).
    pub fn is_valid(&self) -> bool {
        self.grasp.is_valid()
    }

    /// The first reason the grasp is not valid (`None`: valid).
    pub fn invalid(&self) -> Option<Invalid> {
        self.grasp.invalid()
    }
}

/// The result of [`Scene::solve`].
// One per solve, matched by its fields: boxing the finger's solution would
// only add an indirection.
#[allow(clippy::large_enum_variant)]
#[derive(Debug, Clone)]
pub enum SceneSolution {
    /// A finger scene: the solve of its plan ([`PartitionPlan::plan`];
    /// with `tip_tol_mm`, [`Solved::estimated_tip_error_mm`] is the
    /// estimated tip error).
    Finger(Solved),
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
            SceneSolution::Finger(s) => &s.solution,
            SceneSolution::Gripper { grasp: Some(g), .. } => &g.grasp.solution,
            SceneSolution::Gripper { gripper, .. } => gripper.reference(),
        }
    }

    /// The number of elements used.
    pub fn elements(&self) -> usize {
        match self {
            SceneSolution::Finger(s) => s.elements(),
            SceneSolution::Gripper { gripper, .. } => gripper.finger().len(),
        }
    }

    /// Every warning, each once: the solution's (the actuator's notes and
    /// where the answer leaves the model), and in a gripper scene the
    /// gripper's (its design) and the grasp's (`curvature_reversal`,
    /// `beyond_flat`).
    pub fn warnings(&self) -> Vec<Warning> {
        let sources: [&[Warning]; 2] = match self {
            SceneSolution::Finger(s) => [&s.solution.warnings, &[]],
            SceneSolution::Gripper { gripper, grasp } => [
                gripper.warnings(),
                match grasp {
                    Some(g) => &g.grasp.warnings,
                    None => &gripper.reference().warnings,
                },
            ],
        };
        let mut all: Vec<Warning> = Vec::new();
        for w in sources.into_iter().flatten() {
            if !all.contains(w) {
                all.push(w.clone());
            }
        }
        all
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::gripper::PalmSpec;
    use crate::scene::testing::SCENES;
    use crate::scene::Scene;
    use crate::solve_error::SolveError;

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

    /// A sweep's next point on the same finger solves on the fingers the
    /// point before built (with a tip tolerance, every level), with the
    /// answer of a cold solve; a point on another finger builds its own.
    #[test]
    fn a_warm_scene_on_the_same_finger_reuses_its_fingers() {
        let scene = |fx: f64, eps0: f64| {
            Scene::from_toml(&format!(
                "[actuator.pemc]\neps0 = {eps0}\n[partition]\ntip_tol_mm = 0.05\n\
                 [load]\npressure_kpa = 50.0\nfx = {fx}\nfz = 0.2\n"
            ))
            .unwrap()
        };
        let solved = |s: SceneSolution| match s {
            SceneSolution::Finger(s) => s,
            other => panic!("{other:?}"),
        };
        let first = scene(0.5, 0.25).solve().unwrap();
        let kept = solved(first.clone()).planned.unwrap();
        for (fx, eps0, reused) in [(0.3, 0.25, true), (0.3, 0.3, false)] {
            let warm = solved(scene(fx, eps0).solve_warm(Some(&first)).unwrap());
            let cold = solved(scene(fx, eps0).solve().unwrap());
            assert_eq!(Arc::ptr_eq(warm.planned.as_ref().unwrap(), &kept), reused);
            assert_eq!(warm.solution, cold.solution, "fx {fx}, eps0 {eps0}");
            assert_eq!(warm.refinement, cold.refinement);
        }
    }

    /// A sweep's next grasp on the same gripper takes the gripper the
    /// point before built, and answers as with a gripper built afresh; a
    /// point on another finger builds its own.
    #[test]
    fn a_warm_grasp_on_the_same_gripper_reuses_it() {
        let scene = |d_mm: f64, eps0: f64| {
            Scene::from_toml(&format!(
                "[actuator.pemc]\neps0 = {eps0}\n[partition]\nelements = 8\n[gripper]\n\
                 [gripper.grasp]\nkind = \"cuboid\"\npressure_kpa = 20.0\nd_mm = {d_mm}\n\
                 friction_n = 0.3\n"
            ))
            .unwrap()
        };
        let parts = |s: &SceneSolution| match s {
            SceneSolution::Gripper {
                gripper,
                grasp: Some(g),
            } => (gripper.clone(), g.grasp.clone()),
            other => panic!("{other:?}"),
        };
        let first = scene(90.0, 0.25).solve().unwrap();
        let key = parts(&first).0.built_from.unwrap();
        // the same warm grasp with its gripper's key taken away: built again
        let mut unkeyed = first.clone();
        if let SceneSolution::Gripper { gripper, .. } = &mut unkeyed {
            gripper.built_from = None;
        }
        for (eps0, reused) in [(0.25, true), (0.3, false)] {
            let next = scene(92.0, eps0);
            let (kept, grasp) = parts(&next.solve_warm(Some(&first)).unwrap());
            let (built, fresh) = parts(&next.solve_warm(Some(&unkeyed)).unwrap());
            assert_eq!(Arc::ptr_eq(kept.built_from.as_ref().unwrap(), &key), reused);
            assert!(!Arc::ptr_eq(built.built_from.as_ref().unwrap(), &key));
            assert_eq!(grasp, fresh, "eps0 {eps0}");
            assert_eq!(kept.reference(), built.reference());
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
                assert!(g.is_valid(), "{name}: {:?}", g.invalid());
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
        assert_eq!(out.invalid(), direct.invalid());
    }

    fn grasp_of(text: &str) -> (Gripper, GraspOutcome) {
        match Scene::from_toml(text).unwrap().solve().unwrap() {
            SceneSolution::Gripper {
                gripper,
                grasp: Some(g),
            } => (*gripper, *g),
            other => panic!("{text:?}: {other:?}"),
        }
    }

    /// A finger 300 mm long without ribs curls so far that the material
    /// partition's nine elements each turn beyond the slope limit.
    const LONG: &str = "[actuator.geometry]\nlx = 300\n[actuator.channel]\ncx = 295\n[actuator.ribs]\nkind = \"none\"\n[actuator.pemc]\neps0 = 0.4\n";

    fn slope_findings(w: &[Warning]) -> usize {
        w.iter().filter(|w| w.kind() == "element_slope").count()
    }

    fn solve(text: &str) -> SceneSolution {
        Scene::from_toml(text)
            .unwrap_or_else(|e| panic!("{text:?}: {e}"))
            .solve()
            .unwrap_or_else(|e| panic!("{text:?}: {e}"))
    }

    #[test]
    fn auto_partition_of_a_finger_scene() {
        let fixed = solve(&format!("{LONG}[partition]\nelements = 9\n"));
        assert!(slope_findings(&fixed.warnings()) > 0);
        let text = format!("{LONG}[partition]\nelements = \"auto\"\n");
        let scene = Scene::from_toml(&text).unwrap();
        assert_eq!(scene.partition, PartitionPlan::Auto);
        let sol = scene.solve().unwrap();
        assert_eq!(slope_findings(&sol.warnings()), 0, "{:?}", sol.warnings());
        assert_eq!(slope_findings(&sol.solution().warnings), 0);
        assert!(sol.elements() > 9, "{}", sol.elements());
        assert_eq!(sol.elements(), sol.solution().element_lengths.len());
        // the library's automatic partition at the scene's load
        let direct = PlannedFinger::builder(&scene.actuator)
            .model(scene.model)
            .plan(Plan::Auto)
            .build()
            .unwrap()
            .solve(&scene.load, &scene.options)
            .unwrap();
        assert_eq!(sol.elements(), direct.finger.len());
        assert_eq!(sol.solution().tip, direct.solution.tip);
        // the paper's finger under pressure
        let sol = solve("[partition]\nelements = \"auto\"\n[load]\npressure_kpa = 100\n");
        assert_eq!(slope_findings(&sol.warnings()), 0, "{:?}", sol.warnings());
        assert_eq!(sol.elements(), sol.solution().element_lengths.len());
    }

    fn advice(w: &[Warning]) -> Vec<(usize, Option<usize>, usize)> {
        w.iter()
            .filter_map(|w| match *w {
                Warning::PartitionAdvice {
                    elements,
                    clears_with,
                    tried,
                } => Some((elements, clears_with, tried)),
                _ => None,
            })
            .collect()
    }

    #[test]
    fn a_grasp_too_coarse_for_its_partition_says_how_many_elements_clear_it() {
        let grasp = |elements: usize| {
            format!(
                "[actuator.pemc]\neps0 = 0.4\n[partition]\nelements = {elements}\n[gripper]\nmounting_angle_deg = 70\n\
                 [gripper.grasp]\nkind = \"cuboid\"\npressure_kpa = 60\nd_mm = 60\nfriction_n = 0.2\n"
            )
        };
        // the default 8 elements turn beyond the slope limit at this grasp
        let (_, coarse) = grasp_of(&grasp(8));
        assert!(slope_findings(&coarse.grasp.warnings) > 0);
        assert_eq!(advice(&coarse.grasp.warnings), [(8, Some(16), 16)]);
        // the advice holds: the scene solved on its own with 16 elements
        // has no slope finding (and so no advice)
        let (_, fine) = grasp_of(&grasp(16));
        assert_eq!(
            slope_findings(&fine.grasp.warnings),
            0,
            "{:?}",
            fine.grasp.warnings
        );
        assert!(advice(&fine.grasp.warnings).is_empty());
        // the advice is a note: the grasp reported is the scene's own
        assert!(!coarse.is_valid());
        assert!(!Warning::PartitionAdvice {
            elements: 8,
            clears_with: None,
            tried: 32
        }
        .is_validity());

        // a 300 mm finger on 4 elements still turns beyond the limit on 16:
        // the advice says so, and the scene on 16 confirms it
        let long = |n: usize| {
            format!(
                "{LONG}[partition]\nelements = {n}\n[gripper]\n[gripper.grasp]\nkind = \"size\"\npressure_kpa = 0\nd_mm = 100\n"
            )
        };
        let (_, four) = grasp_of(&long(4));
        assert_eq!(advice(&four.grasp.warnings), [(4, None, 16)]);
        let (_, sixteen) = grasp_of(&long(16));
        assert!(slope_findings(&sixteen.grasp.warnings) > 0);
        // no advice without the finding, nor on an automatic partition
        let (_, auto) = grasp_of("[partition]\nelements = \"auto\"\n[gripper]\n[gripper.grasp]\n");
        assert!(advice(&auto.grasp.warnings).is_empty());
    }

    #[test]
    fn auto_partition_of_a_gripper_scene() {
        let fixed = solve(&format!("{LONG}[partition]\nelements = 9\n[gripper]\n"));
        assert!(slope_findings(&fixed.warnings()) > 0);
        let text = format!("{LONG}[partition]\nelements = \"auto\"\n[gripper]\n");
        let scene = Scene::from_toml(&text).unwrap();
        let sol = scene.solve().unwrap();
        let SceneSolution::Gripper { gripper, grasp } = &sol else {
            panic!()
        };
        assert!(grasp.is_none());
        assert_eq!(slope_findings(&sol.warnings()), 0, "{:?}", sol.warnings());
        assert_eq!(slope_findings(&gripper.reference().warnings), 0);
        assert!(sol.elements() > 9, "{}", sol.elements());
        assert_eq!(sol.elements(), gripper.finger().len());
        // chosen by the library at the unloaded, zero-pressure state
        let opts = SolveOptions {
            samples_per_element: GRIPPER_SAMPLES_PER_ELEMENT,
            ..SolveOptions::default()
        };
        let direct = PlannedFinger::builder(&scene.actuator)
            .model(scene.model)
            .plan(Plan::Auto)
            .build()
            .unwrap()
            .solve(&Load::unloaded(), &opts)
            .unwrap();
        assert_eq!(
            gripper.finger().element_lengths(),
            direct.finger.element_lengths()
        );
        // the paper's gripper holding the default cuboid
        let sol = solve("[partition]\nelements = \"auto\"\n[gripper]\n[gripper.grasp]\n");
        let SceneSolution::Gripper {
            gripper,
            grasp: Some(g),
        } = &sol
        else {
            panic!()
        };
        assert!(g.is_valid(), "{:?}", g.invalid());
        assert_eq!(slope_findings(&sol.warnings()), 0, "{:?}", sol.warnings());
        assert_eq!(sol.elements(), gripper.finger().len());
        assert_eq!(sol.elements(), sol.solution().element_lengths.len());
    }

    #[test]
    fn the_finger_is_built_with_the_scenes_model() {
        for name in crate::ModelId::names() {
            let text = format!("[model]\nname = \"{name}\"\n[gripper]\n");
            let SceneSolution::Gripper { gripper, .. } =
                Scene::from_toml(&text).unwrap().solve().unwrap()
            else {
                panic!()
            };
            assert_eq!(gripper.finger().model().name(), name);
        }
    }

    /// A cuboid narrower than the fingers stand apart is not reached: the
    /// error names the key the scene wrote that puts it there (the
    /// overlap, or the size), never the friction it would carry.
    #[test]
    fn a_cuboid_out_of_reach_names_the_key_written() {
        let err = |text: &str| match Scene::from_toml(text).unwrap().solve() {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{text}: solved"),
        };
        let e = err("[gripper]\noverlap_mm = -300\n[gripper.grasp]\nkind = \"cuboid\"\n");
        assert!(
            e.starts_with("gripper.overlap_mm = -300: conflicts with the default of a key not given (gripper.grasp.d_mm = 100: the cuboid does not reach the fingers: at the grasp's pressure, before any normal force, they stand "),
            "{e}"
        );
        assert!(!e.contains("friction_n"), "{e}");
        let e = err("[gripper]\noverlap_mm = -300\n[gripper.grasp]\nd_mm = 50\nfriction_n = 0.3\n");
        assert!(
            e.starts_with("gripper.grasp.d_mm = 50: the cuboid does not reach the fingers"),
            "{e}"
        );
        let e = err("[gripper]\npalm_mm = 700\n[gripper.grasp]\n");
        assert!(
            e.starts_with("gripper.palm_mm = 700: conflicts with the default"),
            "{e}"
        );
    }

    /// A default that fails because of a key the scene wrote (a shorter
    /// finger, and the default overlap exceeds its reach) is said to be a
    /// default; the same key written is named plainly.
    #[test]
    fn a_failing_default_is_said_to_be_one() {
        let short = "[actuator.geometry]\nlx = 60\n[actuator.channel]\ncx = 55\n[gripper]\n";
        let err = |text: &str| match Scene::from_toml(text).unwrap().solve() {
            Err(e) => e.to_string(),
            Ok(_) => panic!("{text}: solved"),
        };
        let e = err(short);
        assert!(
            e.starts_with("gripper.overlap_mm = 20: must not exceed"),
            "{e}"
        );
        assert!(
            e.ends_with("; gripper.overlap_mm holds its default (it is not given)"),
            "{e}"
        );
        let e = err(&format!("{short}overlap_mm = 20\n"));
        assert!(
            e.starts_with("gripper.overlap_mm = 20: must not exceed"),
            "{e}"
        );
        assert!(!e.contains("default"), "{e}");
    }

    #[test]
    fn grasp_validity_is_the_grippers() {
        // friction beyond the cone
        let (_, out) = grasp_of("[gripper]\n[gripper.grasp]\nfriction_n = 50\n");
        assert!(
            matches!(out.invalid(), Some(Invalid::FrictionCone { .. })),
            "{:?}",
            out.invalid()
        );
        assert_eq!(out.invalid(), out.grasp.invalid());
        // a wide cuboid bends the root element backwards: flagged, and
        // invalid only in strict mode
        let text = "[gripper]\n[gripper.grasp]\nd_mm = 140\n";
        let (_, out) = grasp_of(text);
        assert_eq!(out.invalid(), None);
        assert!(out.grasp.is_reversed());
        let (gripper, strict) =
            grasp_of(&text.replace("[gripper]\n", "[gripper]\nstrict = true\n"));
        assert!(gripper.is_strict());
        assert!(
            matches!(
                strict.invalid(),
                Some(Invalid::CurvatureReversal { element: 0, .. })
            ),
            "{:?}",
            strict.invalid()
        );
        assert_eq!(strict.invalid(), strict.grasp.invalid());
        assert!(!strict.is_valid());
    }

    #[test]
    fn sphere_validity_is_the_grippers() {
        let text = "[gripper]\n[gripper.grasp]\nkind = \"sphere\"\nr_mm = 70\nlift_n = 2\n";
        let (gripper, out) = grasp_of(text);
        let direct = gripper
            .sphere_grasp(0.0, 70.0, 2.0, 20f64.to_radians(), None)
            .unwrap();
        assert_eq!(out.invalid(), direct.invalid());
        // the finger reaches its tip from inside the 70 mm sphere (its
        // tangent points about 4.6 degrees into it)
        assert!(
            matches!(out.invalid(), Some(Invalid::TipEntry { angle }) if angle > 0.01),
            "{:?}",
            out.invalid()
        );
        // the contact's geometric verdict is the grasp's rule; its forces are
        // fine
        let contact = out.sphere.clone().unwrap();
        assert_eq!(contact.invalid, out.invalid());
        assert_eq!(out.grasp.verdict.rules, out.invalid());
        let g = &out.grasp;
        assert!(g.friction_ok(gripper.mu()));
        assert_eq!(
            (contact.radius, contact.center),
            (direct.radius, direct.center)
        );
    }

    #[test]
    fn warnings_are_every_warning_once() {
        // the actuator's note reaches the finger, the gripper and the grasp:
        // it is listed once, with the design note and the grasp's findings
        let text = "[actuator.pemc]\neps0 = 0.62\n[gripper]\nmounting_angle_deg = 30\npalm_mm = 40\n[gripper.grasp]\nd_mm = 140\n";
        let scene = Scene::from_toml(text).unwrap();
        assert_eq!(scene.warnings().len(), 1);
        let sol = scene.solve().unwrap();
        let w = sol.warnings();
        let count = |kind: &str| w.iter().filter(|w| w.kind() == kind).count();
        assert_eq!(count("eps0_outside_fit"), 1, "{w:?}");
        assert_eq!(count("mounting_angle_outside_design_space"), 1, "{w:?}");
        assert_eq!(count("curvature_reversal"), 1, "{w:?}");
        for (i, a) in w.iter().enumerate() {
            assert!(!w[i + 1..].contains(a), "{a:?} twice in {w:?}");
        }
        // a finger scene: the solution's findings
        let sol = Scene::from_toml("[partition]\nelements = 2\n[load]\npressure_kpa = 60\n")
            .unwrap()
            .solve()
            .unwrap();
        assert!(!sol.warnings().is_empty());
        assert_eq!(sol.warnings(), sol.solution().warnings);
    }
}

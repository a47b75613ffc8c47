//! `fpc.solve_scene`: a scene file solved as `fpc solve` solves it, with
//! the keys of its `solution.json` (crates/cli/src/solve.rs; the tests
//! compare the two key by key).

use pyo3::prelude::*;
use pyo3::types::PyDict;
use serde::Serialize;

use fpc::scene::{warning_text, GraspOutcome, SceneFile, SceneSolution};
use fpc::{Coefficients, Gripper, Invalid, Solution, SolveReport, Warning};

use crate::convert::{array1, array2, json_to_py, points};
use crate::errors::{detached, from_solve};
use crate::finger::read_scene;

/// `solution.json`.
#[derive(Serialize)]
struct SolutionFile<'a> {
    scene_name: &'a str,
    kind: &'static str,
    elements: usize,
    tip_error_estimate_mm: Option<f64>,
    #[serde(flatten)]
    solution: SolutionKeys<'a>,
    validity: bool,
    warnings: Vec<Warning>,
    warning_messages: Vec<String>,
    scene: &'a SceneFile,
    #[serde(flatten)]
    gripper: Option<GripperKeys<'a>>,
}

/// The keys of a [`Solution`] but its `warnings`.
#[derive(Serialize)]
struct SolutionKeys<'a> {
    tip_mm: &'a [f64; 2],
    end_angle_rad: f64,
    radius_mm: Option<f64>,
    energy_nmm: f64,
    negative_eigenvalues: Option<usize>,
    stable: Option<bool>,
    coefficients: &'a Coefficients,
    points_mm: &'a [[f64; 2]],
    element_lengths_mm: &'a [f64],
    report: &'a SolveReport,
}

impl<'a> SolutionKeys<'a> {
    fn of(s: &'a Solution) -> SolutionKeys<'a> {
        SolutionKeys {
            tip_mm: &s.tip,
            end_angle_rad: s.end_angle,
            radius_mm: s.radius,
            energy_nmm: s.energy,
            negative_eigenvalues: s.negative_eigenvalues,
            stable: s.stable,
            coefficients: &s.coefficients,
            points_mm: &s.points,
            element_lengths_mm: &s.element_lengths,
            report: &s.report,
        }
    }
}

/// The keys only a gripper scene has.
#[derive(Serialize)]
struct GripperKeys<'a> {
    gripper: GripperJson<'a>,
    grasp: Option<GraspJson<'a>>,
    points_gripper_mm: Vec<[f64; 2]>,
}

/// The gripper: the library's keys and three of its design's at the top.
#[derive(Serialize)]
pub struct GripperJson<'a> {
    mounting_angle_deg: f64,
    mu: f64,
    fingers: usize,
    #[serde(flatten)]
    gripper: &'a Gripper,
}

impl<'a> GripperJson<'a> {
    pub fn of(gripper: &'a Gripper) -> GripperJson<'a> {
        GripperJson {
            mounting_angle_deg: degrees(gripper.mounting_angle()),
            mu: gripper.mu(),
            fingers: gripper.params().fingers,
            gripper,
        }
    }
}

/// A solved grasp, per finger.
#[derive(Serialize)]
pub struct GraspJson<'a> {
    kind: &'static str,
    pressure_kpa: f64,
    beta_deg: f64,
    normal_force_n: f64,
    friction_n: f64,
    friction_limit_n: f64,
    lift_n: f64,
    size_mm: f64,
    tip_gap_mm: f64,
    height_mm: f64,
    tip_gripper_mm: [f64; 2],
    tip_load_finger_n: [f64; 2],
    valid: bool,
    invalid: Option<&'a Invalid>,
    #[serde(skip_serializing_if = "Option::is_none")]
    sphere_radius_mm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    sphere_center_gripper_mm: Option<[f64; 2]>,
}

impl<'a> GraspJson<'a> {
    pub fn of(gripper: &Gripper, o: &'a GraspOutcome) -> GraspJson<'a> {
        let g = &o.grasp;
        GraspJson {
            kind: o.spec.name(),
            pressure_kpa: g.pressure_kpa,
            beta_deg: degrees(g.beta),
            normal_force_n: g.normal,
            friction_n: g.friction,
            friction_limit_n: gripper.mu() * g.normal,
            lift_n: g.lift,
            size_mm: g.size,
            tip_gap_mm: g.tip_gap,
            height_mm: g.height,
            tip_gripper_mm: g.tip,
            tip_load_finger_n: [g.load.fx, g.load.fz],
            valid: o.is_valid(),
            invalid: o.invalid.as_ref(),
            sphere_radius_mm: o.sphere.map(|s| s.radius),
            sphere_center_gripper_mm: o.sphere.map(|s| s.center),
        }
    }
}

/// Radians in degrees, rounded to 1e-9 deg (as `fpc solve` writes them).
pub fn degrees(rad: f64) -> f64 {
    (rad.to_degrees() * 1e9).round() / 1e9
}

fn solution_file<'a>(
    stem: &'a str,
    file: &'a SceneFile,
    solved: &'a SceneSolution,
) -> SolutionFile<'a> {
    let warnings = solved.warnings();
    let (kind, tip_error_estimate_mm, gripper) = match solved {
        SceneSolution::Finger {
            tip_error_estimate_mm,
            ..
        } => ("finger", *tip_error_estimate_mm, None),
        SceneSolution::Gripper { gripper, grasp } => (
            if grasp.is_some() { "grasp" } else { "gripper" },
            None,
            Some(GripperKeys {
                gripper: GripperJson::of(gripper),
                grasp: grasp.as_deref().map(|o| GraspJson::of(gripper, o)),
                points_gripper_mm: solved
                    .solution()
                    .points
                    .iter()
                    .map(|&p| gripper.to_gripper(p))
                    .collect(),
            }),
        ),
    };
    let grasp_valid = match solved {
        SceneSolution::Gripper { grasp: Some(g), .. } => g.is_valid(),
        _ => true,
    };
    SolutionFile {
        scene_name: stem,
        kind,
        elements: solved.elements(),
        tip_error_estimate_mm,
        solution: SolutionKeys::of(solved.solution()),
        validity: grasp_valid && !warnings.iter().any(Warning::is_validity),
        warning_messages: warnings.iter().map(warning_text).collect(),
        warnings,
        scene: file,
        gripper,
    }
}

/// Solves a scene as ``fpc solve`` does and returns the contents of its
/// ``solution.json`` as a dict, with the arrays as numpy arrays: ``tip_mm``,
/// ``coefficients`` (elements x unknowns), ``points_mm`` (n x 2),
/// ``element_lengths_mm`` and, in a gripper scene, ``points_gripper_mm``.
/// The other keys are as in the file: ``scene_name``, ``kind`` (``finger``,
/// ``gripper``, ``grasp``), ``elements``, ``tip_error_estimate_mm``,
/// ``end_angle_rad``, ``radius_mm``, ``energy_nmm``,
/// ``negative_eigenvalues``, ``stable``, ``report``, ``validity``,
/// ``warnings``, ``warning_messages``, ``scene`` (every default written
/// out) and, in a gripper scene, ``gripper`` and ``grasp``.
///
/// ``scene``: TOML text or a path to a scene file. ``name``: the
/// ``scene_name`` (default: the file's stem, ``"scene"`` for text).
/// Raises ``fpc.SceneError`` for a syntax error or unknown key,
/// ``fpc.InputError`` naming the scene key of a rejected value, and
/// ``fpc.SolveError`` when the solve fails.
#[pyfunction]
#[pyo3(signature = (scene, name=None))]
pub fn solve_scene<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    name: Option<String>,
) -> PyResult<Bound<'py, PyDict>> {
    let (scene, shown) = read_scene(scene)?;
    let stem = name.unwrap_or_else(|| {
        std::path::Path::new(&shown)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| "scene".into())
    });
    let solved = detached(py, || scene.solve())?.map_err(|e| from_solve(py, &e))?;
    let value = serde_json::to_value(solution_file(&stem, scene.file(), &solved))
        .map_err(|e| crate::errors::InternalError::new_err(format!("serialization: {e}")))?;
    let d = json_to_py(py, &value)?.cast_into::<PyDict>()?;
    let s = solved.solution();
    d.set_item("tip_mm", array1(py, s.tip.to_vec()))?;
    d.set_item(
        "coefficients",
        array2(
            py,
            s.coefficients.as_slice().to_vec(),
            s.coefficients.per_element(),
        )?,
    )?;
    d.set_item("points_mm", points(py, &s.points)?)?;
    d.set_item("element_lengths_mm", array1(py, s.element_lengths.clone()))?;
    if let SceneSolution::Gripper { gripper, .. } = &solved {
        let g: Vec<[f64; 2]> = s.points.iter().map(|&p| gripper.to_gripper(p)).collect();
        d.set_item("points_gripper_mm", points(py, &g)?)?;
    }
    Ok(d)
}

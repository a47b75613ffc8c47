//! `fpc.solve_scene`: a scene file solved as `fpc solve` solves it, with
//! the keys of its `solution.json` (both from the library's
//! `fpc::scene::SolutionRecord`; the tests compare the two key by key).

use pyo3::prelude::*;
use pyo3::types::PyDict;

use fpc::scene::{SceneSolution, SolutionRecord};

use crate::convert::{array1, coefficients, points, to_py};
use crate::errors::{detached, from_solve};
use crate::scene_input::read_scene;

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
/// ``scene``: TOML text or a path to a scene file (an ``os.PathLike``, or
/// a one-line ``str`` ending in ``.toml`` or containing ``/``; a missing
/// file is ``FileNotFoundError``, one over 4 MiB or a directory an
/// ``OSError``). ``name``: the
/// ``scene_name`` (default: the file's stem, ``"scene"`` for text).
/// Raises ``fpc.SceneError`` for a syntax error or unknown key,
/// ``fpc.InputError`` naming the scene key of a rejected value, and
/// ``fpc.SolveError`` when the solve fails.
#[pyfunction]
#[pyo3(signature = (scene, name=None))]
pub fn solve_scene<'py>(
    py: Python<'py>,
    scene: &Bound<'py, PyAny>,
    name: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let name: Option<String> = crate::convert::opt_arg("name", name)?;
    let (scene, shown) = read_scene(scene)?;
    let stem = name.unwrap_or_else(|| {
        std::path::Path::new(&shown)
            .file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .filter(|s| !s.is_empty())
            .unwrap_or_else(|| "scene".into())
    });
    let (solved, uncertainty) = detached(py, || {
        let solved = scene.solve()?;
        let u = scene.uncertainty(&solved)?;
        Ok::<_, fpc::SolveError>((solved, u))
    })?
    .map_err(|e| from_solve(py, &e))?;
    // a calibrated scene's 1-sigma error bars, as fpc solve's solution.json has them
    let record =
        SolutionRecord::new(&stem, scene.file(), &solved).with_uncertainty(uncertainty.as_ref());
    let d = to_py(py, &record)?.cast_into::<PyDict>()?;
    let s = solved.solution();
    d.set_item("tip_mm", array1(py, s.tip.to_vec()))?;
    d.set_item("coefficients", coefficients(py, &s.coefficients)?)?;
    d.set_item("points_mm", points(py, &s.points)?)?;
    d.set_item("element_lengths_mm", array1(py, s.element_lengths.clone()))?;
    if let SceneSolution::Gripper { gripper, .. } = &solved {
        let g: Vec<[f64; 2]> = s.points.iter().map(|&p| gripper.to_gripper(p)).collect();
        d.set_item("points_gripper_mm", points(py, &g)?)?;
    }
    Ok(d)
}

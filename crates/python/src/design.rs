//! `fpc.design`: inverse design from a requirements TOML (the library's
//! `fpc::design`, as `fpc design` runs it).

use pyo3::prelude::*;
use pyo3::types::PyDict;

use fpc::design::{
    optimize, DesignBase, DesignOptions, Requirements, RequirementsError, VARIABLES,
};
use fpc::scene::Scene;

use crate::convert::{scene_list, to_py};
use crate::errors::{from_input, from_scene_read, from_syntax, interruptible};
use crate::scene_input::scene_text;

/// The design that meets every requirement with the largest worst-case
/// margin, or the least-violating one.
///
/// ``design(requirements, starts=2, seed=1, scene=None)``
///
/// - ``requirements``: TOML text or a path to a requirements file (the keys
///   of ``fpc design``, README "Inverse design");
/// - ``starts``: random starts of the optimiser besides the centre and the
///   corners of the bounds (at most 10000, else ``InputError``); ``seed``
///   seeds them;
/// - ``scene``: design from this scene's finger (TOML text or a path, as
///   ``solve_scene`` takes it; a calibrated scene from ``fpc.calibrate``,
///   say) as ``fpc design --scene`` does: its element model, actuator,
///   ``load.kappa`` and ``[calibration]`` table, its eps0 unless eps0
///   varies. ``None``: the paper's actuator.
///
/// Returns a dict: ``feasible``, ``best`` (``design``: ``{"eps0",
/// "mounting_angle_deg", "overlap_mm", "varied"}`` as in ``fpc design``'s
/// design.json; ``margins`` per requirement with ``requirement``,
/// ``margin`` (normalised; >= 0 is met), ``detail``, ``notes`` (what the
/// sample's solution carries without being voided by it; absent when
/// none)..., and ``worst``),
/// ``sensitivities`` (per requirement: ``requirement`` and ``gradient``,
/// d margin / d variable as ``{"eps0", "mounting_angle_deg",
/// "overlap_mm"}``, per unit of each), ``evaluations``, ``starts``,
/// ``failure``, ``reproductions`` (each object's scene solved again:
/// ``file``, ``valid``, ``reproduced``, ``detail`` and ``notes``, what does
/// not void the grasp, such as a reversed element outside strict mode) and
/// ``scenes``: one ``{"name", "toml"}`` per object, a scene that ``fpc
/// solve`` or ``solve_scene`` runs to reproduce the claimed grasp; ``notes``
/// on the requirements as ``fpc design`` prints them (bounds clamped to
/// the design space, the base scene).
///
/// ``requirements`` is read as a path when it is an ``os.PathLike`` or a
/// one-line ``str`` ending in ``.toml`` or containing ``/`` (a missing file
/// is ``FileNotFoundError``, one over 4 MiB or a directory an
/// ``OSError`` naming it), else as TOML text. Raises ``fpc.SceneError``
/// (with ``line`` and ``col``) for a syntax error or an unknown key, and
/// ``fpc.InputError`` naming the field of a rejected value (``starts``
/// beyond 10000: ``design.random_starts``), with ``line`` and ``col``
/// where the requirements write that value. Ctrl-C returns at once with
/// ``KeyboardInterrupt`` (the search finishes on its own thread and is
/// dropped).
#[pyfunction]
#[pyo3(signature = (requirements, starts=None, seed=None, scene=None))]
#[pyo3(text_signature = "(requirements, starts=2, seed=1, scene=None)")]
pub fn design<'py>(
    py: Python<'py>,
    requirements: &Bound<'py, PyAny>,
    starts: Option<&Bound<'py, PyAny>>,
    seed: Option<&Bound<'py, PyAny>>,
    scene: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let starts: usize = crate::convert::arg_or("starts", starts, 2)?;
    let seed: u64 = crate::convert::arg_or("seed", seed, 1)?;
    let (text, shown) = scene_text(requirements)?;
    let mut req = Requirements::parse(&text).map_err(|e| match &e {
        RequirementsError::Input(i) => {
            // where the file writes the value, as a syntax error has it
            let err = from_input(py, i);
            if let Some((line, col)) = e.position(&text) {
                let v = err.value(py);
                let _ = v.setattr("line", line);
                let _ = v.setattr("col", col);
            }
            err
        }
        RequirementsError::Syntax(s) => from_syntax(py, s, &shown),
    })?;
    if let Some(obj) = scene {
        let (text, shown) = scene_text(obj)?;
        let base = Scene::from_toml(&text).map_err(|e| from_scene_read(py, &e, &shown))?;
        req = req.with_base(DesignBase::from_scene(&base, format!("the scene {shown}")));
    }
    let opts = DesignOptions {
        random_starts: starts,
        seed,
        ..DesignOptions::default()
    };
    opts.validate().map_err(|e| from_input(py, &e))?;
    let bounds = req.bounds();
    let notes = req.notes();
    let (found, scenes) = interruptible(py, move || {
        let found = optimize(&req, &opts)?;
        let scenes = found.scenes(&req);
        Ok::<_, fpc::InputError>((found, scenes))
    })?
    .map_err(|e| from_input(py, &e))?;
    let d = to_py(py, &found)?.cast_into::<PyDict>()?;
    // the design variables by name, as design.json has them
    let named = |x: [f64; 3]| -> PyResult<Bound<'py, PyDict>> {
        let v = PyDict::new(py);
        for (name, value) in VARIABLES.iter().zip(x) {
            v.set_item(*name, value)?;
        }
        Ok(v)
    };
    let design = named(found.best.design)?;
    let varied: Vec<&str> = VARIABLES
        .iter()
        .zip(bounds)
        .filter(|(_, b)| b[1] > b[0])
        .map(|(n, _)| *n)
        .collect();
    design.set_item("varied", varied)?;
    d.get_item("best")?
        .ok_or_else(|| crate::errors::InternalError::new_err("design: no best"))?
        .set_item("design", design)?;
    let sens = pyo3::types::PyList::empty(py);
    for s in &found.sensitivities {
        let e = PyDict::new(py);
        e.set_item("requirement", &s.requirement)?;
        e.set_item("gradient", named(s.gradient)?)?;
        sens.append(e)?;
    }
    d.set_item("sensitivities", sens)?;
    d.set_item("scenes", scene_list(py, scenes)?)?;
    d.set_item("notes", notes)?;
    Ok(d)
}

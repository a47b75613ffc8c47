//! `fpc.design`: inverse design from a requirements TOML (the library's
//! `fpc::design`, as `fpc design` runs it).

use pyo3::prelude::*;
use pyo3::types::PyDict;

use fpc::design::{optimize, DesignOptions, Requirements, RequirementsError};

use crate::convert::to_py;
use crate::errors::{detached, from_input, from_syntax};
use crate::finger::scene_text;

/// The design that meets every requirement with the largest worst-case
/// margin, or the least-violating one.
///
/// ``design(requirements, starts=2, seed=1)``
///
/// - ``requirements``: TOML text or a path to a requirements file (the keys
///   of ``fpc design``, README "Inverse design");
/// - ``starts``: random starts of the optimiser besides the centre and the
///   corners of the bounds (at most 10000, else ``InputError``); ``seed``
///   seeds them.
///
/// Returns a dict: ``feasible``, ``best`` (``design`` as ``[eps0,
/// mounting_angle_deg, overlap_mm]``, ``margins`` per requirement with
/// ``requirement``, ``margin`` (normalised; >= 0 is met), ``detail``...,
/// and ``worst``), ``sensitivities`` (d margin / d variable per
/// requirement), ``evaluations``, ``starts`` and ``scenes``: one
/// ``{"name", "toml"}`` per object, a scene that ``fpc solve`` or
/// ``solve_scene`` runs to reproduce the claimed grasp.
///
/// Raises ``fpc.SceneError`` (with ``line`` and ``col``) for a syntax error
/// or an unknown key, and ``fpc.InputError`` naming the field of a rejected
/// value.
#[pyfunction]
#[pyo3(signature = (requirements, starts=2, seed=1))]
pub fn design<'py>(
    py: Python<'py>,
    requirements: &Bound<'py, PyAny>,
    starts: usize,
    seed: u64,
) -> PyResult<Bound<'py, PyDict>> {
    let (text, shown) = scene_text(requirements)?;
    let req = Requirements::parse(&text).map_err(|e| match e {
        RequirementsError::Input(i) => from_input(py, &i),
        RequirementsError::Syntax(s) => from_syntax(py, &s, &shown),
    })?;
    let opts = DesignOptions {
        random_starts: starts,
        seed,
        ..DesignOptions::default()
    };
    let (found, scenes) = detached(py, || {
        let found = optimize(&req, &opts)?;
        let scenes = found.scenes(&req);
        Ok::<_, fpc::InputError>((found, scenes))
    })?
    .map_err(|e| from_input(py, &e))?;
    let d = to_py(py, &found)?.cast_into::<PyDict>()?;
    let list = pyo3::types::PyList::empty(py);
    for (name, toml) in scenes {
        let s = PyDict::new(py);
        s.set_item("name", name)?;
        s.set_item("toml", toml)?;
        list.append(s)?;
    }
    d.set_item("scenes", list)?;
    Ok(d)
}

//! The Python module `fpc`: fluidic prestressed composite fingers and the
//! soft grippers built from them (the chained composite model), from
//! Python. A thin layer over the `fpc` library: every number comes from
//! it; this crate converts arguments, results (dicts of numpy arrays) and
//! errors, releases the GIL while solving, and runs batches in parallel.
//!
//! - [`actuator_args`]: the keyword arguments that describe an actuator;
//! - [`finger`]: `fpc.Finger` and its own arguments (model, elements, load);
//! - [`scene_input`]: scene arguments (TOML text or a path) and file errors;
//! - [`scene`]: `fpc.solve_scene` (the dict of `fpc solve`'s solution.json);
//! - [`gripper`]: `fpc.Gripper` and its grasp solves and sweeps;
//! - [`studies`]: `fpc.run_study`, `fpc.studies`;
//! - [`design`]: `fpc.design`, inverse design from requirements;
//! - [`batch`]: `fpc.batch_solve`, parallel (rayon);
//! - [`errors`]: the exceptions, and the guard that keeps panics inside.

use pyo3::prelude::*;

pub mod actuator_args;
pub mod batch;
pub mod convert;
pub mod design;
pub mod errors;
pub mod finger;
pub mod gripper;
pub mod measure;
pub mod scene;
pub mod scene_input;
pub mod studies;

/// Fluidic prestressed composite fingers and soft grippers: the chained
/// composite model (CCM), from Python.
///
/// - ``Finger``: one finger; ``Finger.solve`` returns a dict of numpy arrays;
/// - ``solve_scene``: a TOML scene solved as ``fpc solve`` solves it;
/// - ``Gripper``: grasp solves (size, cuboid, sphere) and sweeps;
/// - ``run_study``: the paper's studies, tables as numpy arrays;
/// - ``design``: the gripper to build for a requirements file;
/// - ``batch_solve``: many solves in parallel, the GIL released.
///
/// Errors: ``InputError`` (a ``ValueError`` naming the field), ``SceneError``
/// (a ``ValueError`` with ``line`` and ``col``), ``SolveError`` (a
/// ``RuntimeError``), ``InternalError`` (a bug, never a crash).
#[pymodule(name = "fpc")]
fn fpc_module(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<finger::Finger>()?;
    m.add_class::<gripper::Gripper>()?;
    m.add_function(wrap_pyfunction!(finger::models, m)?)?;
    m.add_function(wrap_pyfunction!(scene::solve_scene, m)?)?;
    m.add_function(wrap_pyfunction!(studies::studies, m)?)?;
    m.add_function(wrap_pyfunction!(studies::run_study, m)?)?;
    m.add_function(wrap_pyfunction!(design::design, m)?)?;
    m.add_function(wrap_pyfunction!(measure::compare, m)?)?;
    m.add_function(wrap_pyfunction!(measure::calibrate, m)?)?;
    m.add_function(wrap_pyfunction!(batch::batch_solve, m)?)?;
    m.add_function(wrap_pyfunction!(batch::_batch_reference, m)?)?;
    m.add("InputError", py.get_type::<errors::InputError>())?;
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add("SolveError", py.get_type::<errors::SolveError>())?;
    m.add("MeasureError", py.get_type::<errors::MeasureError>())?;
    m.add("InternalError", py.get_type::<errors::InternalError>())?;
    m.add(
        "BATCH_STATUS",
        pyo3::types::PyTuple::new(py, batch::STATUS_NAMES)?,
    )?;
    m.add(
        "PAPER_EPS0",
        pyo3::types::PyTuple::new(py, fpc::studies::PAPER_EPS0)?,
    )?;
    Ok(())
}

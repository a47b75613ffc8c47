//! A lab's measurements: `fpc.compare`, the model against them with no
//! fitting (docs/measurements.md), and `fpc.calibrate`, the parameters
//! that fit them (docs/calibration.md).

use std::path::Path;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use fpc::calibrate::{calibrated_scenes, CalibrateOptions};
use fpc::measure::{Comparison, Manifest};

use crate::convert::{array1, array2, scene_list, to_py};
use crate::errors::{from_measure, from_solve, interruptible};
use crate::scene_input::io_error;

/// The model against the measurements of a manifest (``str`` or
/// ``os.PathLike``; its CSV files are found relative to it), as ``fpc
/// compare`` computes them: no parameter is fitted.
///
/// Returns a dict with the keys of ``fpc compare --json`` (``manifest``,
/// ``chi_square``, ``points``, ``specimens`` with their ``tests`` and
/// each row's ``predictions``...), and in every test ``arrays``: one entry
/// per measured quantity of every row, in file order, as 1-D float arrays
/// ``pressure_kpa``, ``measured``, ``sd``, ``predicted``, ``residual`` and
/// ``residual_sd`` (NaN where the model has no prediction), with the
/// list ``quantity`` (``x_mm``, ``z_mm``, ``radius_mm`` or ``force_n``).
///
/// A missing manifest is ``FileNotFoundError``; bad measurement input
/// ``fpc.MeasureError`` (``.file``, ``.line``, ``.col``, ``.field``); an
/// actuator the model cannot be built for ``fpc.InputError``. Ctrl-C
/// interrupts.
#[pyfunction]
#[pyo3(signature = (manifest))]
pub fn compare<'py>(py: Python<'py>, manifest: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyDict>> {
    let m = read_manifest(py, manifest)?;
    let c = interruptible(py, move || fpc::compare(&m))?.map_err(|e| from_solve(py, &e))?;
    let d = to_py(py, &c)?.cast_into::<PyDict>()?;
    add_arrays(py, &d, &c)?;
    Ok(d)
}

/// The parameters that make the model match the measurements of a
/// manifest (``str`` or ``os.PathLike``), as ``fpc calibrate`` fits them:
/// weighted least squares (Levenberg-Marquardt with bounds) on the exact
/// Jacobian (docs/calibration.md).
///
/// - ``fit``: the parameters, a list of names or one comma-separated
///   ``str`` (``"eps0,kappa"``; scene keys such as ``actuator.cl.e``, the
///   short names ``eps0``, ``kappa``, ``p1``...``p4``,
///   ``shear_correction``, or ``camera``; the shear model's
///   ``actuator.laminate.shear_correction`` and ``actuator.cl.g13``...); at
///   most 16 names.
/// - ``max_iterations``: 1 to 1000 (default 100).
/// - ``cross_validate``: also predict each pressure left out in turn.
/// - ``choose_model``: also fit with every element model, with the
///   manifest's ribs and without, in plane stress and in plane strain
///   across the width, and rank them by held-out error (``model_choice``:
///   ``candidates``, each with ``model``, ``ribs``, ``plane_strain``,
///   ``held_out_rms_sd``..., and ``best``, as ``fpc calibrate
///   --choose-model`` writes it).
///
/// Returns a dict with the keys of ``calibration.json`` (``parameters``
/// with ``name``, ``value``, ``standard_error``..., ``identifiability``
/// with its ``verdict`` and ``message``, ``chi_square_per_dof``,
/// ``residuals``, ``iterations``, ``reproduction``: the calibrated scenes
/// compared with the data again through ``compare``'s path, with
/// ``reproduced`` and ``detail``, ...), and ``values`` and
/// ``standard_errors`` (NaN where not determined) as arrays in the order
/// of ``parameters``, ``covariance`` and ``correlation`` as square arrays
/// (None when the data do not determine the parameters), and ``scenes``:
/// one ``{"name", "toml"}`` per specimen, its calibrated scene file.
///
/// Raises ``FileNotFoundError``, ``fpc.MeasureError`` for bad
/// measurement input, ``fpc.InputError`` naming ``fit``,
/// ``max_iterations`` or a parameter; Ctrl-C interrupts.
#[pyfunction]
#[pyo3(signature = (manifest, fit, *, max_iterations=None, cross_validate=None, choose_model=None))]
#[pyo3(
    text_signature = "(manifest, fit, *, max_iterations=100, cross_validate=False, choose_model=False)"
)]
pub fn calibrate<'py>(
    py: Python<'py>,
    manifest: &Bound<'py, PyAny>,
    fit: &Bound<'py, PyAny>,
    max_iterations: Option<&Bound<'py, PyAny>>,
    cross_validate: Option<&Bound<'py, PyAny>>,
    choose_model: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    use crate::convert::arg_or;
    let max_iterations: usize = arg_or("max_iterations", max_iterations, 100)?;
    let cross_validate: bool = arg_or("cross_validate", cross_validate, false)?;
    let choose_model: bool = arg_or("choose_model", choose_model, false)?;
    let names: Vec<String> = match fit.extract::<String>() {
        Ok(s) => s.split(',').map(|n| n.trim().to_string()).collect(),
        Err(_) => fit.extract().map_err(|_| {
            PyTypeError::new_err("fit is a list of parameter names or one comma-separated str")
        })?,
    };
    let options = CalibrateOptions {
        fit: names,
        max_iterations,
        cross_validate,
    };
    let m = read_manifest(py, manifest)?;
    let (c, scenes, choice) = interruptible(py, move || {
        let c = fpc::calibrate::calibrate(&m, &options)?;
        let scenes = calibrated_scenes(&m, &c)?;
        let choice = if choose_model {
            Some(fpc::calibrate::choose_model(&m, &options)?)
        } else {
            None
        };
        Ok::<_, fpc::SolveError>((c, scenes, choice))
    })?
    .map_err(|e| from_solve(py, &e))?;
    let d = to_py(py, &c)?.cast_into::<PyDict>()?;
    if let Some(choice) = &choice {
        d.set_item("model_choice", to_py(py, choice)?)?;
    }
    let n = c.parameters.len();
    d.set_item(
        "values",
        array1(py, c.parameters.iter().map(|p| p.value).collect()),
    )?;
    d.set_item(
        "standard_errors",
        array1(
            py,
            c.parameters
                .iter()
                .map(|p| p.standard_error.unwrap_or(f64::NAN))
                .collect(),
        ),
    )?;
    for (key, m) in [
        ("covariance", &c.covariance),
        ("correlation", &c.correlation),
    ] {
        match m {
            Some(rows) => d.set_item(
                key,
                array2(py, rows.iter().flatten().copied().collect(), n)?,
            )?,
            None => d.set_item(key, py.None())?,
        }
    }
    d.set_item("scenes", scene_list(py, scenes)?)?;
    Ok(d)
}

/// Reads a manifest argument (a path): a missing file is
/// `FileNotFoundError`, bad measurement input `fpc.MeasureError`.
fn read_manifest(py: Python<'_>, manifest: &Bound<'_, PyAny>) -> PyResult<Manifest> {
    let os = py.import("os")?;
    let path: String = os
        .call_method1("fspath", (manifest,))
        .and_then(|p| p.extract())
        .map_err(|_| {
            PyTypeError::new_err(format!(
                "a manifest is a path (str or os.PathLike), not {}",
                manifest
                    .get_type()
                    .name()
                    .map(|n| n.to_string())
                    .unwrap_or_default()
            ))
        })?;
    if let Err(e) = std::fs::metadata(&path) {
        let message = format!("cannot read the manifest {path}: {e}");
        return Err(io_error(py, &e.into(), message, &path));
    }
    Manifest::load(Path::new(&path)).map_err(|e| from_measure(py, &e))
}

/// Each test's residuals as arrays, beside its records.
fn add_arrays<'py>(py: Python<'py>, d: &Bound<'py, PyDict>, c: &Comparison) -> PyResult<()> {
    let specimens = d
        .get_item("specimens")?
        .ok_or_else(|| crate::errors::InternalError::new_err("compare: no specimens"))?
        .cast_into::<PyList>()?;
    for (s, spec) in c.specimens.iter().zip(specimens.iter()) {
        let tests = spec.get_item("tests")?.cast_into::<PyList>()?;
        for (t, test) in s.tests.iter().zip(tests.iter()) {
            let or_nan = |v: Option<f64>| v.unwrap_or(f64::NAN);
            let rows = || {
                t.predictions
                    .iter()
                    .flat_map(|p| p.residuals.iter().map(move |r| (p, r)))
            };
            let a = PyDict::new(py);
            a.set_item(
                "quantity",
                rows().map(|(_, r)| r.quantity).collect::<Vec<_>>(),
            )?;
            let columns: [(&str, Vec<f64>); 6] = [
                (
                    "pressure_kpa",
                    rows().map(|(p, _)| p.pressure_kpa).collect(),
                ),
                ("measured", rows().map(|(_, r)| r.measured).collect()),
                ("sd", rows().map(|(_, r)| r.sd).collect()),
                (
                    "predicted",
                    rows().map(|(_, r)| or_nan(r.predicted)).collect(),
                ),
                (
                    "residual",
                    rows().map(|(_, r)| or_nan(r.residual)).collect(),
                ),
                (
                    "residual_sd",
                    rows().map(|(_, r)| or_nan(r.residual_sd)).collect(),
                ),
            ];
            for (name, v) in columns {
                a.set_item(name, array1(py, v))?;
            }
            test.set_item("arrays", a)?;
        }
    }
    Ok(())
}

//! `fpc.compare`: the model against a lab's measurements, with no fitting
//! (docs/measurements.md).

use std::path::Path;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use fpc::measure::{Comparison, Manifest};

use crate::convert::{array1, to_py};
use crate::errors::{from_measure, from_solve, interruptible};
use crate::finger::io_error;

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
        return Err(io_error(
            &e,
            format!("cannot read the manifest {path}: {e}"),
            &path,
        ));
    }
    let m = Manifest::load(Path::new(&path)).map_err(|e| from_measure(py, &e))?;
    let c = interruptible(py, move || fpc::compare(&m))?.map_err(|e| from_solve(py, &e))?;
    let d = to_py(py, &c)?.cast_into::<PyDict>()?;
    add_arrays(py, &d, &c)?;
    Ok(d)
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

//! Conversions between library values and Python objects: JSON-like data
//! both ways, numpy arrays, and a [`fpc::Solution`] as a dict.

use numpy::{PyArray1, PyArray2, PyArrayMethods};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use serde_json::Value;

/// A JSON value as a Python object (objects as dicts, arrays as lists;
/// numbers keep their exact value).
pub fn json_to_py<'py>(py: Python<'py>, v: &Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => {
            if let Some(i) = n.as_i64() {
                i.into_pyobject(py)?.into_any()
            } else if let Some(u) = n.as_u64() {
                u.into_pyobject(py)?.into_any()
            } else {
                PyFloat::new(py, n.as_f64().unwrap_or(f64::NAN)).into_any()
            }
        }
        Value::String(s) => PyString::new(py, s).into_any(),
        Value::Array(a) => {
            let items = a
                .iter()
                .map(|x| json_to_py(py, x))
                .collect::<PyResult<Vec<_>>>()?;
            PyList::new(py, items)?.into_any()
        }
        Value::Object(m) => {
            let d = PyDict::new(py);
            for (k, x) in m {
                d.set_item(k, json_to_py(py, x)?)?;
            }
            d.into_any()
        }
    })
}

/// Any `Serialize` value as a Python object, through JSON.
pub fn to_py<'py, T: serde::Serialize + ?Sized>(
    py: Python<'py>,
    v: &T,
) -> PyResult<Bound<'py, PyAny>> {
    let v = serde_json::to_value(v)
        .map_err(|e| crate::errors::InternalError::new_err(format!("serialization: {e}")))?;
    json_to_py(py, &v)
}

/// A Python object of plain data (dict with str keys, list or tuple, str,
/// bool, int, float, None, numpy scalars and arrays through `tolist`) as JSON.
pub fn py_to_json(obj: &Bound<'_, PyAny>) -> PyResult<Value> {
    if obj.is_none() {
        return Ok(Value::Null);
    }
    if let Ok(b) = obj.cast::<PyBool>() {
        return Ok(Value::Bool(b.is_true()));
    }
    if obj.is_instance_of::<PyInt>() {
        if let Ok(i) = obj.extract::<i64>() {
            return Ok(Value::from(i));
        }
        if let Ok(u) = obj.extract::<u64>() {
            return Ok(Value::from(u));
        }
    }
    if obj.is_instance_of::<PyFloat>() {
        let x: f64 = obj.extract()?;
        // JSON has no NaN: keep it as a float the library then rejects by name
        return Ok(serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number));
    }
    if let Ok(s) = obj.cast::<PyString>() {
        return Ok(Value::String(s.extract::<String>()?));
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut m = serde_json::Map::new();
        for (k, v) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err("dictionary keys must be strings"))?;
            m.insert(k, py_to_json(&v)?);
        }
        return Ok(Value::Object(m));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let items = obj
            .try_iter()?
            .map(|x| py_to_json(&x?))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(Value::Array(items));
    }
    // numpy scalars and arrays
    if obj.hasattr("tolist")? {
        let plain = obj.call_method0("tolist")?;
        if !plain.is(obj) {
            return py_to_json(&plain);
        }
    }
    Err(PyTypeError::new_err(format!(
        "cannot use a value of type {} here (expected numbers, strings, booleans, lists or dicts)",
        obj.get_type().name()?
    )))
}

/// A vector as a 1-D float array.
pub fn array1<'py>(py: Python<'py>, v: Vec<f64>) -> Bound<'py, PyArray1<f64>> {
    PyArray1::from_vec(py, v)
}

/// Rows of `width` values as an `n x width` array (`0 x width` when empty).
pub fn array2<'py>(
    py: Python<'py>,
    flat: Vec<f64>,
    width: usize,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    let rows = flat.len().checked_div(width).unwrap_or(0);
    PyArray1::from_vec(py, flat).reshape([rows, width])
}

/// Points `[x, z]` as an `n x 2` array.
pub fn points<'py>(py: Python<'py>, pts: &[[f64; 2]]) -> PyResult<Bound<'py, PyArray2<f64>>> {
    array2(py, pts.iter().flatten().copied().collect(), 2)
}

/// Coefficients as an `elements x unknowns` array.
pub fn coefficients<'py>(
    py: Python<'py>,
    c: &fpc::Coefficients,
) -> PyResult<Bound<'py, PyArray2<f64>>> {
    array2(py, c.as_slice().to_vec(), c.per_element())
}

/// The warnings as a list of `{kind, message, element?, value?, limit?}`.
pub fn warnings<'py>(py: Python<'py>, w: &[fpc::Warning]) -> PyResult<Bound<'py, PyAny>> {
    to_py(py, w)
}

/// A solution as a dict: `tip` (mm, finger frame), `end_angle` (rad),
/// `radius` (mm or None), `energy` (N mm), `negative_eigenvalues`,
/// `stable`, `coefficients` (elements x unknowns), `points` (n x 2, mm),
/// `element_lengths` (mm), `warnings`, `valid` (no validity finding),
/// `report` and `elements`.
pub fn solution_dict<'py>(py: Python<'py>, s: &fpc::Solution) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("tip", array1(py, s.tip.to_vec()))?;
    d.set_item("end_angle", s.end_angle)?;
    d.set_item("radius", s.radius)?;
    d.set_item("energy", s.energy)?;
    d.set_item("negative_eigenvalues", s.negative_eigenvalues)?;
    d.set_item("stable", s.stable)?;
    d.set_item("coefficients", coefficients(py, &s.coefficients)?)?;
    d.set_item("points", points(py, &s.points)?)?;
    d.set_item("element_lengths", array1(py, s.element_lengths.clone()))?;
    d.set_item("warnings", warnings(py, &s.warnings)?)?;
    d.set_item("valid", s.is_within_model())?;
    d.set_item("report", report_dict(py, &s.report)?)?;
    d.set_item("elements", s.element_lengths.len())?;
    Ok(d)
}

/// A solve report as a dict (`reason`, `iterations`, `residual_norm`,
/// `evaluations`, `coupled`, `continuation_steps`, and `steps`: the
/// iterations by phase, `element`, `coupled`, `continuation`, and the
/// globalisation's `chord`, `shifted`, `damped`, `grown`, `extended`).
pub fn report_dict<'py>(
    py: Python<'py>,
    r: &fpc::finger::SolveReport,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("reason", r.reason.to_string())?;
    d.set_item("iterations", r.iterations)?;
    d.set_item("residual_norm", r.residual_norm)?;
    d.set_item("evaluations", r.evaluations)?;
    d.set_item("coupled", r.coupled)?;
    d.set_item("continuation_steps", r.continuation_steps)?;
    d.set_item("steps", to_py(py, &r.steps)?)?;
    Ok(d)
}

/// `v` as a float64 numpy array for the argument `name`: the one
/// conversion of every array argument (`batch_solve`'s inputs,
/// `Gripper.sweep`'s, `guess`). Numbers (bool, int, float, and objects
/// that convert to float) are converted; anything else is a `TypeError`
/// naming the argument, as for a scalar argument: strings are not parsed
/// (`eps0="0.3"`), and complex values (Python complex, complex numpy
/// dtype, or a list holding one) are refused rather than losing their
/// imaginary part. A value numpy cannot make an array of (a ragged list)
/// is `fpc.InputError` naming the argument.
pub fn real_array<'py>(
    py: Python<'py>,
    name: &str,
    v: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, PyAny>> {
    let np = py.import("numpy")?;
    let a = np.call_method1("asarray", (v,)).map_err(|e| {
        if e.is_instance_of::<PyTypeError>(py) {
            named(py, name, e)
        } else {
            crate::errors::input_error(py, name, format!("{name}: not an array of numbers ({e})"))
        }
    })?;
    let dtype = a.getattr("dtype")?;
    let kind: String = dtype.getattr("kind")?.extract()?;
    match kind.as_str() {
        "b" | "i" | "u" | "f" => np.call_method1("asarray", (a, "float64")),
        "c" => Err(PyTypeError::new_err(format!(
            "{name}: complex values are not accepted (real numbers only)"
        ))),
        // Python objects (ints beyond int64, None, Decimal, ...): as float
        // does them, or a wrong type
        "O" => a.call_method1("astype", ("float64",)).map_err(|e| {
            PyTypeError::new_err(format!("argument '{name}': must be real numbers ({e})"))
        }),
        other => {
            let what = match other {
                "U" => "str".to_string(),
                "S" => "bytes".to_string(),
                _ => dtype.str()?.to_string(),
            };
            Err(PyTypeError::new_err(format!(
                "argument '{name}': must be real numbers, not {what}"
            )))
        }
    }
}

/// Scene files as a list of `{"name", "toml"}` dicts (a design's or a
/// calibration's scenes).
pub fn scene_list<'py>(
    py: Python<'py>,
    scenes: Vec<(String, String)>,
) -> PyResult<Bound<'py, pyo3::types::PyList>> {
    let list = pyo3::types::PyList::empty(py);
    for (name, toml) in scenes {
        let s = PyDict::new(py);
        s.set_item("name", name)?;
        s.set_item("toml", toml)?;
        list.append(s)?;
    }
    Ok(list)
}

/// The argument `name` converted to `T`. A failed conversion keeps its
/// Python type (`TypeError` for a wrong type, `OverflowError` for an int
/// that does not fit) and its message names the argument as the caller
/// wrote it: `argument 'eps0': must be real number, not str`. (pyo3 only
/// attaches the name as a note, which `str(e)` does not show.)
pub fn arg<'py, T>(name: &str, obj: &Bound<'py, PyAny>) -> PyResult<T>
where
    T: pyo3::conversion::FromPyObjectOwned<'py>,
{
    obj.extract::<T>()
        .map_err(|e| named(obj.py(), name, e.into()))
}

/// An optional argument: absent or None is None, anything else as [`arg`].
pub fn opt_arg<'py, T>(name: &str, obj: Option<&Bound<'py, PyAny>>) -> PyResult<Option<T>>
where
    T: pyo3::conversion::FromPyObjectOwned<'py>,
{
    match obj {
        Some(o) if !o.is_none() => arg(name, o).map(Some),
        _ => Ok(None),
    }
}

/// An argument with a default: absent or None is `default`.
pub fn arg_or<'py, T>(name: &str, obj: Option<&Bound<'py, PyAny>>, default: T) -> PyResult<T>
where
    T: pyo3::conversion::FromPyObjectOwned<'py>,
{
    Ok(opt_arg(name, obj)?.unwrap_or(default))
}

/// `e` (a conversion error) as the same exception type, its message
/// prefixed with the argument's name.
pub fn named(py: Python<'_>, name: &str, e: PyErr) -> PyErr {
    let err = PyErr::from_type(
        e.get_type(py),
        format!("argument '{name}': {}", e.value(py)),
    );
    err.set_cause(py, e.cause(py));
    err
}

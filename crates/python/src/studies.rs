//! `fpc.run_study` and `fpc.studies`: the paper's studies from the
//! library's registry, their tables as dicts of numpy arrays.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};

use fpc::studies::{Cell, Table, INVALID, NOTE, STATUS, WARNINGS};
use fpc::studies::{StudyInfo, STUDIES};
use fpc::StudyOptions;

use crate::actuator_args::actuator_from_kwargs;
use crate::convert::{arg, arg_or, json_to_py, opt_arg, to_py};
use crate::errors::{from_input, from_solve, input_error, interruptible};

/// The study `study` names: its number (1 to 8) or its key.
fn find(py: Python<'_>, study: &Bound<'_, PyAny>) -> PyResult<&'static StudyInfo> {
    let keys = || {
        STUDIES
            .iter()
            .map(|s| format!("{} ({})", s.number, s.key))
            .collect::<Vec<_>>()
            .join(", ")
    };
    // a number or a key; any other type (a float, a bool) is a TypeError
    // naming the argument, as for any other argument
    let found = if let Ok(k) = study.extract::<String>() {
        STUDIES
            .iter()
            .find(|s| s.key == k || s.stem() == k || s.number.to_string() == k)
    } else if study.is_instance_of::<pyo3::types::PyBool>() {
        return Err(pyo3::exceptions::PyTypeError::new_err(
            "argument 'study': must be a study's number (int) or key (str), not bool",
        ));
    } else {
        let n: i64 = arg("study", study)?;
        STUDIES.iter().find(|s| s.number as i64 == n)
    };
    found.ok_or_else(|| {
        input_error(
            py,
            "study",
            format!("study = {study}: not a study (studies: {})", keys()),
        )
    })
}

/// A table column as a numpy array: numbers (empty cells NaN) as float64,
/// flags as bool, text (empty cells "") as a str array, the studies' text
/// columns (`status`, `note`, `invalid`, `warnings`) always; columns mixing
/// kinds (or flags with empty cells) as an object array (empty cells None).
fn column<'py>(py: Python<'py>, t: &Table, j: usize) -> PyResult<Bound<'py, PyAny>> {
    let cells: Vec<&Cell> = t.rows.iter().map(|r| &r[j]).collect();
    let all = |f: fn(&Cell) -> bool| cells.iter().all(|c| f(c));
    let np = py.import("numpy")?;
    // the studies' text columns are text whatever their cells (all empty
    // when every point is ok): the dtype must not depend on the content
    let text_column = [STATUS, NOTE, INVALID, WARNINGS].contains(&t.columns[j]);
    let any_text = cells.iter().any(|c| matches!(c, Cell::Text(_)));
    if (text_column || any_text) && all(|c| matches!(c, Cell::Text(_) | Cell::Empty)) {
        let v: Vec<&str> = cells
            .iter()
            .map(|c| match c {
                Cell::Text(s) => s.as_str(),
                _ => "",
            })
            .collect();
        return np.call_method1("array", (PyList::new(py, v)?, "str"));
    }
    if all(|c| matches!(c, Cell::Num(_) | Cell::Empty)) {
        let v: Vec<f64> = cells
            .iter()
            .map(|c| match c {
                Cell::Num(x) => *x,
                _ => f64::NAN,
            })
            .collect();
        return Ok(PyArray1::from_vec(py, v).into_any());
    }
    if all(|c| matches!(c, Cell::Bool(_))) {
        let v: Vec<bool> = cells
            .iter()
            .map(|c| matches!(c, Cell::Bool(true)))
            .collect();
        return Ok(PyArray1::from_vec(py, v).into_any());
    }
    let items = cells
        .iter()
        .map(|c| match c {
            Cell::Empty => Ok(py.None().into_bound(py)),
            c => to_py(py, *c),
        })
        .collect::<PyResult<Vec<_>>>()?;
    np.call_method1("array", (PyList::new(py, items)?, "object"))
}

/// The options of `run_study` that only some studies use, and the studies
/// (by number) that use each: any other study refuses them.
const STUDY_OPTIONS: [(&str, &[usize]); 5] = [
    ("sweep_points", &[1, 2, 3, 5]),
    ("angle_samples", &[5, 6]),
    ("pressure_points", &[7]),
    ("mu", &[1, 2, 3, 4, 5, 6]),
    ("strict", &[1, 2, 3, 4, 5, 6]),
];

/// `TypeError` for an option given to a study that does not use it.
fn check_used(info: &StudyInfo, given: &[(&str, bool)]) -> PyResult<()> {
    for &(name, is_given) in given {
        let Some((_, users)) = STUDY_OPTIONS.iter().find(|o| o.0 == name) else {
            continue;
        };
        if is_given && !users.contains(&info.number) {
            let users: Vec<String> = users.iter().map(|n| n.to_string()).collect();
            return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                "run_study({}): study {} ({}) does not use the keyword argument '{name}' \
                 (studies that do: {})",
                info.number,
                info.number,
                info.key,
                users.join(", ")
            )));
        }
    }
    Ok(())
}

/// A study's registry entry as a dict.
fn info_dict<'py>(py: Python<'py>, s: &StudyInfo) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    d.set_item("number", s.number)?;
    d.set_item("key", s.key)?;
    d.set_item("title", s.title)?;
    d.set_item("description", s.description)?;
    Ok(d)
}

/// The paper's studies: a list of ``{number, key, title, description}``.
#[pyfunction]
pub fn studies(py: Python<'_>) -> PyResult<Vec<Bound<'_, PyDict>>> {
    STUDIES.iter().map(|s| info_dict(py, s)).collect()
}

/// Runs one of the paper's studies (``fpc.studies()`` lists them) by its
/// number (1 to 8) or key, with the GIL released. Returns a dict:
///
/// - ``number``, ``key``, ``title``, ``description``;
/// - ``tables``: ``{table name: {column: numpy array}}``; numeric columns
///   are float64 (empty cells NaN), flags bool, text str arrays (empty
///   cells ""), mixed columns object arrays (empty cells None);
/// - ``units``: ``{table name: {column: unit or None}}``;
/// - ``columns``: ``{table name: [column names in order]}``;
/// - ``figure``: the figure's description (panels, series with their
///   points, axes, reference lines), ready to draw;
/// - ``summary``, ``overview``, ``notes``, ``stops``, ``design_warnings``,
///   ``points``, ``warnings_by_kind``, ``strict_dropped``.
///
/// Options left as None take the library's defaults (``coarse=True``: the
/// coarse sweeps of the tests): ``elements`` (8), ``mu`` (0.6),
/// ``sweep_points`` (32), ``angle_samples`` (24), ``pressure_points`` (21),
/// ``strict`` (False). ``**actuator``: the base actuator's keywords (as
/// for ``fpc.Finger``; each study sets the prestrain it needs).
///
/// An option the study does not use is a ``TypeError`` (``sweep_points``:
/// studies 1, 2, 3, 5; ``angle_samples``: 5, 6; ``pressure_points``: 7;
/// ``mu`` and ``strict``: 1 to 6), as is ``pemc={"eps0": ...}`` (each
/// study sets the prestrain it needs). The work is bounded before it starts
/// (``fpc.InputError`` beyond): ``sweep_points`` <= 2000,
/// ``angle_samples`` <= 200, and for study 5 ``sweep_points *
/// angle_samples * elements`` <= 800000 (100000 grasps of 8 elements,
/// about a minute; ``fpc::studies::MAX_SPHERE_WORK``), ``pressure_points`` <= 10000,
/// ``elements`` as for a finger. Ctrl-C returns at once with ``KeyboardInterrupt`` (the
/// interrupted study finishes on its own thread and is dropped).
#[pyfunction]
#[pyo3(signature = (study, *, elements=None, mu=None, sweep_points=None, angle_samples=None, pressure_points=None, strict=None, coarse=None, **actuator))]
#[pyo3(
    text_signature = "(study, *, elements=None, mu=None, sweep_points=None, angle_samples=None, pressure_points=None, strict=None, coarse=False, **actuator)"
)]
#[allow(clippy::too_many_arguments)]
pub fn run_study<'py>(
    py: Python<'py>,
    study: &Bound<'py, PyAny>,
    elements: Option<&Bound<'py, PyAny>>,
    mu: Option<&Bound<'py, PyAny>>,
    sweep_points: Option<&Bound<'py, PyAny>>,
    angle_samples: Option<&Bound<'py, PyAny>>,
    pressure_points: Option<&Bound<'py, PyAny>>,
    strict: Option<&Bound<'py, PyAny>>,
    coarse: Option<&Bound<'py, PyAny>>,
    actuator: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let elements: Option<usize> = opt_arg("elements", elements)?;
    let mu: Option<f64> = opt_arg("mu", mu)?;
    let sweep_points: Option<usize> = opt_arg("sweep_points", sweep_points)?;
    let angle_samples: Option<usize> = opt_arg("angle_samples", angle_samples)?;
    let pressure_points: Option<usize> = opt_arg("pressure_points", pressure_points)?;
    let strict: Option<bool> = opt_arg("strict", strict)?;
    let coarse: bool = arg_or("coarse", coarse, false)?;
    let info = find(py, study)?;
    check_used(
        info,
        &[
            ("sweep_points", sweep_points.is_some()),
            ("angle_samples", angle_samples.is_some()),
            ("pressure_points", pressure_points.is_some()),
            ("mu", mu.is_some()),
            ("strict", strict.is_some()),
        ],
    )?;
    let base = if coarse {
        StudyOptions::coarse()
    } else {
        StudyOptions::default()
    };
    // field by field: options the library adds keep their defaults
    let mut opts = base;
    opts.elements = elements.unwrap_or(base.elements);
    opts.mu = mu.unwrap_or(base.mu);
    opts.sweep_points = sweep_points.unwrap_or(base.sweep_points);
    opts.angle_samples = angle_samples.unwrap_or(base.angle_samples);
    opts.pressure_points = pressure_points.unwrap_or(base.pressure_points);
    opts.strict = strict.unwrap_or(base.strict);
    opts.validate().map_err(|e| from_input(py, &e))?;
    crate::actuator_args::refuse_pemc_eps0(actuator, "each study sets the prestrain it needs")?;
    let caller = crate::actuator_args::Caller {
        name: "run_study",
        keywords: &[
            "study",
            "elements",
            "mu",
            "sweep_points",
            "angle_samples",
            "pressure_points",
            "strict",
            "coarse",
        ],
    };
    let act = actuator_from_kwargs(py, caller, None, actuator)?;
    let out =
        interruptible(py, move || info.output(&act, &opts))?.map_err(|e| from_solve(py, &e))?;

    let d = info_dict(py, info)?;
    let tables = PyDict::new(py);
    let units = PyDict::new(py);
    let columns = PyDict::new(py);
    for t in &out.tables {
        let cols = PyDict::new(py);
        let us = PyDict::new(py);
        for (j, c) in t.columns.iter().enumerate() {
            cols.set_item(c.name, column(py, t, j)?)?;
            us.set_item(c.name, c.unit)?;
        }
        tables.set_item(&t.name, cols)?;
        units.set_item(&t.name, us)?;
        columns.set_item(
            &t.name,
            t.columns.iter().map(|c| c.name).collect::<Vec<_>>(),
        )?;
    }
    d.set_item("tables", tables)?;
    d.set_item("units", units)?;
    d.set_item("columns", columns)?;
    d.set_item("figure", to_py(py, &out.figure)?)?;
    let summary = PyDict::new(py);
    for (k, v) in &out.summary {
        summary.set_item(k, json_to_py(py, v)?)?;
    }
    d.set_item("summary", summary)?;
    d.set_item("overview", to_py(py, &out.overview)?)?;
    d.set_item("notes", out.notes.clone())?;
    d.set_item("stops", to_py(py, &out.stops)?)?;
    d.set_item("design_warnings", out.design_warnings.clone())?;
    d.set_item("points", out.points)?;
    d.set_item("warnings_by_kind", to_py(py, &out.warnings_by_kind)?)?;
    d.set_item("strict_dropped", out.strict_dropped)?;
    Ok(d)
}

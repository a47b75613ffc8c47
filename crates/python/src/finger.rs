//! `fpc.Finger`: one finger (actuator, element model, partition) and its
//! solves; the keyword arguments that describe an actuator; scene input.

use std::path::Path;

use numpy::PyReadonlyArray2;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use serde_json::{Map, Value};

use fpc::plan::RefinementRecord;
use fpc::scene::{ActuatorSection, PartitionPlan, SceneFile};
use fpc::{
    Actuator, Coefficients, InputError, Load, ModelId, Partition, Plan, PlannedFinger,
    SolveOptions, Solved,
};

use crate::convert::{arg, arg_or, array1, opt_arg, points, solution_dict, to_py};
use crate::errors::{detached, from_input, from_scene_read, from_solve, input_error};

// ------------------------------------------------------------ arguments

/// The geometry keys accepted as keyword arguments on their own.
const GEOMETRY_KEYS: [&str; 7] = ["lx", "ly", "lc", "h", "h1", "h2", "h3"];
/// The channel keys accepted as keyword arguments on their own.
const CHANNEL_KEYS: [&str; 4] = ["cx", "cy", "h3a", "h3b"];
/// The laminate keys accepted as keyword arguments on their own
/// (`[actuator.laminate]`: the shear model's correction factor, plane
/// strain across the width).
const LAMINATE_KEYS: [&str; 2] = ["shear_correction", "plane_strain"];
/// Keyword arguments that are whole sections (dicts with the scene's keys),
/// and the section each fills.
const SECTION_KEYS: [(&str, &str); 9] = [
    ("geometry", "geometry"),
    ("channel", "channel"),
    ("rib_layout", "ribs"),
    ("cl", "cl"),
    ("emc", "emc"),
    ("fluidic", "fluidic"),
    ("pemc", "pemc"),
    ("laminate", "laminate"),
    ("cl_ribs", "cl_ribs"),
];

/// The actuator keyword arguments the constructors accept.
fn actuator_keyword_list() -> Vec<&'static str> {
    let mut k: Vec<&str> = GEOMETRY_KEYS.to_vec();
    k.extend(CHANNEL_KEYS);
    k.extend(LAMINATE_KEYS);
    k.extend(SECTION_KEYS.iter().map(|s| s.0));
    k
}

/// `TypeError` for the unknown keyword `k` given to `function`, whose own
/// keyword arguments are `own`: names the nearest keyword (of either
/// kind) and lists both kinds.
fn unexpected_keyword(k: &str, function: &str, own: &[&str]) -> PyErr {
    let actuator = actuator_keyword_list();
    let nearest = own
        .iter()
        .chain(&actuator)
        .map(|n| (fpc::scene::edit_distance(n, k), n))
        .min()
        // near enough to be a slip of the keyboard
        .filter(|&(d, _)| d <= (k.chars().count() / 3).max(2))
        .map(|(_, n)| format!("did you mean '{n}'? "))
        .unwrap_or_default();
    PyTypeError::new_err(format!(
        "{function}() got an unexpected keyword argument '{k}' ({nearest}{function}'s \
         keywords: {}; actuator keywords: {})",
        own.join(", "),
        actuator.join(", ")
    ))
}

/// The function a set of actuator keyword arguments was given to: its
/// name and its own keyword arguments, for the message on an unknown one.
#[derive(Debug, Clone, Copy)]
pub struct Caller {
    pub name: &'static str,
    pub keywords: &'static [&'static str],
}

/// A Python value of plain data as JSON, non-finite numbers rejected by
/// `path` (JSON has no NaN, and an absent key would mean the default).
fn value_at(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<Value> {
    if let Ok(x) = obj.extract::<f64>() {
        if !obj.is_instance_of::<pyo3::types::PyBool>() && !obj.is_instance_of::<PyString>() {
            if !x.is_finite() {
                return Err(from_input(
                    obj.py(),
                    &InputError::NotFinite {
                        field: path.to_string().into(),
                        value: x,
                    },
                ));
            }
            if obj.is_instance_of::<pyo3::types::PyInt>() {
                return crate::convert::py_to_json(obj);
            }
            return Ok(serde_json::Number::from_f64(x).map_or(Value::Null, Value::Number));
        }
    }
    if let Ok(d) = obj.cast::<PyDict>() {
        let mut m = Map::new();
        for (k, v) in d.iter() {
            let k: String = k
                .extract()
                .map_err(|_| PyTypeError::new_err(format!("{path}: keys must be strings")))?;
            let sub = format!("{path}.{k}");
            m.insert(k, value_at(&v, &sub)?);
        }
        return Ok(Value::Object(m));
    }
    if obj.is_instance_of::<pyo3::types::PyList>() || obj.is_instance_of::<pyo3::types::PyTuple>() {
        let items = obj
            .try_iter()?
            .enumerate()
            .map(|(i, x)| value_at(&x?, &format!("{path}[{i}]")))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(Value::Array(items));
    }
    crate::convert::py_to_json(obj)
}

/// The `[actuator]` section of the keyword arguments: `eps0`, the geometry
/// and channel keys on their own, and whole sections as dicts. A key given
/// twice (`h1=` and `geometry={"h1": ...}`, `eps0=` and
/// `pemc={"eps0": ...}`) is a `TypeError` naming both.
pub fn actuator_section(
    py: Python<'_>,
    caller: Caller,
    eps0: Option<f64>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<ActuatorSection> {
    let mut sections: Map<String, Value> = Map::new();
    // where each (section, key) came from, for the message on a repeat
    let mut given: Vec<(String, String, String)> = Vec::new();
    let mut put = |section: &str, key: &str, v: Value, source: String| -> PyResult<()> {
        if let Some((_, _, first)) = given.iter().find(|g| g.0 == section && g.1 == key) {
            return Err(PyTypeError::new_err(format!(
                "actuator.{section}.{key} given twice: as {first} and as {source}"
            )));
        }
        given.push((section.to_string(), key.to_string(), source));
        let s = sections
            .entry(section.to_string())
            .or_insert_with(|| Value::Object(Map::new()));
        if let Value::Object(m) = s {
            m.insert(key.to_string(), v);
        }
        Ok(())
    };
    if let Some(kw) = kwargs {
        for (k, v) in kw.iter() {
            let k: String = k.extract()?;
            if v.is_none() {
                continue;
            }
            if GEOMETRY_KEYS.contains(&k.as_str()) {
                put(
                    "geometry",
                    &k,
                    value_at(&v, &format!("actuator.geometry.{k}"))?,
                    format!("{k}="),
                )?;
            } else if CHANNEL_KEYS.contains(&k.as_str()) {
                put(
                    "channel",
                    &k,
                    value_at(&v, &format!("actuator.channel.{k}"))?,
                    format!("{k}="),
                )?;
            } else if LAMINATE_KEYS.contains(&k.as_str()) {
                put(
                    "laminate",
                    &k,
                    value_at(&v, &format!("actuator.laminate.{k}"))?,
                    format!("{k}="),
                )?;
            } else if let Some(&(_, section)) = SECTION_KEYS.iter().find(|s| s.0 == k) {
                let path = format!("actuator.{section}");
                check_rib_count(section, &v)?;
                let value = value_at(&v, &path)?;
                // the ribs on the constraining layer may be given as their
                // list alone: `cl_ribs=[{"x0": ..., ...}, ...]`
                if let (Value::Array(_), "cl_ribs") = (&value, section) {
                    put(section, "list", value, format!("{k}="))?;
                    continue;
                }
                let Value::Object(m) = value else {
                    let list = if section == "cl_ribs" {
                        "a list of ribs (dicts with x0, x1, width, height) or "
                    } else {
                        ""
                    };
                    return Err(PyTypeError::new_err(format!(
                        "{k} must be {list}a dict of the scene's [{path}] keys"
                    )));
                };
                for (key, x) in m {
                    let source = format!("{k}[{key:?}]");
                    put(section, &key, x, source)?;
                }
            } else {
                return Err(unexpected_keyword(&k, caller.name, caller.keywords));
            }
        }
    }
    if let Some(e) = eps0 {
        let path = "actuator.pemc.eps0";
        let v = value_at(&e.into_pyobject(py)?.into_any(), path)?;
        put("pemc", "eps0", v, "eps0=".into())?;
    }
    // each section on its own, so that a serde error names its section
    let mut out = ActuatorSection::default();
    for (section, v) in sections {
        let err = |e: serde_json::Error| {
            input_error(
                py,
                &format!("actuator.{section}"),
                format!("actuator.{section}: {e}"),
            )
        };
        match section.as_str() {
            "geometry" => out.geometry = serde_json::from_value(v).map_err(err)?,
            "channel" => out.channel = serde_json::from_value(v).map_err(err)?,
            "ribs" => out.ribs = serde_json::from_value(v).map_err(err)?,
            "cl" => out.cl = serde_json::from_value(v).map_err(err)?,
            "emc" => out.emc = serde_json::from_value(v).map_err(err)?,
            "fluidic" => out.fluidic = serde_json::from_value(v).map_err(err)?,
            "pemc" => out.pemc = serde_json::from_value(v).map_err(err)?,
            "laminate" => out.laminate = serde_json::from_value(v).map_err(err)?,
            "cl_ribs" => out.cl_ribs = serde_json::from_value(v).map_err(err)?,
            _ => unreachable!("sections come from SECTION_KEYS"),
        }
    }
    Ok(out)
}

/// The library's bound on a rib list (`[actuator.ribs] list` or
/// `[actuator.cl_ribs] list`) checked on the Python list's length, before
/// any of it is converted: the same error the library gives, without a
/// copy of an unbounded list first. `section` is the scene section the
/// keyword fills; `v` the keyword's value (a dict, or `cl_ribs`'s list).
fn check_rib_count(section: &str, v: &Bound<'_, PyAny>) -> PyResult<()> {
    let (field, max) = match section {
        "ribs" => (fpc::Field::Ribs, fpc::actuator::MAX_LISTED_RIBS),
        "cl_ribs" => (fpc::Field::ClRibs, fpc::actuator::MAX_CL_RIBS),
        _ => return Ok(()),
    };
    let list = match v.cast::<PyDict>() {
        Ok(d) => match d.get_item("list")? {
            Some(l) => l,
            None => return Ok(()),
        },
        Err(_) => v.clone(),
    };
    let is_list = list.is_instance_of::<pyo3::types::PyList>()
        || list.is_instance_of::<pyo3::types::PyTuple>();
    let n = if is_list { list.len()? } else { 0 };
    if n > max {
        return Err(from_input(
            v.py(),
            &InputError::OutOfRange {
                field,
                value: n as f64,
                rule: format!("lists {n} ribs, more than {max}"),
            },
        ));
    }
    Ok(())
}

/// True when the keyword arguments hold `pemc={"eps0": ...}`.
pub fn has_pemc_eps0(kwargs: Option<&Bound<'_, PyDict>>) -> PyResult<bool> {
    Ok(
        match kwargs.map(|a| a.get_item("pemc")).transpose()?.flatten() {
            Some(p) => p
                .cast::<PyDict>()
                .is_ok_and(|p| p.contains("eps0").unwrap_or(false)),
            None => false,
        },
    )
}

/// `TypeError` for `pemc={"eps0": ...}` where the call sets the prestrain
/// itself (`why`), instead of ignoring it.
pub fn refuse_pemc_eps0(kwargs: Option<&Bound<'_, PyDict>>, why: &str) -> PyResult<()> {
    if has_pemc_eps0(kwargs)? {
        return Err(PyTypeError::new_err(format!(
            "pemc={{\"eps0\": ...}} is not used here: {why}"
        )));
    }
    Ok(())
}

/// A validated actuator from the keyword arguments (errors name the
/// scene's keys: `actuator.geometry.h1`, `actuator.pemc.eps0`, ...).
pub fn actuator_from_kwargs(
    py: Python<'_>,
    caller: Caller,
    eps0: Option<f64>,
    kwargs: Option<&Bound<'_, PyDict>>,
) -> PyResult<Actuator> {
    let file = SceneFile {
        actuator: actuator_section(py, caller, eps0, kwargs)?,
        ..SceneFile::default()
    };
    file.resolve()
        .map(|s| s.actuator)
        .map_err(|e| from_input(py, &e))
}

/// The model named `name`, or `fpc.InputError` for `model`.
pub fn model(py: Python<'_>, name: &str) -> PyResult<ModelId> {
    ModelId::parse(fpc::Field::key("model"), name).map_err(|e| from_input(py, &e))
}

/// `elements`: a whole number, `"auto"`, or None.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ElementsArg {
    /// Not given: 8 equal elements (with a tip tolerance: the fastest
    /// configuration for it).
    Default,
    /// `N` equal elements (with a tip tolerance: equal elements doubled from N).
    Count(usize),
    /// The automatic partition (with a tip tolerance: the fastest configuration).
    Auto,
}

/// The prestrain of `Finger()` when none is given.
pub const DEFAULT_EPS0: f64 = 0.25;

/// The number of elements when none is given.
pub const DEFAULT_ELEMENTS: usize = 8;

/// Reads `elements`.
pub fn elements_arg(obj: Option<&Bound<'_, PyAny>>) -> PyResult<ElementsArg> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(ElementsArg::Default);
    };
    let py = obj.py();
    if obj.is_instance_of::<PyString>() {
        let s: String = obj.extract()?;
        let s = s.as_str();
        return if s == "auto" {
            Ok(ElementsArg::Auto)
        } else {
            Err(input_error(
                py,
                "elements",
                format!("elements = `{s}`: must be a whole number of elements or \"auto\""),
            ))
        };
    }
    if obj.is_instance_of::<pyo3::types::PyBool>() {
        return Err(PyTypeError::new_err(
            "elements must be a whole number or \"auto\"",
        ));
    }
    // a non-integer is a TypeError, an int too large for a count an
    // OverflowError, both naming elements
    match arg::<i64>("elements", obj)? {
        n if n >= 1 => Ok(ElementsArg::Count(n as usize)),
        n => Err(input_error(
            py,
            "elements",
            format!("elements = {n}: must be at least 1"),
        )),
    }
}

/// `n` equal elements over `lx`, errors naming `elements`.
pub fn equal_partition(py: Python<'_>, lx: f64, n: usize) -> PyResult<Partition> {
    Partition::equal(lx, n).map_err(|e| from_input(py, &e))
}

/// `value` unless it is not finite: the error names `field`.
fn finite(field: &'static str, value: f64) -> Result<f64, InputError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(InputError::NotFinite {
            field: fpc::Field::key(field),
            value,
        })
    }
}

/// The argument `pressure_kpa` (gauge, kPa): finite and not below
/// absolute vacuum, the error naming `pressure_kpa` in kPa (every solve
/// of a finger or a grasp checks it so before the library sees the load).
pub fn check_pressure_kpa(pressure_kpa: f64) -> Result<(), InputError> {
    finite("pressure_kpa", pressure_kpa)?;
    let vacuum_kpa = fpc::finger::VACUUM_GAUGE_MPA * 1e3;
    if pressure_kpa < vacuum_kpa {
        return Err(InputError::OutOfRange {
            field: fpc::Field::key("pressure_kpa"),
            value: pressure_kpa,
            rule: format!("is below absolute vacuum ({vacuum_kpa} kPa gauge)"),
        });
    }
    Ok(())
}

/// The load of a solve from Python's arguments, checked in their terms
/// (`pressure_kpa`, `kappa`, `fx`, `fz`).
pub fn load(pressure_kpa: f64, kappa: f64, fx: f64, fz: f64) -> Result<Load, InputError> {
    check_pressure_kpa(pressure_kpa)?;
    finite("kappa", kappa)?;
    if kappa <= 0.0 {
        return Err(InputError::NotPositive {
            field: fpc::Field::key("kappa"),
            value: kappa,
        });
    }
    finite("fx", fx)?;
    finite("fz", fz)?;
    Ok(Load {
        kappa,
        ..Load::unloaded()
    }
    .with_pressure_kpa(pressure_kpa)
    .with_tip_force(fx, fz))
}

/// True when a `str` scene argument is meant as a path, not TOML text: a
/// single line that ends in `.toml` or contains a path separator (`/`, or
/// `\\` on Windows). TOML text of one line has a `=` or a `[` before any
/// of these (`a = "x/y.toml"`), so those stay text.
pub fn looks_like_path(s: &str) -> bool {
    if s.is_empty() || s.contains('\n') {
        return false;
    }
    let t = s.trim();
    let sep = t.contains('/') || (cfg!(windows) && t.contains('\\'));
    let toml_like = t.starts_with('[') || t.contains('=');
    (t.to_ascii_lowercase().ends_with(".toml") || sep) && !toml_like
}

/// A scene argument: TOML text, or a path to a scene file (any
/// `os.PathLike`, or a `str` that [`looks_like_path`]). Returns the text
/// and the path shown in messages (empty for text). A path that does not
/// exist is `FileNotFoundError` naming it (never parsed as TOML).
pub fn scene_text(obj: &Bound<'_, PyAny>) -> PyResult<(String, String)> {
    let py = obj.py();
    let os = py.import("os")?;
    let is_pathlike = obj.is_instance(&os.getattr("PathLike")?)?;
    let path: Option<String> = if is_pathlike {
        Some(
            os.call_method1("fspath", (obj,))?
                .extract()
                .map_err(|_| PyTypeError::new_err("a scene path must be a str path, not bytes"))?,
        )
    } else {
        let s: String = obj.extract().map_err(|_| {
            PyTypeError::new_err(format!(
                "a scene is TOML text or a path to a scene file (str or os.PathLike), not {}",
                obj.get_type()
                    .name()
                    .map(|n| n.to_string())
                    .unwrap_or_default()
            ))
        })?;
        (looks_like_path(&s) || (!s.contains('\n') && !s.is_empty() && Path::new(&s).is_file()))
            .then_some(s)
    };
    match path {
        Some(p) => {
            let text = std::fs::read_to_string(&p)
                .map_err(|e| io_error(&e, format!("cannot read the scene file {p}: {e}"), &p))?;
            Ok((text, p))
        }
        None => Ok((obj.extract()?, String::new())),
    }
}

/// An I/O error on the file `path` as Python's own: `FileNotFoundError`
/// and `PermissionError` (with errno and the file name), else `OSError`.
pub fn io_error(e: &std::io::Error, message: String, path: &str) -> PyErr {
    match e.kind() {
        std::io::ErrorKind::NotFound => {
            pyo3::exceptions::PyFileNotFoundError::new_err((2, message, path.to_string()))
        }
        std::io::ErrorKind::PermissionDenied => {
            pyo3::exceptions::PyPermissionError::new_err((13, message, path.to_string()))
        }
        _ => pyo3::exceptions::PyOSError::new_err(message),
    }
}

/// Parses and resolves a scene argument.
pub fn read_scene(obj: &Bound<'_, PyAny>) -> PyResult<(fpc::Scene, String)> {
    let (text, shown) = scene_text(obj)?;
    let scene = fpc::Scene::from_toml(&text).map_err(|e| from_scene_read(obj.py(), &e, &shown))?;
    Ok((scene, shown))
}

// ------------------------------------------------------------ the class

/// A finger: the actuator (the paper's by default), an element model and
/// a partition, ready to solve.
///
/// ``Finger(eps0=None, elements=None, model="ccm", ribs=True, **actuator)``
///
/// - ``eps0``: prestrain of the prestressed layer (0.25 unless given here
///   or as ``pemc={"eps0": ...}``; both at once is a ``TypeError``);
/// - ``elements``: a number of equal elements (default 8), or ``"auto"``
///   (boundaries on the material changes, split until every element is
///   within the slope limit, at most 1000 elements and 64 rounds of
///   splits, and no further once a split meets a fold or does not solve,
///   which the answer's note ``partition_fold`` or
///   ``partition_split_failed`` reports; chosen at each solve's load);
/// - ``model``: the element model (``fpc.models()`` lists them);
/// - ``ribs``: model the ribs inside the channel;
/// - ``**actuator``: the scene file's ``[actuator.*]`` keys: ``lx``, ``ly``,
///   ``lc``, ``h``, ``h1``, ``h2``, ``h3`` (mm), ``cx``, ``cy``, ``h3a``,
///   ``h3b`` (mm), ``shear_correction`` (the ``shear`` model's factor ks,
///   default 5/6), ``plane_strain`` (bool, default False: plane stress
///   across the width), or whole sections as dicts: ``geometry``,
///   ``channel``, ``rib_layout`` (``[actuator.ribs]``), ``cl``, ``emc``,
///   ``fluidic``, ``pemc`` (each with ``g13``, the layer's transverse
///   shear modulus, for the ``shear`` model), ``laminate``; ``cl_ribs``,
///   the ribs on the constraining layer as a list of dicts with ``x0``,
///   ``x1``, ``width`` and ``height`` (mm; default none).
///
/// Invalid values raise ``fpc.InputError`` (a ``ValueError``) naming the
/// field, e.g. ``actuator.geometry.h1``; an unknown keyword, or a key given
/// twice (``h1=`` and ``geometry={"h1": ...}``), a ``TypeError``.
#[pyclass(module = "fpc", frozen)]
#[derive(Debug, Clone)]
pub struct Finger {
    pub model: ModelId,
    pub actuator: Actuator,
    pub ribs: bool,
    /// The finger and its plan: a fixed partition (built once) or the
    /// automatic partition (chosen at each solve's load).
    pub planned: PlannedFinger,
    /// N for equal elements given as a count (a tip tolerance doubles it).
    pub count: Option<usize>,
    /// The load of `solve()` without arguments (a scene's; else unloaded).
    pub load: Load,
    /// A scene's tip tolerance.
    pub tip_tol_mm: Option<f64>,
    pub options: SolveOptions,
}

impl Finger {
    /// A finger from its parts; `elements` as given.
    pub fn build(
        py: Python<'_>,
        model: ModelId,
        actuator: Actuator,
        ribs: bool,
        elements: ElementsArg,
    ) -> PyResult<Finger> {
        let (plan, count) = match elements {
            ElementsArg::Auto => (Plan::Auto, None),
            ElementsArg::Default | ElementsArg::Count(_) => {
                let n = match elements {
                    ElementsArg::Count(n) => n,
                    _ => DEFAULT_ELEMENTS,
                };
                let part = equal_partition(py, actuator.geometry().lx, n)?;
                (
                    Plan::Fixed(part),
                    matches!(elements, ElementsArg::Count(_)).then_some(n),
                )
            }
        };
        let planned = PlannedFinger::builder(&actuator)
            .model(model)
            .ribs(ribs)
            .plan(plan)
            .build()
            .map_err(|e| from_input(py, &e))?;
        Ok(Finger {
            model,
            actuator,
            ribs,
            planned,
            count,
            load: Load::unloaded(),
            tip_tol_mm: None,
            options: SolveOptions::default(),
        })
    }

    /// The finger of a resolved scene (its load, tolerance and solver
    /// settings become the defaults of `solve()`).
    pub fn of_scene(scene: &fpc::Scene) -> Finger {
        let count = match scene.file().partition.elements {
            Some(fpc::scene::Elements::Count(n)) if scene.file().partition.lengths.is_none() => {
                Some(n)
            }
            _ => None,
        };
        // a tip tolerance is the default of solve(): the finger itself is
        // on the equal elements it starts from
        let (plan, count, tip_tol_mm) = match &scene.partition {
            &PartitionPlan::TipTolerance { tip_tol_mm, start } => {
                let n = start.unwrap_or(DEFAULT_ELEMENTS);
                let part = Partition::equal(scene.actuator.geometry().lx, n)
                    .expect("the scene checked its partition");
                (Plan::Fixed(part), start, Some(tip_tol_mm))
            }
            other => (other.plan(), count, None),
        };
        let planned = PlannedFinger::builder(&scene.actuator)
            .model(scene.model)
            .plan(plan)
            .build()
            .expect("the scene checked its partition");
        Finger {
            model: scene.model,
            actuator: scene.actuator.clone(),
            ribs: true,
            planned,
            count,
            load: scene.load,
            tip_tol_mm,
            options: scene.options,
        }
    }

    /// The solve: the finger's plan, or refined to a tip tolerance (from
    /// its count of equal elements, if given).
    pub fn run(
        &self,
        load: &Load,
        tip_tol_mm: Option<f64>,
        guess: Option<&Coefficients>,
        opts: &SolveOptions,
    ) -> Result<Solved, fpc::SolveError> {
        if let Some(tip_tol_mm) = tip_tol_mm {
            let start = match self.planned.fixed() {
                Some(_) => self.count,
                None => None,
            };
            return PlannedFinger::builder(&self.actuator)
                .model(self.model)
                .ribs(self.ribs)
                .plan(Plan::TipTolerance { tip_tol_mm, start })
                .build()?
                .solve(load, opts);
        }
        match guess {
            Some(g) => self.planned.solve_from(load, g, opts),
            None => self.planned.solve(load, opts),
        }
    }
}

/// A refinement as the dict of `fpc finger --json`'s `refinement`.
fn refinement_dict<'py>(py: Python<'py>, r: &RefinementRecord) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    let steps: Vec<_> = r.levels.iter().map(|l| l.steps).collect();
    let tips: Vec<[f64; 2]> = r.levels.iter().map(|l| l.tip).collect();
    d.set_item("configuration", r.plan.label())?;
    d.set_item(
        "levels",
        r.levels.iter().map(|l| l.elements).collect::<Vec<_>>(),
    )?;
    d.set_item(
        "level_iterations",
        r.levels.iter().map(|l| l.iterations).collect::<Vec<_>>(),
    )?;
    d.set_item("level_steps", to_py(py, &steps)?)?;
    d.set_item("level_tips", points(py, &tips)?)?;
    d.set_item("extrapolated", r.is_extrapolated())?;
    d.set_item("extrapolation", to_py(py, &r.extrapolation())?)?;
    d.set_item("tip", array1(py, r.tip.to_vec()))?;
    d.set_item("end_angle", r.end_angle)?;
    Ok(d)
}

#[pymethods]
impl Finger {
    #[new]
    #[pyo3(signature = (eps0=None, elements=None, model=None, ribs=None, **actuator))]
    #[pyo3(text_signature = "(eps0=None, elements=None, model='ccm', ribs=True, **actuator)")]
    fn new(
        py: Python<'_>,
        eps0: Option<&Bound<'_, PyAny>>,
        elements: Option<&Bound<'_, PyAny>>,
        model: Option<&Bound<'_, PyAny>>,
        ribs: Option<&Bound<'_, PyAny>>,
        actuator: Option<&Bound<'_, PyDict>>,
    ) -> PyResult<Finger> {
        let eps0: Option<f64> = opt_arg("eps0", eps0)?;
        let model = self::model(py, &arg_or("model", model, "ccm".to_string())?)?;
        let ribs = arg_or("ribs", ribs, true)?;
        let elements = elements_arg(elements)?;
        // 0.25 unless given, as eps0= or as pemc={"eps0": ...} (not both)
        let in_pemc = match actuator.map(|a| a.get_item("pemc")).transpose()?.flatten() {
            Some(p) => p
                .cast::<PyDict>()
                .is_ok_and(|p| p.contains("eps0").unwrap_or(false)),
            None => false,
        };
        let eps0 = eps0.or((!in_pemc).then_some(DEFAULT_EPS0));
        let caller = Caller {
            name: "Finger",
            keywords: &["eps0", "elements", "model", "ribs"],
        };
        let act = actuator_from_kwargs(py, caller, eps0, actuator)?;
        Finger::build(py, model, act, ribs, elements)
    }

    /// The finger of a scene file: TOML text, or a path to a ``.toml`` file
    /// (an ``os.PathLike``, or a one-line ``str`` that ends in ``.toml`` or
    /// contains ``/``; a missing file is ``FileNotFoundError``).
    /// The scene's model, actuator and partition make the finger; its load,
    /// ``partition.tip_tol_mm`` and ``[solve]`` settings become the defaults
    /// of :meth:`solve` (so ``Finger.from_scene(s).solve()`` solves the
    /// scene's finger). A gripper scene gives its finger, unloaded.
    #[staticmethod]
    fn from_scene(scene: &Bound<'_, PyAny>) -> PyResult<Finger> {
        let (scene, _) = read_scene(scene)?;
        Ok(Finger::of_scene(&scene))
    }

    /// Solves the finger under a channel pressure (kPa) and a tip force
    /// (N, finger frame), returning a dict:
    ///
    /// - ``tip``: tip (X, Z) in mm, finger frame (numpy array);
    /// - ``end_angle``: tip tangent angle from X (rad);
    /// - ``radius``: least-squares circle radius (mm) or None;
    /// - ``energy``: total potential energy (N mm);
    /// - ``coefficients``: element unknowns, elements x unknowns (numpy);
    /// - ``points``: mid-plane samples, root to tip, n x 2 (mm, numpy;
    ///   0 x 2 with ``shape=False``);
    /// - ``element_lengths``: undeformed element lengths (mm, numpy);
    /// - ``warnings``: list of ``{kind, message, element?, value?, limit?}``;
    /// - ``valid``: no warning puts the answer outside the model;
    /// - ``stable``, ``negative_eigenvalues``: the Hessian's inertia (None
    ///   with ``stability=False``);
    /// - ``report``: ``{reason, iterations, residual_norm, evaluations,
    ///   coupled, continuation_steps}``;
    /// - ``elements``, ``model``;
    /// - ``tip_error_estimate`` (mm) and ``refinement`` (with ``tip_tol_mm``):
    ///   the estimate is of ``refinement["tip"]``, the extrapolated tip when
    ///   ``refinement["extrapolation"]`` is set; ``tip`` and the keys above
    ///   are the finest level's.
    ///
    /// Arguments left as None take the finger's defaults: 0 kPa, no tip
    /// force, kappa 2.5 (or a scene's). ``tip_tol_mm`` refines until the
    /// estimated tip error is at most that many mm. ``guess``: coefficients
    /// to start Newton from (elements x unknowns, e.g. a previous solution's
    /// ``coefficients``; fixed partitions only). Raises ``fpc.InputError``
    /// naming the argument, ``fpc.SolveError`` when the solve fails.
    #[pyo3(signature = (pressure_kpa=None, fx=None, fz=None, kappa=None, tip_tol_mm=None, *, shape=None, stability=None, guess=None))]
    #[allow(clippy::too_many_arguments)]
    fn solve<'py>(
        &self,
        py: Python<'py>,
        pressure_kpa: Option<&Bound<'py, PyAny>>,
        fx: Option<&Bound<'py, PyAny>>,
        fz: Option<&Bound<'py, PyAny>>,
        kappa: Option<&Bound<'py, PyAny>>,
        tip_tol_mm: Option<&Bound<'py, PyAny>>,
        shape: Option<&Bound<'py, PyAny>>,
        stability: Option<&Bound<'py, PyAny>>,
        guess: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let pressure_kpa: Option<f64> = opt_arg("pressure_kpa", pressure_kpa)?;
        let fx: Option<f64> = opt_arg("fx", fx)?;
        let fz: Option<f64> = opt_arg("fz", fz)?;
        let kappa: Option<f64> = opt_arg("kappa", kappa)?;
        let tip_tol_mm: Option<f64> = opt_arg("tip_tol_mm", tip_tol_mm)?;
        let shape: Option<bool> = opt_arg("shape", shape)?;
        let stability: Option<bool> = opt_arg("stability", stability)?;
        let load = load(
            pressure_kpa.unwrap_or(self.load.pressure * 1e3),
            kappa.unwrap_or(self.load.kappa),
            fx.unwrap_or(self.load.fx),
            fz.unwrap_or(self.load.fz),
        )
        .map_err(|e| from_input(py, &e))?;
        let mut opts = self.options;
        if let Some(s) = shape {
            opts.shape = s;
        }
        if let Some(s) = stability {
            opts.stability = s;
        }
        let tip_tol = tip_tol_mm.or(self.tip_tol_mm);
        let guess = match guess.filter(|g| !g.is_none()) {
            None => None,
            Some(g) => Some(self.guess(py, g, tip_tol.is_some())?),
        };
        let solved = detached(py, || self.run(&load, tip_tol, guess.as_ref(), &opts))?
            .map_err(|e| from_solve(py, &e))?;
        let d = solution_dict(py, &solved.solution)?;
        d.set_item("model", self.model.name())?;
        d.set_item("tip_error_estimate", solved.estimated_tip_error_mm())?;
        match &solved.refinement {
            Some(r) => d.set_item("refinement", refinement_dict(py, r)?)?,
            None => d.set_item("refinement", py.None())?,
        }
        Ok(d)
    }

    /// The element model's name.
    #[getter]
    fn model(&self) -> &'static str {
        self.model.name()
    }

    /// The element model's unknowns per element, by name.
    #[getter]
    fn unknowns(&self) -> Vec<&'static str> {
        self.model.info().unknowns.to_vec()
    }

    /// The prestrain of the prestressed layer.
    #[getter]
    fn eps0(&self) -> f64 {
        self.actuator.eps0()
    }

    /// The modelled length Lx (mm).
    #[getter]
    fn length(&self) -> f64 {
        self.actuator.geometry().lx
    }

    /// True when the ribs are modelled.
    #[getter]
    fn ribs(&self) -> bool {
        self.ribs
    }

    /// The number of elements, or ``"auto"``.
    #[getter]
    fn elements<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        Ok(match self.planned.fixed() {
            Some(finger) => finger.len().into_pyobject(py)?.into_any(),
            None => PyString::new(py, "auto").into_any(),
        })
    }

    /// Undeformed element lengths (mm), root to tip; None for ``"auto"``.
    #[getter]
    fn element_lengths<'py>(&self, py: Python<'py>) -> Option<Bound<'py, numpy::PyArray1<f64>>> {
        self.planned
            .fixed()
            .map(|finger| array1(py, finger.element_lengths().to_vec()))
    }

    /// Notes on the actuator and the model's law (a prestrain outside the
    /// fitted range, ...), as ``{kind, message, ...}`` dicts; every solution
    /// carries them too.
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &fpc::finger::input_warnings(self.model, &self.actuator))
    }

    fn __repr__(&self) -> String {
        let elements = match self.planned.fixed() {
            Some(finger) => finger.len().to_string(),
            None => "'auto'".into(),
        };
        format!(
            "fpc.Finger(eps0={}, elements={elements}, model='{}', ribs={})",
            self.actuator.eps0(),
            self.model.name(),
            if self.ribs { "True" } else { "False" }
        )
    }
}

impl Finger {
    /// A starting guess from an array-like of elements x unknowns.
    fn guess(&self, py: Python<'_>, g: &Bound<'_, PyAny>, refined: bool) -> PyResult<Coefficients> {
        let Some(finger) = self.planned.fixed() else {
            return Err(input_error(
                py,
                "guess",
                "guess: needs a fixed partition (not elements=\"auto\")".into(),
            ));
        };
        if refined {
            return Err(input_error(
                py,
                "guess",
                "guess: not used with tip_tol_mm (the refinement starts each level itself)".into(),
            ));
        }
        let np = py.import("numpy")?;
        let arr = crate::convert::real_array(py, "guess", g)?;
        // a fresh C-ordered copy: aligned, whatever the input
        let arr = np
            .call_method1("atleast_2d", (arr,))?
            .call_method1("copy", ("C",))?;
        let ndim: usize = arr.getattr("ndim")?.extract()?;
        if ndim != 2 {
            return Err(input_error(
                py,
                "guess",
                format!(
                    "guess: has {ndim} dimensions, expected 2 ({} x {}: elements x unknowns)",
                    finger.len(),
                    finger.unknowns_per_element()
                ),
            ));
        }
        let arr: PyReadonlyArray2<'_, f64> = arg("guess", &arr)?;
        let view = arr.as_array();
        let (rows, cols) = (view.shape()[0], view.shape()[1]);
        let per = finger.unknowns_per_element();
        if rows != finger.len() || cols != per {
            return Err(input_error(
                py,
                "guess",
                format!(
                    "guess: has shape ({rows}, {cols}), expected ({}, {per}) (elements x unknowns)",
                    finger.len()
                ),
            ));
        }
        let values: Vec<f64> = view.iter().copied().collect();
        Coefficients::new(per, values).map_err(|e| from_input(py, &e))
    }
}

/// ``models()``: the element models, as ``{name, spec, description, unknowns}``.
#[pyfunction]
pub fn models<'py>(py: Python<'py>) -> PyResult<Vec<Bound<'py, PyDict>>> {
    ModelId::names()
        .into_iter()
        .map(|n| {
            let info = ModelId::from_name(n).expect("listed").info();
            let d = PyDict::new(py);
            d.set_item("name", info.name)?;
            d.set_item("spec", info.spec)?;
            d.set_item("description", info.description)?;
            d.set_item("unknowns", info.unknowns.to_vec())?;
            Ok(d)
        })
        .collect()
}

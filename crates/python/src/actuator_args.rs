//! The keyword arguments that describe an actuator (`lx=`, `geometry={...}`,
//! `pemc={...}`, ...), read into the scene's `[actuator]` section and
//! checked by the library, for every constructor and function that takes
//! them.

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};
use serde_json::{Map, Value};

use fpc::scene::{ActuatorSection, SceneFile};
use fpc::{Actuator, InputError};

use crate::convert::arg;
use crate::errors::{from_input, input_error};

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
            let flat: [(&[&str], &str); 3] = [
                (&GEOMETRY_KEYS, "geometry"),
                (&CHANNEL_KEYS, "channel"),
                (&LAMINATE_KEYS, "laminate"),
            ];
            if let Some(&(_, section)) = flat.iter().find(|f| f.0.contains(&k.as_str())) {
                // a keyword of one value: a wrong type is a TypeError naming
                // it, as for any scalar argument
                if k == "plane_strain" {
                    arg::<bool>(&k, &v)?;
                } else {
                    arg::<f64>(&k, &v)?;
                }
                let path = format!("actuator.{section}.{k}");
                put(section, &k, value_at(&v, &path)?, format!("{k}="))?;
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

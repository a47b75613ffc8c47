//! Rust errors as Python exceptions, and the guard that keeps a panic from
//! crossing the FFI boundary.
//!
//! | Rust | Python |
//! |---|---|
//! | [`fpc::InputError`] (also inside [`fpc::SolveError::Input`]) | `fpc.InputError`, a `ValueError`: message starts with the field, `.field` |
//! | [`fpc::scene::SceneError`] (TOML syntax, unknown key) | `fpc.SceneError`, a `ValueError`: `.line`, `.col` |
//! | [`fpc::SolveError::NotConverged`], [`fpc::SolveError::TargetNotReached`], [`fpc::SolveError::NotOnPath`] | `fpc.SolveError`, a `RuntimeError`: `.kind` and the details |
//! | a panic inside the library | `fpc.InternalError`, a `RuntimeError` |

use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

create_exception!(
    fpc,
    InputError,
    PyValueError,
    "A rejected input value. The message starts with the field's path \
     (`actuator.geometry.h1`, `load.pressure`, `elements`, ...), also in `.field`."
);
create_exception!(
    fpc,
    SceneError,
    PyValueError,
    "A scene document that is not valid TOML, or has an unknown key or a value of \
     the wrong type: `.line` and `.col` (from 1) locate the offending text."
);
create_exception!(
    fpc,
    SolveError,
    PyRuntimeError,
    "A solve that failed: Newton (with continuation) did not reach the tolerance \
     (`.kind == \"not_converged\"`: `.iterations`, `.relative_residual`, `.element`, \
     `.reason`), or a target solve stopped short (`.kind == \"target_not_reached\"`: \
     `.target`, `.value`, `.reached`)."
);
create_exception!(
    fpc,
    InternalError,
    PyRuntimeError,
    "A bug: the library panicked. The panic was caught at the boundary; please report it."
);

/// `fpc.InputError` for a field and a message that starts with it.
pub fn input_error(py: Python<'_>, field: &str, message: String) -> PyErr {
    let err = InputError::new_err(message);
    let _ = err.value(py).setattr("field", field);
    err
}

/// An [`fpc::InputError`] as `fpc.InputError`.
pub fn from_input(py: Python<'_>, e: &fpc::InputError) -> PyErr {
    input_error(py, e.field(), e.to_string())
}

/// An [`fpc::SolveError`] as `fpc.InputError` or `fpc.SolveError`.
pub fn from_solve(py: Python<'_>, e: &fpc::SolveError) -> PyErr {
    match e {
        fpc::SolveError::Input(i) => from_input(py, i),
        fpc::SolveError::NotConverged {
            reason,
            iterations,
            relative_residual,
            element,
            ..
        } => {
            let err = SolveError::new_err(e.to_string());
            let v = err.value(py);
            let _ = v.setattr("kind", "not_converged");
            let _ = v.setattr("reason", reason.to_string());
            let _ = v.setattr("iterations", *iterations);
            let _ = v.setattr("relative_residual", *relative_residual);
            let _ = v.setattr("element", *element);
            err
        }
        fpc::SolveError::TargetNotReached {
            target,
            value,
            reached,
            ..
        } => {
            let err = SolveError::new_err(e.to_string());
            let v = err.value(py);
            let _ = v.setattr("kind", "target_not_reached");
            let _ = v.setattr("target", target.as_str());
            let _ = v.setattr("value", *value);
            let _ = v.setattr("reached", *reached);
            err
        }
        fpc::SolveError::NotOnPath { target, value, .. } => {
            let err = SolveError::new_err(e.to_string());
            let v = err.value(py);
            let _ = v.setattr("kind", "not_on_path");
            let _ = v.setattr("target", target.as_str());
            let _ = v.setattr("value", *value);
            err
        }
    }
}

/// `e` with its field `from` renamed `to` (same value, same unit), other
/// errors unchanged.
pub fn renamed(e: fpc::SolveError, from: &str, to: &str) -> fpc::SolveError {
    use fpc::InputError as E;
    let fpc::SolveError::Input(i) = e else {
        return e;
    };
    if i.field() != from {
        return fpc::SolveError::Input(i);
    }
    let field = to.to_string();
    fpc::SolveError::Input(match i {
        E::NotFinite { value, .. } => E::NotFinite { field, value },
        E::NotPositive { value, .. } => E::NotPositive { field, value },
        E::OutOfRange { value, rule, .. } => E::OutOfRange { field, value, rule },
        E::Inconsistent { rule, .. } => E::Inconsistent { field, rule },
        E::Unrecognised { value, rule, .. } => E::Unrecognised { field, value, rule },
    })
}

/// A scene read error as `fpc.SceneError` or `fpc.InputError`; `shown`
/// (a path, or empty) prefixes a syntax error's position.
pub fn from_scene_read(py: Python<'_>, e: &fpc::SceneReadError, shown: &str) -> PyErr {
    match e {
        fpc::SceneReadError::Input(i) => from_input(py, i),
        fpc::SceneReadError::Syntax(s) => from_syntax(py, s, shown),
    }
}

/// A TOML syntax error or unknown key as `fpc.SceneError`, with `line` and
/// `col`; `shown` (a path, or empty) prefixes the position.
pub fn from_syntax(py: Python<'_>, s: &fpc::SceneError, shown: &str) -> PyErr {
    let message = if shown.is_empty() {
        s.to_string()
    } else {
        format!("{shown}:{s}")
    };
    let err = SceneError::new_err(message);
    let v = err.value(py);
    let _ = v.setattr("line", s.line);
    let _ = v.setattr("col", s.col);
    err
}

/// The text of a caught panic's payload.
pub fn panic_message(payload: &(dyn std::any::Any + Send)) -> String {
    if let Some(s) = payload.downcast_ref::<&str>() {
        (*s).to_string()
    } else if let Some(s) = payload.downcast_ref::<String>() {
        s.clone()
    } else {
        "a panic without a message".to_string()
    }
}

/// Runs `f`, turning a panic into `Err(message)`.
pub fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|p| panic_message(&*p))
}

/// Runs `f` with the GIL released, a panic turned into `fpc.InternalError`.
pub fn detached<T: Send>(py: Python<'_>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    py.detach(|| guarded(f))
        .map_err(|m| InternalError::new_err(format!("internal error (a bug): {m}")))
}

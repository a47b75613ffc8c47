//! Rust errors as Python exceptions, and the guard that keeps a panic from
//! crossing the FFI boundary.
//!
//! | Rust | Python |
//! |---|---|
//! | [`fpc::InputError`] (also inside [`fpc::SolveError::Input`]) | `fpc.InputError`, a `ValueError`: message starts with the field, `.field` |
//! | [`fpc::scene::SceneError`] (TOML syntax, unknown key) | `fpc.SceneError`, a `ValueError`: `.line`, `.col` |
//! | [`fpc::SolveError::NotConverged`], [`fpc::SolveError::TargetNotReached`], [`fpc::SolveError::NotOnPath`] | `fpc.SolveError`, a `RuntimeError`: `.kind` and the details |
//! | [`fpc::measure::MeasureError`] (a manifest or its CSV files) | `fpc.MeasureError`, a `ValueError`: `.file`, `.line`, `.col`, `.field` |
//! | a panic inside the library | `fpc.InternalError`, a `RuntimeError` |

use std::panic::{catch_unwind, AssertUnwindSafe};

use pyo3::create_exception;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use fpc::field::RefinementKey;
use fpc::Field;

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
    MeasureError,
    PyValueError,
    "Bad measurement input (a manifest or one of its CSV files): `.file`, `.line` \
     and `.col` (from 1; None for what concerns the whole file) and `.field` (the \
     column or manifest key)."
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
    let e = input_in_python_terms(e.clone());
    input_error(py, &e.field().to_string(), e.to_string())
}

/// An [`fpc::SolveError`] as `fpc.InputError` or `fpc.SolveError`.
pub fn from_solve(py: Python<'_>, e: &fpc::SolveError) -> PyErr {
    let e = &in_python_terms(e.clone());
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
            let _ = v.setattr("target", target.to_string());
            let _ = v.setattr("value", *value);
            let _ = v.setattr("reached", *reached);
            err
        }
        fpc::SolveError::NotOnPath { target, value, .. } => {
            let err = SolveError::new_err(e.to_string());
            let v = err.value(py);
            let _ = v.setattr("kind", "not_on_path");
            let _ = v.setattr("target", target.to_string());
            let _ = v.setattr("value", *value);
            err
        }
        fpc::SolveError::Cancelled => {
            let err = SolveError::new_err(e.to_string());
            let _ = err.value(py).setattr("kind", "cancelled");
            err
        }
    }
}

/// The Python argument that sets a field of the library under another
/// name (the same value, the same unit; the angles are checked in degrees
/// before the library sees them).
fn argument(field: &Field) -> Option<&'static str> {
    Some(match field {
        Field::PartitionN | Field::Refinement(RefinementKey::Start) => "elements",
        Field::LoadKappa => "kappa",
        Field::GripperOverlap => "gripper.overlap_mm",
        Field::GripperPalm => "gripper.palm_mm",
        Field::GraspSize => "d_mm",
        Field::GraspFriction => "friction_n",
        Field::GraspPressureKpa => "pressure_kpa",
        Field::SphereRadius => "r_mm",
        Field::SphereLift => "lift_n",
        Field::SphereSamples => "samples",
        _ => return None,
    })
}

/// `e` naming the Python argument that sets its field, where one does.
pub fn input_in_python_terms(e: fpc::InputError) -> fpc::InputError {
    match argument(e.field()) {
        Some(a) => e.renamed(Field::key(a), |v| v),
        None => e,
    }
}

/// `e` in the terms of the Python arguments: its input error, or the
/// target it did not reach.
pub fn in_python_terms(e: fpc::SolveError) -> fpc::SolveError {
    e.renamed(|f| argument(f).map(Field::key), |_, v| v)
}

/// A scene read error as `fpc.SceneError` or `fpc.InputError`; `shown`
/// (a path, or empty) prefixes a syntax error's position.
pub fn from_scene_read(py: Python<'_>, e: &fpc::scene::SceneReadError, shown: &str) -> PyErr {
    match e {
        fpc::scene::SceneReadError::Input(i) => from_input(py, i),
        fpc::scene::SceneReadError::Syntax(s) => from_syntax(py, s, shown),
    }
}

/// A TOML syntax error or unknown key as `fpc.SceneError`, with `line` and
/// `col`; `shown` (a path, or empty) prefixes the position.
pub fn from_syntax(py: Python<'_>, s: &fpc::scene::SceneError, shown: &str) -> PyErr {
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

/// A [`fpc::measure::MeasureError`] as `fpc.MeasureError`.
pub fn from_measure(py: Python<'_>, e: &fpc::measure::MeasureError) -> PyErr {
    let err = MeasureError::new_err(e.to_string());
    let v = err.value(py);
    let _ = v.setattr("file", &e.file);
    let _ = v.setattr("line", e.row());
    let _ = v.setattr("col", e.column());
    let _ = v.setattr("field", &e.field);
    err
}

/// Runs `f`, turning a panic into `Err(message)`.
pub fn guarded<T>(f: impl FnOnce() -> T) -> Result<T, String> {
    catch_unwind(AssertUnwindSafe(f)).map_err(|p| fpc::cancel::panic_text(&*p))
}

/// Runs `f` with the GIL released, a panic turned into `fpc.InternalError`.
pub fn detached<T: Send>(py: Python<'_>, f: impl FnOnce() -> T + Send) -> PyResult<T> {
    py.detach(|| guarded(f))
        .map_err(|m| InternalError::new_err(format!("internal error (a bug): {m}")))
}

/// How often a long call re-takes the GIL to look for Ctrl-C.
const SIGNAL_POLL: std::time::Duration = std::time::Duration::from_millis(50);

/// Runs `f` on a worker thread with the GIL released, re-taking the GIL
/// every 50 ms to run Python's signal handlers: Ctrl-C (or any handler
/// that raises) returns at once with its exception (`KeyboardInterrupt`)
/// and sets the worker's [`fpc::cancel`] flag, so every solve `f` starts
/// from then on fails at once and `f` winds down within milliseconds on
/// its thread; its result is dropped. A panic is `fpc.InternalError`.
pub fn interruptible<T: Send + 'static>(
    py: Python<'_>,
    f: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    let (tx, rx) = std::sync::mpsc::channel();
    let flag = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
    let worker_flag = flag.clone();
    std::thread::Builder::new()
        .name("fpc-work".into())
        .stack_size(8 << 20)
        .spawn(move || {
            let _ = tx.send(guarded(|| fpc::cancel::with_flag(worker_flag, f)));
        })
        .map_err(|e| InternalError::new_err(format!("cannot start a worker thread: {e}")))?;
    // an interrupted f winds down on its own thread
    wait_polling(py, rx, move |_, _| {
        flag.store(true, std::sync::atomic::Ordering::Relaxed)
    })
}

/// Runs `f(cancel)` on a scoped worker thread with the GIL released,
/// re-taking the GIL every 50 ms to run Python's signal handlers; when one
/// raises (Ctrl-C), sets `cancel` and waits for `f` to notice it and
/// return. `f` should look at `cancel` between small pieces of work.
/// Returns `(result, None)` when `f` ran to the end, `(partial result,
/// Some(exception))` when a signal handler raised and `f` then stopped. A
/// panic is `fpc.InternalError`.
pub fn cancellable_partial<T: Send>(
    py: Python<'_>,
    f: impl FnOnce(&std::sync::atomic::AtomicBool) -> T + Send,
) -> PyResult<(T, Option<PyErr>)> {
    use std::sync::atomic::{AtomicBool, Ordering};
    let cancel = AtomicBool::new(false);
    let (tx, rx) = std::sync::mpsc::channel();
    std::thread::scope(|s| {
        let cancel = &cancel;
        s.spawn(move || {
            let _ = tx.send(guarded(|| f(cancel)));
        });
        let mut stopped = None;
        let got = wait_polling(py, rx, |py, rx| {
            cancel.store(true, Ordering::Relaxed);
            // the scope joins the worker, which stops at its next check
            stopped = py.detach(move || rx.recv().ok());
        });
        match (got, stopped) {
            (Ok(t), _) => Ok((t, None)),
            (Err(e), Some(Ok(t))) => Ok((t, Some(e))),
            (Err(e), Some(Err(m))) => {
                let bug = InternalError::new_err(format!("internal error (a bug): {m}"));
                bug.set_cause(py, Some(e));
                Err(bug)
            }
            (Err(e), None) => Err(e),
        }
    })
}

/// `d`, the result of a long call, or the exception of the Ctrl-C that
/// stopped it (`stopped`), which then carries `d` as its `partial`
/// attribute: what was done is not lost.
pub fn kept_on_interrupt<'py, T: IntoPyObject<'py>>(
    py: Python<'py>,
    d: T,
    stopped: Option<PyErr>,
) -> PyResult<T> {
    match stopped {
        None => Ok(d),
        Some(e) => {
            e.value(py).setattr("partial", d)?;
            Err(e)
        }
    }
}

/// Waits for a worker's result on `rx`, re-taking the GIL every
/// [`SIGNAL_POLL`] to run Python's signal handlers. When one raises
/// (Ctrl-C), `interrupted` runs with the receiver (to stop or abandon the
/// worker) and the exception is returned. A panic, or a worker gone
/// without a result, is `fpc.InternalError`.
fn wait_polling<T: Send>(
    py: Python<'_>,
    mut rx: std::sync::mpsc::Receiver<Result<T, String>>,
    interrupted: impl FnOnce(Python<'_>, std::sync::mpsc::Receiver<Result<T, String>>),
) -> PyResult<T> {
    use std::sync::mpsc::RecvTimeoutError;
    loop {
        let (back, got) = py.detach(move || {
            let got = rx.recv_timeout(SIGNAL_POLL);
            (rx, got)
        });
        rx = back;
        match got {
            Ok(r) => {
                return r
                    .map_err(|m| InternalError::new_err(format!("internal error (a bug): {m}")))
            }
            Err(RecvTimeoutError::Timeout) => {
                if let Err(e) = py.check_signals() {
                    interrupted(py, rx);
                    return Err(e);
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(InternalError::new_err(
                    "internal error (a bug): the worker thread ended without a result",
                ))
            }
        }
    }
}

/// `fpc.InputError` unless `value <= max`: a count the caller controls,
/// checked before any work or allocation.
pub fn at_most(py: Python<'_>, field: &str, value: usize, max: usize) -> PyResult<()> {
    if value > max {
        return Err(input_error(
            py,
            field,
            format!("{field} = {value}: must be at most {max} (a bound on the work of one call)"),
        ));
    }
    Ok(())
}

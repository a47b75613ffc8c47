//! `fpc.batch_solve`: many finger solves in parallel (rayon), the GIL
//! released, results as arrays.
//!
//! The points are ordered by prestrain and split into chunks, each
//! solved on one thread: prestrain after prestrain, each with its finger,
//! built for its points and dropped after them (so memory goes with the
//! threads, not with the number of distinct `eps0`), and one reused
//! [`fpc::finger::Solver`] workspace. By default every
//! point is solved cold, exactly as `Finger.solve` solves it (the batch
//! equals a loop of single solves bit for bit, whatever the number of
//! threads); `warm_start` sorts each group by load and starts each solve
//! from the previous point of its chunk (falling back to a cold solve when
//! that fails), which agrees to the solver's tolerance.

use std::time::Instant;

use numpy::{PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList, PyTuple};
use rayon::prelude::*;

use fpc::finger::Solver;
use fpc::{
    Actuator, Coefficients, InputError, Load, ModelId, Plan, PlannedFinger, SolveError,
    SolveOptions, Solved,
};

use std::sync::atomic::{AtomicBool, Ordering};

use crate::convert::{arg_or, array1, array2, opt_arg, real_array};
use crate::errors::{at_most, cancellable_partial, from_input, guarded, input_error};

/// The most points of one `batch_solve` (the broadcast size), checked
/// before the inputs are flattened.
pub const MAX_BATCH_POINTS: usize = 1_000_000;
/// The most `threads` of one `batch_solve`.
pub const MAX_THREADS: usize = 1024;
use crate::actuator_args::actuator_from_kwargs;
use crate::finger::{elements_arg, load, model, ElementsArg};

/// `status` codes of a batch point, by index: 0 ok, 1 input_error,
/// 2 not_converged, 3 internal_error, 4 stopped (not solved: Ctrl-C came
/// first; seen only in a `KeyboardInterrupt`'s `partial`).
pub const STATUS_NAMES: [&str; 5] = [
    "ok",
    "input_error",
    "not_converged",
    "internal_error",
    "stopped",
];

/// The error of a point that a Ctrl-C left unsolved (a batch's or a
/// sweep's).
pub const STOPPED: &str = "stopped by Ctrl-C before this point";

/// One point of a batch.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Point {
    pub eps0: f64,
    pub pressure_kpa: f64,
    pub fx: f64,
    pub fz: f64,
    pub kappa: f64,
}

/// How every point is solved.
#[derive(Debug, Clone)]
pub struct Config {
    pub actuator: Actuator,
    pub model: ModelId,
    pub ribs: bool,
    /// How every point's finger is solved: equal elements, the automatic
    /// partition, or refined to a tip tolerance.
    pub plan: Plan,
    pub warm_start: bool,
    pub options: SolveOptions,
}

/// The outcome of one point.
#[derive(Debug, Clone, PartialEq)]
pub struct Outcome {
    pub status: u8,
    pub tip: [f64; 2],
    pub end_angle: f64,
    /// A tip tolerance's estimated error of `tip` (mm; NaN without one).
    pub tip_error: f64,
    pub residual: f64,
    pub iterations: usize,
    pub valid: bool,
    pub elements: usize,
    pub error: String,
}

impl Outcome {
    fn failed(status: u8, error: String) -> Outcome {
        Outcome {
            status,
            tip: [f64::NAN; 2],
            end_angle: f64::NAN,
            tip_error: f64::NAN,
            residual: f64::NAN,
            iterations: 0,
            valid: false,
            elements: 0,
            error,
        }
    }

    fn of(r: Result<fpc::Solution, SolveError>) -> Outcome {
        // the message names the argument the caller wrote (`kappa`, not
        // the library's `load.kappa`), as `Finger.solve`'s does
        match r.map_err(crate::errors::in_python_terms) {
            Ok(s) => Outcome {
                status: 0,
                tip: s.tip,
                end_angle: s.end_angle,
                tip_error: f64::NAN,
                residual: s.report.residual_norm,
                iterations: s.report.iterations,
                valid: s.is_within_model(),
                elements: s.element_lengths.len(),
                error: String::new(),
            },
            Err(SolveError::Input(e)) => Outcome::failed(1, e.to_string()),
            Err(e) => {
                let mut o = Outcome::failed(2, e.to_string());
                if let SolveError::NotConverged {
                    iterations,
                    relative_residual,
                    ..
                } = e
                {
                    o.iterations = iterations;
                    o.residual = relative_residual;
                }
                o
            }
        }
    }

    /// The outcome of a planned solve: with a refinement, its best tip
    /// and end angle (extrapolated where the plan extrapolates), their
    /// estimated error and the iterations of every level.
    fn of_planned(r: Result<Solved, SolveError>) -> Outcome {
        let Ok(s) = r else {
            return Outcome::of(r.map(|s| s.solution));
        };
        let (tip, end_angle, iterations) = (s.tip(), s.end_angle(), s.iterations());
        let tip_error = s.estimated_tip_error_mm().unwrap_or(f64::NAN);
        let mut o = Outcome::of(Ok(s.solution));
        (o.tip, o.end_angle, o.tip_error, o.iterations) = (tip, end_angle, tip_error, iterations);
        o
    }

    fn panicked(message: String) -> Outcome {
        Outcome::failed(3, format!("internal error (a bug): {message}"))
    }
}

/// Solves every point; `threads` (None: rayon's global pool, all cores).
/// Points not yet started when `cancel` is set fail with status 3 and
/// the error "cancelled".
pub fn run(
    points: &[Point],
    cfg: &Config,
    threads: Option<usize>,
    cancel: &AtomicBool,
) -> Result<Vec<Outcome>, String> {
    match threads {
        None => Ok(run_in_pool(points, cfg, cancel)),
        Some(n) => rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .map_err(|e| e.to_string())
            .map(|pool| pool.install(|| run_in_pool(points, cfg, cancel))),
    }
}

/// The points' indices by prestrain (bitwise, `total_cmp`), increasing;
/// within a prestrain by index, or with `warm_start` by load (pressure,
/// fx, fz, kappa, then index) so that a chunk starts each solve from a
/// neighbouring point.
fn by_prestrain(points: &[Point], warm_start: bool) -> Vec<usize> {
    let mut order: Vec<usize> = (0..points.len()).collect();
    order.par_sort_by(|&a, &b| {
        let (p, q) = (&points[a], &points[b]);
        let by_load = || {
            p.pressure_kpa
                .total_cmp(&q.pressure_kpa)
                .then(p.fx.total_cmp(&q.fx))
                .then(p.fz.total_cmp(&q.fz))
                .then(p.kappa.total_cmp(&q.kappa))
        };
        let order = p.eps0.total_cmp(&q.eps0);
        let order = if warm_start {
            order.then_with(by_load)
        } else {
            order
        };
        order.then(a.cmp(&b))
    });
    order
}

/// The finger of the prestrain `eps0` and its plan; a build error of the
/// automatic partition or a tip tolerance is each point's (after its
/// load's). `Err`: why the prestrain has no finger (the actuator refuses
/// it, a fixed partition does not build, or a panic), every point's
/// error.
fn build(cfg: &Config, eps0: f64) -> Result<Result<PlannedFinger, InputError>, String> {
    let built = guarded(|| -> Result<Result<PlannedFinger, InputError>, String> {
        let act = cfg.actuator.with_eps0(eps0).map_err(|e| e.to_string())?;
        let finger = PlannedFinger::builder(&act)
            .model(cfg.model)
            .ribs(cfg.ribs)
            .plan(cfg.plan.clone())
            .build()
            .map_err(crate::errors::input_in_python_terms);
        // a fixed partition that does not build fails the prestrain
        match (&cfg.plan, finger) {
            (Plan::Equal(_), Err(e)) => Err(e.to_string()),
            (_, f) => Ok(f),
        }
    });
    built.unwrap_or_else(|p| Err(format!("internal error (a bug): {p}")))
}

fn run_in_pool(points: &[Point], cfg: &Config, cancel: &AtomicBool) -> Vec<Outcome> {
    let order = by_prestrain(points, cfg.warm_start);
    // chunks of about 1/8 of a thread's share: balanced, and long enough
    // for a warm start to pay
    let threads = rayon::current_num_threads().max(1);
    let chunk = points.len().div_ceil(8 * threads).max(1);
    // each chunk solves its prestrains one after the other, building each
    // one's finger and dropping it after its points: the fingers alive at
    // once are one per thread, however many distinct prestrains (a finger
    // is tens of kilobytes; a million of them would not fit in memory)
    let solved: Vec<Vec<(usize, Outcome)>> = order
        .par_chunks(chunk)
        .map(|c| {
            let mut out = Vec::with_capacity(c.len());
            let same = |&a: &usize, &b: &usize| points[a].eps0.total_cmp(&points[b].eps0).is_eq();
            for members in c.chunk_by(same) {
                let eps0 = points[members[0]].eps0;
                solve_prestrain(points, cfg, eps0, members, cancel, &mut out);
            }
            out
        })
        .collect();
    let mut out = vec![Outcome::failed(3, String::new()); points.len()];
    for (i, o) in solved.into_iter().flatten() {
        out[i] = o;
    }
    out
}

/// The points `members` of one prestrain (of one chunk), in order, on
/// one thread, their outcomes pushed on `out`: the prestrain's finger is
/// built for them and dropped after them.
fn solve_prestrain(
    points: &[Point],
    cfg: &Config,
    eps0: f64,
    members: &[usize],
    cancel: &AtomicBool,
    out: &mut Vec<(usize, Outcome)>,
) {
    let planned = match build(cfg, eps0) {
        Ok(planned) => planned,
        Err(e) => {
            let status = if e.starts_with("internal error") {
                3
            } else {
                1
            };
            out.extend(
                members
                    .iter()
                    .map(|&i| (i, Outcome::failed(status, e.clone()))),
            );
            return;
        }
    };
    // each point's load, or its outcome when it has none: once
    // cancelled, the remaining points are not solved
    let mut loads = members.iter().map(|&i| {
        let p = &points[i];
        let l = if cancel.load(Ordering::Relaxed) {
            Err(Outcome::failed(4, STOPPED.into()))
        } else {
            load(p.pressure_kpa, p.kappa, p.fx, p.fz).map_err(|e| Outcome::failed(1, e.to_string()))
        };
        (i, l)
    });
    match planned.as_ref().ok().and_then(PlannedFinger::fixed) {
        Some(finger) => {
            let mut solver = Solver::new(finger);
            let mut prev: Option<Coefficients> = None;
            for (i, l) in loads.by_ref() {
                let l = match l {
                    Ok(l) => l,
                    Err(failed) => {
                        out.push((i, failed));
                        continue;
                    }
                };
                let r = guarded(|| match (&prev, cfg.warm_start) {
                    (Some(k), true) => solver
                        .solve(&l, Some(k), &cfg.options)
                        .or_else(|_| solver.solve(&l, None, &cfg.options)),
                    _ => solver.solve(&l, None, &cfg.options),
                });
                match r {
                    Ok(r) => {
                        if let Ok(s) = &r {
                            if cfg.warm_start {
                                prev = Some(s.coefficients.clone());
                            }
                        }
                        out.push((i, Outcome::of(r)));
                    }
                    Err(p) => {
                        // the workspace may be left mid-solve: start afresh
                        solver = Solver::new(finger);
                        prev = None;
                        out.push((i, Outcome::panicked(p)));
                    }
                }
            }
        }
        None => {
            for (i, l) in loads {
                let l = match l {
                    Ok(l) => l,
                    Err(failed) => {
                        out.push((i, failed));
                        continue;
                    }
                };
                let r = guarded(|| match &planned {
                    Ok(f) => f.solve(&l, &cfg.options),
                    Err(e) => Err(e.clone().into()),
                });
                out.push((
                    i,
                    match r {
                        Ok(r) => Outcome::of_planned(r),
                        Err(p) => Outcome::panicked(p),
                    },
                ));
            }
        }
    }
}

// ------------------------------------------------------------ Python

/// The inputs `(name, value, default)` broadcast against each other
/// (numpy rules), flattened, at most `max_points` of them (checked before
/// any copy): the shape and the columns. Each value is converted by
/// [`real_array`] (a wrong type, such as a string or a complex value, is a
/// `TypeError` naming the argument); shapes that do not broadcast are
/// `fpc.InputError` naming the first argument.
pub fn broadcast<'py>(
    py: Python<'py>,
    inputs: &[(&str, Option<&Bound<'py, PyAny>>, f64)],
    max_points: usize,
) -> PyResult<(Vec<usize>, Vec<Vec<f64>>)> {
    let np = py.import("numpy")?;
    let mut arrays = Vec::new();
    for (name, v, default) in inputs {
        let v = match v {
            Some(v) if !v.is_none() => (*v).clone(),
            _ => default.into_pyobject(py)?.into_any(),
        };
        arrays.push(real_array(py, name, &v)?);
    }
    let b = np
        .call_method1("broadcast_arrays", PyTuple::new(py, &arrays)?)
        .map_err(|e| {
            let names: Vec<&str> = inputs.iter().map(|i| i.0).collect();
            input_error(
                py,
                names[0],
                format!("{}: shapes do not broadcast ({e})", names.join(", ")),
            )
        })?;
    // the size before any copy: the broadcast arrays are views
    let first = b.get_item(0)?;
    let size: usize = first.getattr("size")?.extract()?;
    at_most(py, "points", size, max_points)?;
    let mut shape: Vec<usize> = Vec::new();
    let mut cols = Vec::new();
    for a in b.try_iter()? {
        let a = a?;
        shape = a.getattr("shape")?.extract()?;
        // a fresh C-ordered copy: aligned, whatever the input (a view, a
        // buffer unpickled at an odd offset, a broadcast with zero strides)
        let flat = a.call_method1("flatten", ("C",))?;
        let flat: PyReadonlyArray1<'_, f64> = flat.extract()?;
        cols.push(flat.as_slice()?.to_vec());
    }
    Ok((shape, cols))
}

/// The configuration from Python's arguments.
#[allow(clippy::too_many_arguments)]
fn config(
    py: Python<'_>,
    elements: Option<&Bound<'_, PyAny>>,
    model_name: &str,
    ribs: bool,
    tip_tol_mm: Option<f64>,
    warm_start: bool,
    actuator: Option<&Bound<'_, PyDict>>,
) -> PyResult<Config> {
    let model = model(py, model_name)?;
    let elements = elements_arg(elements)?;
    if let Some(t) = tip_tol_mm {
        if !(t.is_finite() && t > 0.0) {
            return Err(from_input(
                py,
                &fpc::InputError::NotPositive {
                    field: fpc::Field::key("tip_tol_mm"),
                    value: t,
                },
            ));
        }
    }
    crate::actuator_args::refuse_pemc_eps0(
        actuator,
        "every point's prestrain is batch_solve's eps0 argument",
    )?;
    let caller = crate::actuator_args::Caller {
        name: "batch_solve",
        keywords: &[
            "eps0",
            "pressure_kpa",
            "fx",
            "fz",
            "kappa",
            "elements",
            "model",
            "ribs",
            "tip_tol_mm",
            "warm_start",
            "threads",
        ],
    };
    let actuator = actuator_from_kwargs(py, caller, None, actuator)?;
    let (count, start) = match elements {
        ElementsArg::Default => (Some(crate::finger::DEFAULT_ELEMENTS), None),
        ElementsArg::Count(n) => {
            crate::finger::equal_partition(py, actuator.geometry().lx, n)?;
            (Some(n), Some(n))
        }
        ElementsArg::Auto => (None, None),
    };
    let plan = match (tip_tol_mm, count) {
        (Some(tip_tol_mm), _) => Plan::TipTolerance { tip_tol_mm, start },
        (None, Some(n)) => Plan::Equal(n),
        (None, None) => Plan::Auto,
    };
    let options = SolveOptions::default().tip_only();
    Ok(Config {
        actuator,
        model,
        ribs,
        plan,
        warm_start,
        options,
    })
}

/// Solves a batch of fingers in parallel and returns a dict of arrays.
///
/// ``eps0``, ``pressure_kpa``, ``fx``, ``fz`` and ``kappa`` are scalars or
/// array-likes, broadcast against each other like numpy arrays; the M
/// points are the broadcast result flattened in C order (``shape`` keeps
/// its shape). Every point is a finger of the same actuator
/// (``**actuator``, as for ``fpc.Finger``) at its own prestrain, under its
/// own load, with ``elements`` (default 8, or ``"auto"``), ``model`` and
/// ``ribs``; ``tip_tol_mm`` refines each point to a tip tolerance.
///
/// The solves run on ``threads`` threads (default: all cores, rayon) with
/// the GIL released. ``warm_start=False`` (default) solves every point as
/// ``Finger.solve(..., shape=False, stability=False)`` does: the results
/// equal a loop of single solves exactly (with a fixed partition whatever
/// the output options; a refinement re-solves its finest level for them). ``warm_start=True`` starts each solve from a neighbouring
/// point of the same prestrain (faster; agrees to the solver's tolerance).
/// Only the tip is computed (no shape sampling, no eigenvalues); the
/// validity checks are those of ``Finger.solve``.
///
/// Returns: ``shape`` (tuple), the inputs flattened (``eps0``,
/// ``pressure_kpa``, ``fx``, ``fz``, ``kappa``), ``tip`` (M x 2, mm),
/// ``end_angle`` (rad), ``tip_error`` (mm: with ``tip_tol_mm`` the
/// estimated error of ``tip``, which is then the refinement's best,
/// extrapolated tip, as ``Finger.solve``'s ``refinement["tip"]``; NaN
/// without), ``status`` (int8: 0 ok, 1 input_error,
/// 2 not_converged, 3 internal_error; names in ``fpc.BATCH_STATUS``),
/// ``residual`` (relative, also for not_converged), ``iterations`` (with
/// ``tip_tol_mm``, over every level),
/// ``valid`` (solved and within the model), ``elements`` and ``error``
/// (list of messages, "" where solved). Failed points have NaN tips.
///
/// Bounds, checked before any work: at most 1000000 points (the broadcast
/// size; ``fpc.InputError`` for ``points`` beyond) and 1024 ``threads``;
/// memory grows with the points and the threads, not with the number of
/// distinct prestrains. Strings and complex inputs, and
/// ``pemc={"eps0": ...}`` (the prestrain is ``eps0``), are a
/// ``TypeError``. Ctrl-C stops the batch within one
/// solve per thread and raises ``KeyboardInterrupt`` whose ``partial``
/// attribute is the same dict for the points solved so far (the others
/// have status 4, ``stopped``).
#[pyfunction]
#[pyo3(signature = (eps0=None, pressure_kpa=None, fx=None, fz=None, kappa=None, *, elements=None, model=None, ribs=None, tip_tol_mm=None, warm_start=None, threads=None, **actuator))]
#[pyo3(
    text_signature = "(eps0=None, pressure_kpa=None, fx=None, fz=None, kappa=None, *, elements=None, model='ccm', ribs=True, tip_tol_mm=None, warm_start=False, threads=None, **actuator)"
)]
#[allow(clippy::too_many_arguments)]
pub fn batch_solve<'py>(
    py: Python<'py>,
    eps0: Option<&Bound<'py, PyAny>>,
    pressure_kpa: Option<&Bound<'py, PyAny>>,
    fx: Option<&Bound<'py, PyAny>>,
    fz: Option<&Bound<'py, PyAny>>,
    kappa: Option<&Bound<'py, PyAny>>,
    elements: Option<&Bound<'py, PyAny>>,
    model: Option<&Bound<'py, PyAny>>,
    ribs: Option<&Bound<'py, PyAny>>,
    tip_tol_mm: Option<&Bound<'py, PyAny>>,
    warm_start: Option<&Bound<'py, PyAny>>,
    threads: Option<&Bound<'py, PyAny>>,
    actuator: Option<&Bound<'py, PyDict>>,
) -> PyResult<Bound<'py, PyDict>> {
    let model: String = arg_or("model", model, "ccm".to_string())?;
    let ribs: bool = arg_or("ribs", ribs, true)?;
    let tip_tol_mm: Option<f64> = opt_arg("tip_tol_mm", tip_tol_mm)?;
    let warm_start: bool = arg_or("warm_start", warm_start, false)?;
    let threads: Option<usize> = opt_arg("threads", threads)?;
    if threads == Some(0) {
        return Err(input_error(
            py,
            "threads",
            "threads = 0: must be at least 1".into(),
        ));
    }
    if let Some(t) = threads {
        at_most(py, "threads", t, MAX_THREADS)?;
    }
    let cfg = config(py, elements, &model, ribs, tip_tol_mm, warm_start, actuator)?;
    let (dims, cols) = broadcast(
        py,
        &[
            ("eps0", eps0, 0.25),
            ("pressure_kpa", pressure_kpa, 0.0),
            ("fx", fx, 0.0),
            ("fz", fz, 0.0),
            ("kappa", kappa, 2.5),
        ],
        MAX_BATCH_POINTS,
    )?;
    let points: Vec<Point> = (0..cols[0].len())
        .map(|i| Point {
            eps0: cols[0][i],
            pressure_kpa: cols[1][i],
            fx: cols[2][i],
            fz: cols[3][i],
            kappa: cols[4][i],
        })
        .collect();
    let (outcomes, stopped) =
        cancellable_partial(py, |cancel| run(&points, &cfg, threads, cancel))?;
    let outcomes = outcomes.map_err(crate::errors::InternalError::new_err)?;

    let d = PyDict::new(py);
    d.set_item("shape", PyTuple::new(py, &dims)?)?;
    for (name, col) in ["eps0", "pressure_kpa", "fx", "fz", "kappa"]
        .iter()
        .zip(cols)
    {
        d.set_item(*name, array1(py, col))?;
    }
    let m = outcomes.len();
    let mut tip = Vec::with_capacity(2 * m);
    let (mut end_angle, mut residual) = (Vec::with_capacity(m), Vec::with_capacity(m));
    let mut tip_error = Vec::with_capacity(m);
    let (mut status, mut iterations) = (Vec::with_capacity(m), Vec::with_capacity(m));
    let (mut valid, mut elements) = (Vec::with_capacity(m), Vec::with_capacity(m));
    let mut errors = Vec::with_capacity(m);
    for o in outcomes {
        tip.extend(o.tip);
        end_angle.push(o.end_angle);
        tip_error.push(o.tip_error);
        residual.push(o.residual);
        status.push(o.status as i8);
        iterations.push(o.iterations as i64);
        valid.push(o.valid);
        elements.push(o.elements as i64);
        errors.push(o.error);
    }
    d.set_item("tip", array2(py, tip, 2)?)?;
    d.set_item("end_angle", array1(py, end_angle))?;
    d.set_item("tip_error", array1(py, tip_error))?;
    d.set_item("status", PyArray1::from_vec(py, status))?;
    d.set_item("residual", array1(py, residual))?;
    d.set_item("iterations", PyArray1::from_vec(py, iterations))?;
    d.set_item("valid", PyArray1::from_vec(py, valid))?;
    d.set_item("elements", PyArray1::from_vec(py, elements))?;
    d.set_item("error", PyList::new(py, errors)?)?;
    crate::errors::kept_on_interrupt(py, d, stopped)
}

/// For benchmarks only: the batch of the paper's finger at ``eps0`` (N
/// equal elements, tip-only output, cold solves) over the given loads,
/// solved by a plain rayon loop in Rust (one reused ``Solver`` per chunk,
/// no Python objects, no outcome records); returns the wall time in
/// seconds measured in Rust, and the number of points solved.
#[pyfunction]
#[pyo3(signature = (eps0, pressure_kpa, fx, fz, elements=8, threads=None))]
pub fn _batch_reference(
    py: Python<'_>,
    eps0: f64,
    pressure_kpa: Vec<f64>,
    fx: Vec<f64>,
    fz: Vec<f64>,
    elements: usize,
    threads: Option<usize>,
) -> PyResult<(f64, usize)> {
    let n = pressure_kpa.len();
    if fx.len() != n || fz.len() != n {
        return Err(input_error(
            py,
            "fx",
            "fx, fz: must have as many values as pressure_kpa".into(),
        ));
    }
    let finger = fpc::Finger::paper(eps0, elements).map_err(|e| from_input(py, &e))?;
    let loads: Vec<Load> = (0..n)
        .map(|i| {
            Load::unloaded()
                .with_pressure_kpa(pressure_kpa[i])
                .with_tip_force(fx[i], fz[i])
        })
        .collect();
    let opts = SolveOptions::default().tip_only();
    let work = || {
        let threads = rayon::current_num_threads().max(1);
        let chunk = n.div_ceil(8 * threads).max(1);
        let start = Instant::now();
        let solved: usize = loads
            .par_chunks(chunk)
            .map(|c| {
                let mut solver = Solver::new(&finger);
                c.iter()
                    .filter(|l| solver.solve(l, None, &opts).is_ok())
                    .count()
            })
            .sum();
        (start.elapsed().as_secs_f64(), solved)
    };
    let r = py.detach(|| {
        guarded(|| match threads {
            None => Ok(work()),
            Some(t) => rayon::ThreadPoolBuilder::new()
                .num_threads(t)
                .build()
                .map(|p| p.install(work))
                .map_err(|e| e.to_string()),
        })
    });
    match r {
        Ok(Ok(x)) => Ok(x),
        Ok(Err(e)) => Err(crate::errors::InternalError::new_err(e)),
        Err(p) => Err(crate::errors::InternalError::new_err(p)),
    }
}

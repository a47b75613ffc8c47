//! `fpc.Finger`: one finger (actuator, element model, partition) and its
//! solves, and the finger's own arguments (model, elements, load). The
//! actuator's keyword arguments are in [`crate::actuator_args`], scene
//! files in [`crate::scene_input`].

use numpy::PyReadonlyArray2;
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyString};

use fpc::plan::RefinementRecord;
use fpc::scene::PartitionPlan;
use fpc::{
    Actuator, Coefficients, InputError, Load, ModelId, Partition, Plan, PlannedFinger,
    SolveOptions, Solved,
};

use crate::actuator_args::{actuator_from_kwargs, Caller};
use crate::convert::{arg, arg_or, array1, opt_arg, points, solution_dict, to_py};
use crate::errors::{detached, from_input, from_solve, input_error};
use crate::scene_input::read_scene;

// ------------------------------------------------------------ arguments

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
    /// contains ``/``; a missing file is ``FileNotFoundError``, one over
    /// 4 MiB or a directory an ``OSError`` naming it).
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

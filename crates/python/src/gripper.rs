//! `fpc.Gripper`: a gripper of identical fingers, its geometry and its
//! grasp solves (size, cuboid, sphere), one at a time or as warm-started
//! sweeps.

use numpy::PyArray1;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use fpc::gripper::GRIPPER_SAMPLES_PER_ELEMENT;
use fpc::scene::{GraspSpec, GripperSection, PartitionPlan, SceneFile};
use fpc::{Grasp, GripperParams, Load, SolveError, SolveOptions};

use crate::convert::{arg, arg_or, array1, opt_arg, points, solution_dict, to_py};
use crate::errors::{
    cancellable_partial, detached, from_input, from_solve, guarded, in_python_terms, input_error,
};
use crate::finger::{check_pressure_kpa, Finger};
use crate::scene_input::read_scene;
use fpc::scene::{GraspJson, GripperJson};

/// A gripper: identical, synchronised fingers on a palm (one finger is
/// analysed), with the geometry its unloaded finger fixes.
///
/// ``Gripper(finger=None, *, mounting_angle_deg=60, overlap_mm=None,
/// palm_mm=None, fingers=3, mu=0.6, strict=False, stability=True)``
///
/// ``finger``: an ``fpc.Finger`` (default: the paper's, eps0 = 0.25, 8
/// elements; ``elements="auto"`` is chosen at the unloaded state). The palm
/// is given by the overlap of the fingers at rest (default 20 mm) or by its
/// diameter ``palm_mm``. ``strict``: a grasp that bends an element
/// backwards is invalid, not only flagged. ``stability``: judge every
/// grasp's stability with the object holding the tip (the restricted
/// Hessian's inertia; an unstable grasp is invalid, and a grasp that a
/// direct solve finds unstable is followed along its path from the rest
/// state). Errors name the scene's
/// keys (``gripper.overlap_mm``, ...).
#[pyclass(module = "fpc", frozen)]
pub struct Gripper {
    inner: fpc::Gripper,
    /// A scene's grasp (``Gripper.from_scene``), solved by ``solve()``.
    scene_grasp: Option<GraspSpec>,
}

/// The finger a gripper is built on.
fn gripper_finger(py: Python<'_>, f: &Finger) -> PyResult<fpc::Finger> {
    match f.planned.fixed() {
        Some(finger) => Ok(finger.clone()),
        None => {
            let opts = SolveOptions {
                samples_per_element: GRIPPER_SAMPLES_PER_ELEMENT,
                stability: false,
                ..SolveOptions::default()
            };
            let planned = f.planned.clone();
            detached(py, move || {
                planned.solve(&Load::unloaded(), &opts).map(|a| a.finger)
            })?
            .map_err(|e| from_solve(py, &e))
        }
    }
}

/// One grasp's outcome as a dict: the keys of `solution.json`'s `grasp`,
/// and `solution` (the finger's equilibrium, as `Finger.solve` returns
/// it), `points_gripper` (n x 2, gripper frame) and `warnings`.
fn grasp_dict<'py>(
    py: Python<'py>,
    gripper: &fpc::Gripper,
    o: &fpc::scene::GraspOutcome,
) -> PyResult<Bound<'py, PyDict>> {
    let d = to_py(py, &GraspJson::of(gripper, o))?.cast_into::<PyDict>()?;
    let sol = &o.grasp.solution;
    d.set_item("solution", solution_dict(py, sol)?)?;
    let g: Vec<[f64; 2]> = sol.points.iter().map(|&p| gripper.to_gripper(p)).collect();
    d.set_item("points_gripper", points(py, &g)?)?;
    d.set_item("warnings", to_py(py, &o.grasp.warnings)?)?;
    d.set_item("reversed", o.grasp.is_reversed())?;
    Ok(d)
}

/// The most points of one `Gripper.sweep` (the broadcast size), checked
/// before the inputs are flattened.
pub const MAX_SWEEP_POINTS: usize = 100_000;

/// `beta_deg`: finite, in [-90, 90] degrees (open: (-90, 90) for a sphere).
fn check_beta_deg(beta_deg: f64, open: bool) -> Result<(), fpc::InputError> {
    let field = fpc::Field::key("beta_deg");
    if !beta_deg.is_finite() {
        return Err(fpc::InputError::NotFinite {
            field,
            value: beta_deg,
        });
    }
    let inside = if open {
        beta_deg.abs() < 90.0
    } else {
        beta_deg.abs() <= 90.0
    };
    if inside {
        Ok(())
    } else {
        Err(fpc::InputError::OutOfRange {
            field,
            value: beta_deg,
            rule: if open {
                "must lie in (-90, 90) degrees".into()
            } else {
                "must lie in [-90, 90] degrees".into()
            },
        })
    }
}

/// [`solve_spec`] with the errors in the terms of the Python arguments.
fn solve_py(
    g: &fpc::Gripper,
    spec: GraspSpec,
    warm: Option<&Grasp>,
) -> Result<fpc::scene::GraspOutcome, SolveError> {
    match spec {
        GraspSpec::Size {
            beta_deg,
            pressure_kpa,
            ..
        } => {
            check_pressure_kpa(pressure_kpa)?;
            check_beta_deg(beta_deg, false)?
        }
        GraspSpec::Sphere {
            beta_deg,
            pressure_kpa,
            ..
        } => {
            check_pressure_kpa(pressure_kpa)?;
            check_beta_deg(beta_deg, true)?
        }
        GraspSpec::Cuboid { pressure_kpa, .. } => check_pressure_kpa(pressure_kpa)?,
    }
    solve_spec(g, spec, warm).map_err(in_python_terms)
}

/// Solves one grasp as `fpc solve` does (the library's one grasp solve).
fn solve_spec(
    g: &fpc::Gripper,
    spec: GraspSpec,
    warm: Option<&Grasp>,
) -> Result<fpc::scene::GraspOutcome, SolveError> {
    spec.solve(g, warm)
}

/// The validated design from Python's arguments, through the scene's
/// `[gripper]` checks (errors name `gripper.<key>`).
fn params(py: Python<'_>, section: GripperSection) -> PyResult<(GripperParams, Option<GraspSpec>)> {
    let file = SceneFile {
        gripper: Some(section),
        ..SceneFile::default()
    };
    let scene = file.resolve().map_err(|e| from_input(py, &e))?;
    let g = scene
        .gripper
        .expect("a gripper section resolves to a gripper");
    Ok((g.params, g.grasp))
}

impl Gripper {
    fn solve_one<'py>(&self, py: Python<'py>, spec: GraspSpec) -> PyResult<Bound<'py, PyDict>> {
        let g = &self.inner;
        let out = detached(py, || solve_py(g, spec, None))?.map_err(|e| from_solve(py, &e))?;
        grasp_dict(py, g, &out)
    }
}

#[pymethods]
impl Gripper {
    #[new]
    #[pyo3(signature = (finger=None, *, mounting_angle_deg=None, overlap_mm=None, palm_mm=None, fingers=None, mu=None, strict=None, stability=None))]
    #[pyo3(
        text_signature = "(finger=None, *, mounting_angle_deg=None, overlap_mm=None, palm_mm=None, fingers=None, mu=None, strict=None, stability=True)"
    )]
    #[allow(clippy::too_many_arguments)]
    fn new(
        py: Python<'_>,
        finger: Option<&Bound<'_, PyAny>>,
        mounting_angle_deg: Option<&Bound<'_, PyAny>>,
        overlap_mm: Option<&Bound<'_, PyAny>>,
        palm_mm: Option<&Bound<'_, PyAny>>,
        fingers: Option<&Bound<'_, PyAny>>,
        mu: Option<&Bound<'_, PyAny>>,
        strict: Option<&Bound<'_, PyAny>>,
        stability: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Gripper> {
        let finger: Option<PyRef<'_, Finger>> = opt_arg("finger", finger)?;
        let mounting_angle_deg: Option<f64> = opt_arg("mounting_angle_deg", mounting_angle_deg)?;
        let overlap_mm: Option<f64> = opt_arg("overlap_mm", overlap_mm)?;
        let palm_mm: Option<f64> = opt_arg("palm_mm", palm_mm)?;
        let fingers: Option<usize> = opt_arg("fingers", fingers)?;
        let mu: Option<f64> = opt_arg("mu", mu)?;
        let strict: Option<bool> = opt_arg("strict", strict)?;
        let stability: bool = arg_or("stability", stability, true)?;
        for (field, v) in [
            ("gripper.mounting_angle_deg", mounting_angle_deg),
            ("gripper.overlap_mm", overlap_mm),
            ("gripper.palm_mm", palm_mm),
            ("gripper.mu", mu),
        ] {
            if let Some(x) = v.filter(|x| !x.is_finite()) {
                return Err(from_input(
                    py,
                    &fpc::InputError::NotFinite {
                        field: fpc::Field::key(field),
                        value: x,
                    },
                ));
            }
        }
        let (params, _) = self::params(
            py,
            GripperSection {
                mounting_angle_deg,
                overlap_mm,
                palm_mm,
                fingers,
                mu,
                strict,
                grasp: None,
            },
        )?;
        let default;
        let finger = match &finger {
            Some(f) => &**f,
            None => {
                default = Finger::build(
                    py,
                    fpc::ModelId::default(),
                    fpc::Actuator::default(),
                    true,
                    crate::finger::ElementsArg::Default,
                )?;
                &default
            }
        };
        let f = gripper_finger(py, finger)?;
        let inner = detached(py, move || fpc::Gripper::new(f, params))?
            .map_err(|e| from_solve(py, &e))?
            .with_stability(stability);
        Ok(Gripper {
            inner,
            scene_grasp: None,
        })
    }

    /// The gripper of a scene file with a ``[gripper]`` section (TOML text
    /// or a path, as for ``Finger.from_scene``: an ``os.PathLike`` or a
    /// one-line ``str`` ending in ``.toml`` or containing ``/``; a missing
    /// file is ``FileNotFoundError``, one over 4 MiB or a directory an
    /// ``OSError``). Its ``[gripper.grasp]``, if any, is
    /// solved by :meth:`solve`.
    #[staticmethod]
    fn from_scene(py: Python<'_>, scene: &Bound<'_, PyAny>) -> PyResult<Gripper> {
        let (scene, _) = read_scene(scene)?;
        let Some(g) = scene.gripper else {
            return Err(input_error(
                py,
                "gripper",
                "gripper: the scene has no [gripper] section".into(),
            ));
        };
        let finger = match &scene.partition {
            PartitionPlan::Fixed(part) => {
                fpc::Finger::with_model(scene.model, &scene.actuator, part, true)
            }
            _ => gripper_finger(py, &Finger::of_scene(&scene))?,
        };
        let params = g.params;
        let inner = detached(py, move || fpc::Gripper::new(finger, params))?
            .map_err(|e| from_solve(py, &e))?
            .with_stability(g.stability);
        Ok(Gripper {
            inner,
            scene_grasp: g.grasp,
        })
    }

    /// Solves the scene's grasp (``Gripper.from_scene``) and returns its
    /// dict (see :meth:`grasp_cuboid`); None when the scene asks for none.
    fn solve<'py>(&self, py: Python<'py>) -> PyResult<Option<Bound<'py, PyDict>>> {
        self.scene_grasp
            .map(|spec| self.solve_one(py, spec))
            .transpose()
    }

    /// (a) The normal force F that gives grasping size ``d_mm`` at grasping
    /// angle ``beta_deg`` with full friction f = mu F, at a channel pressure.
    /// Returns the grasp dict (see :meth:`grasp_cuboid`).
    #[pyo3(signature = (d_mm, beta_deg=None, pressure_kpa=None))]
    #[pyo3(text_signature = "($self, d_mm, beta_deg=0.0, pressure_kpa=0.0)")]
    fn grasp_size<'py>(
        &self,
        py: Python<'py>,
        d_mm: &Bound<'py, PyAny>,
        beta_deg: Option<&Bound<'py, PyAny>>,
        pressure_kpa: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        self.solve_one(
            py,
            GraspSpec::Size {
                pressure_kpa: arg_or("pressure_kpa", pressure_kpa, 0.0)?,
                d_mm: arg("d_mm", d_mm)?,
                beta_deg: arg_or("beta_deg", beta_deg, 0.0)?,
            },
        )
    }

    /// (b) Force control by pressure: the normal force F (grasping angle 0)
    /// that holds a cuboid of size ``d_mm`` with friction ``friction_n`` per
    /// finger, at a channel pressure. Returns a dict with the keys of
    /// ``solution.json``'s ``grasp`` (``kind``, ``pressure_kpa``,
    /// ``beta_deg``, ``normal_force_n``, ``friction_n``,
    /// ``friction_limit_n``, ``lift_n``, ``size_mm``, ``tip_gap_mm``,
    /// ``height_mm``, ``tip_gripper_mm``, ``tip_load_finger_n``, ``valid``,
    /// ``invalid``; for a sphere ``sphere_radius_mm`` and
    /// ``sphere_center_gripper_mm``), and ``solution`` (the finger's
    /// equilibrium as ``Finger.solve`` returns it), ``points_gripper``
    /// (n x 2, gripper frame, mm), ``warnings`` and ``reversed``.
    #[pyo3(signature = (d_mm=None, friction_n=None, pressure_kpa=None))]
    #[pyo3(text_signature = "($self, d_mm=100.0, friction_n=0.3, pressure_kpa=0.0)")]
    fn grasp_cuboid<'py>(
        &self,
        py: Python<'py>,
        d_mm: Option<&Bound<'py, PyAny>>,
        friction_n: Option<&Bound<'py, PyAny>>,
        pressure_kpa: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        self.solve_one(
            py,
            GraspSpec::Cuboid {
                pressure_kpa: arg_or("pressure_kpa", pressure_kpa, 0.0)?,
                d_mm: arg_or("d_mm", d_mm, 100.0)?,
                friction_n: arg_or("friction_n", friction_n, 0.3)?,
            },
        )
    }

    /// (c) A sphere of radius ``r_mm`` held with lifting force ``lift_n``
    /// per finger at grasping angle ``beta_deg``; F and f are solved for.
    /// Returns the grasp dict (see :meth:`grasp_cuboid`).
    #[pyo3(signature = (r_mm=None, lift_n=None, beta_deg=None, pressure_kpa=None))]
    #[pyo3(text_signature = "($self, r_mm=50.0, lift_n=0.5, beta_deg=20.0, pressure_kpa=0.0)")]
    fn grasp_sphere<'py>(
        &self,
        py: Python<'py>,
        r_mm: Option<&Bound<'py, PyAny>>,
        lift_n: Option<&Bound<'py, PyAny>>,
        beta_deg: Option<&Bound<'py, PyAny>>,
        pressure_kpa: Option<&Bound<'py, PyAny>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        self.solve_one(
            py,
            GraspSpec::Sphere {
                pressure_kpa: arg_or("pressure_kpa", pressure_kpa, 0.0)?,
                r_mm: arg_or("r_mm", r_mm, 50.0)?,
                lift_n: arg_or("lift_n", lift_n, 0.5)?,
                beta_deg: arg_or("beta_deg", beta_deg, 20.0)?,
            },
        )
    }

    /// A sweep of grasps of one ``kind`` (``"size"``, ``"cuboid"`` or
    /// ``"sphere"``): the keyword arguments of that kind's method
    /// (``d_mm``, ``beta_deg``, ``friction_n``, ``r_mm``, ``lift_n``,
    /// ``pressure_kpa``) broadcast like numpy arrays; the points are solved
    /// in order, each warm-started from the previous success (the GIL is
    /// released). A failed point does not stop the sweep. Returns a dict of
    /// arrays over the points: ``inputs`` (a dict of the broadcast inputs,
    /// flattened), ``normal_force_n``,
    /// ``friction_n``, ``lift_n``, ``size_mm``, ``tip_gap_mm``,
    /// ``height_mm``, ``tip_gripper`` (n x 2), ``valid``, ``reversed``,
    /// ``ok`` (solved) and ``error`` (list of messages, "" when solved).
    /// At most 100000 points (``fpc.InputError`` for ``points`` beyond);
    /// an input of strings or complex numbers is a ``TypeError`` naming
    /// the argument, one numpy cannot make an array of (a ragged list), or
    /// shapes that do not broadcast, ``fpc.InputError`` naming it (as for
    /// ``batch_solve``); Ctrl-C stops the sweep between
    /// points and raises ``KeyboardInterrupt`` whose ``partial`` attribute
    /// is the same dict with the points solved so far (the others have
    /// ``ok`` False and the error "stopped by Ctrl-C before this point").
    #[pyo3(signature = (kind, **params))]
    fn sweep<'py>(
        &self,
        py: Python<'py>,
        kind: &Bound<'py, PyAny>,
        params: Option<&Bound<'py, PyDict>>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let kind: String = arg("kind", kind)?;
        let kind = kind.as_str();
        let (names, defaults): (&[&str], &[f64]) = match kind {
            "size" => (&["d_mm", "beta_deg", "pressure_kpa"], &[100.0, 0.0, 0.0]),
            "cuboid" => (&["d_mm", "friction_n", "pressure_kpa"], &[100.0, 0.3, 0.0]),
            "sphere" => (
                &["r_mm", "lift_n", "beta_deg", "pressure_kpa"],
                &[50.0, 0.5, 20.0, 0.0],
            ),
            _ => {
                return Err(input_error(
                    py,
                    "kind",
                    format!("kind = `{kind}`: must be size, cuboid or sphere"),
                ))
            }
        };
        if let Some(p) = params {
            for k in p.keys() {
                let k: String = k.extract()?;
                if !names.contains(&k.as_str()) {
                    return Err(pyo3::exceptions::PyTypeError::new_err(format!(
                        "unexpected keyword argument '{k}' for a {kind} sweep (takes {})",
                        names.join(", ")
                    )));
                }
            }
        }
        let mut given = Vec::new();
        for name in names {
            given.push(params.map(|p| p.get_item(name)).transpose()?.flatten());
        }
        let inputs: Vec<(&str, Option<&Bound<'py, PyAny>>, f64)> = names
            .iter()
            .zip(&given)
            .zip(defaults)
            .map(|((name, v), default)| (*name, v.as_ref(), *default))
            .collect();
        // batch_solve's conversion: the same errors for the same mistakes
        let (_, cols) = crate::batch::broadcast(py, &inputs, MAX_SWEEP_POINTS)?;
        let n = cols.first().map_or(0, Vec::len);
        let specs: Vec<GraspSpec> = (0..n)
            .map(|i| match kind {
                "size" => GraspSpec::Size {
                    d_mm: cols[0][i],
                    beta_deg: cols[1][i],
                    pressure_kpa: cols[2][i],
                },
                "cuboid" => GraspSpec::Cuboid {
                    d_mm: cols[0][i],
                    friction_n: cols[1][i],
                    pressure_kpa: cols[2][i],
                },
                _ => GraspSpec::Sphere {
                    r_mm: cols[0][i],
                    lift_n: cols[1][i],
                    beta_deg: cols[2][i],
                    pressure_kpa: cols[3][i],
                },
            })
            .collect();
        let g = &self.inner;
        let (mut results, stopped): (Vec<Result<fpc::scene::GraspOutcome, String>>, _) =
            cancellable_partial(py, |cancel| {
                let mut warm: Option<Grasp> = None;
                specs
                    .iter()
                    .map_while(|&spec| {
                        if cancel.load(std::sync::atomic::Ordering::Relaxed) {
                            return None;
                        }
                        let r = guarded(|| solve_py(g, spec, warm.as_ref()))
                            .map_err(|m| format!("internal error (a bug): {m}"))
                            .and_then(|r| r.map_err(|e| e.to_string()));
                        if let Ok(o) = &r {
                            warm = Some(o.grasp.clone());
                        }
                        Some(r)
                    })
                    .collect()
            })?;
        // the points after a Ctrl-C: not solved, and said so
        results.resize_with(n, || Err(crate::batch::STOPPED.to_string()));
        let d = PyDict::new(py);
        let inputs = PyDict::new(py);
        for (name, col) in names.iter().zip(&cols) {
            inputs.set_item(*name, array1(py, col.clone()))?;
        }
        d.set_item("inputs", inputs)?;
        let pick = |f: &dyn Fn(&fpc::scene::GraspOutcome) -> f64| -> Bound<'py, PyArray1<f64>> {
            array1(
                py,
                results
                    .iter()
                    .map(|r| r.as_ref().map_or(f64::NAN, f))
                    .collect(),
            )
        };
        d.set_item("normal_force_n", pick(&|o| o.grasp.normal))?;
        d.set_item("friction_n", pick(&|o| o.grasp.friction))?;
        d.set_item("lift_n", pick(&|o| o.grasp.lift))?;
        d.set_item("size_mm", pick(&|o| o.grasp.size))?;
        d.set_item("tip_gap_mm", pick(&|o| o.grasp.tip_gap))?;
        d.set_item("height_mm", pick(&|o| o.grasp.height))?;
        let tips: Vec<[f64; 2]> = results
            .iter()
            .map(|r| r.as_ref().map_or([f64::NAN; 2], |o| o.grasp.tip))
            .collect();
        d.set_item("tip_gripper", points(py, &tips)?)?;
        let flags = |f: &dyn Fn(&fpc::scene::GraspOutcome) -> bool| -> Vec<bool> {
            results.iter().map(|r| r.as_ref().is_ok_and(f)).collect()
        };
        d.set_item("valid", PyArray1::from_vec(py, flags(&|o| o.is_valid())))?;
        d.set_item(
            "reversed",
            PyArray1::from_vec(py, flags(&|o| o.grasp.is_reversed())),
        )?;
        d.set_item("ok", PyArray1::from_vec(py, flags(&|_| true)))?;
        let errors: Vec<String> = results
            .iter()
            .map(|r| r.as_ref().err().cloned().unwrap_or_default())
            .collect();
        d.set_item("error", errors)?;
        crate::errors::kept_on_interrupt(py, d, stopped)
    }

    /// The design and the geometry its rest state fixes, as
    /// ``solution.json``'s ``gripper``: ``mounting_angle_deg``, ``mu``,
    /// ``fingers``, ``params``, ``model``, ``elements``, ``l0_mm``,
    /// ``palm_mm``, ``overlap_mm``, ``d_min_mm``, ``d_max_mm``, ``r_max_mm``,
    /// ``tip_is_innermost``, ``rest_tip_gripper_mm``, ``warnings``.
    fn info<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, &GripperJson::of(&self.inner))
    }

    /// The unloaded finger at zero pressure (the reference state), as
    /// ``Finger.solve`` returns it, with ``points_gripper`` (gripper frame).
    fn rest<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        let d = solution_dict(py, self.inner.reference())?;
        d.set_item("points_gripper", points(py, &self.inner.rest_shape())?)?;
        Ok(d)
    }

    /// ``l0``: the largest inward reach of the rest mid-plane (mm).
    #[getter]
    fn l0(&self) -> f64 {
        self.inner.l0()
    }

    /// Palm diameter (mm).
    #[getter]
    fn palm(&self) -> f64 {
        self.inner.palm()
    }

    /// Overlap of the fingers at rest, ``g = l0 - palm / 2`` (mm).
    #[getter]
    fn overlap(&self) -> f64 {
        self.inner.overlap()
    }

    /// Smallest grasping size ``max(0, palm - 2 l0)`` (mm).
    #[getter]
    fn d_min(&self) -> f64 {
        self.inner.d_min()
    }

    /// Largest grasping size: the fingers pressed flat (mm).
    #[getter]
    fn d_max(&self) -> f64 {
        self.inner.d_max()
    }

    /// Largest sphere radius (mm).
    #[getter]
    fn r_max(&self) -> f64 {
        self.inner.r_max()
    }

    /// The mounting angle (deg).
    #[getter]
    fn mounting_angle_deg(&self) -> f64 {
        self.inner.mounting_angle().to_degrees()
    }

    /// Friction coefficient between object and tip.
    #[getter]
    fn mu(&self) -> f64 {
        self.inner.mu()
    }

    /// Notes on the finger and the design, as ``{kind, message, ...}`` dicts.
    #[getter]
    fn warnings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        to_py(py, self.inner.warnings())
    }

    fn __repr__(&self) -> String {
        format!(
            "fpc.Gripper(mounting_angle_deg={}, palm_mm={:.3}, overlap_mm={:.3}, mu={}, elements={})",
            self.inner.mounting_angle().to_degrees(),
            self.inner.palm(),
            self.inner.overlap(),
            self.inner.mu(),
            self.inner.finger().len()
        )
    }
}

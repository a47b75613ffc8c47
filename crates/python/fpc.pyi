"""Type stubs of the `fpc` extension module (crates/python/src).

Fluidic prestressed composite fingers and soft grippers: the chained
composite model (CCM), from Python. Units: mm, N, N mm, rad unless a key
says otherwise (`_kpa`, `_deg`, `_mm`, `_n`, ...).
"""

from os import PathLike
from typing import Any, Literal, Optional, Sequence, Tuple, TypedDict, Union

import numpy as np
import numpy.typing as npt

__version__: str

#: Names of the `status` codes of `batch_solve`, by code:
#: ("ok", "input_error", "not_converged", "internal_error", "stopped").
BATCH_STATUS: Sequence[str]
#: Prestrains of the paper's samples (0.4, 0.25, 0.15).
PAPER_EPS0: Sequence[float]

FloatArray = npt.NDArray[np.float64]
ArrayLike = Union[float, Sequence[float], npt.ArrayLike]
Scene = Union[str, "PathLike[str]"]
Elements = Union[int, Literal["auto"], None]

class InputError(ValueError):
    """A rejected input. The message starts with the field's path
    (``actuator.geometry.h1``, ``pressure_kpa``, ``elements``, ...)."""

    field: str

class SceneError(ValueError):
    """A scene document that is not valid TOML, or has an unknown key or a
    value of the wrong type, at ``line``:``col`` (from 1)."""

    line: int
    col: int

class SolveError(RuntimeError):
    """A failed solve. ``kind`` is ``"not_converged"`` (with ``reason``,
    ``iterations``, ``relative_residual``, ``element``),
    ``"target_not_reached"`` (with ``target``, ``value``, ``reached``),
    ``"not_on_path"`` (with ``target``, ``value``) or ``"cancelled"``."""

    kind: str

class MeasureError(ValueError):
    """Bad measurement input (a manifest or one of its CSV files) at
    ``file``:``line``:``col`` (from 1; ``None`` for what concerns the whole
    file), naming the column or manifest key in ``field``."""

    file: str
    line: Optional[int]
    col: Optional[int]
    field: str

class InternalError(RuntimeError):
    """A bug: the library panicked; the panic was caught at the boundary."""

class WarningDict(TypedDict, total=False):
    """A warning: ``kind``, ``message``, and where they apply ``element``,
    ``value`` and ``limit``."""

    kind: str
    message: str
    element: int
    value: float
    limit: float

class Steps(TypedDict):
    element: int
    coupled: int
    continuation: int
    chord: int
    shifted: int
    damped: int
    grown: int
    extended: int

class Report(TypedDict):
    reason: str
    iterations: int
    residual_norm: float
    evaluations: int
    coupled: bool
    continuation_steps: int
    steps: Steps

class Refinement(TypedDict):
    configuration: str
    levels: list[int]
    level_iterations: list[int]
    level_steps: list[Steps]
    level_tips: FloatArray  # (levels, 2), mm, each level's tip
    extrapolated: bool
    extrapolation: Optional[Literal["last_two", "last_three"]]
    tip: FloatArray
    end_angle: float

class FingerSolution(TypedDict):
    """What `Finger.solve` returns."""

    tip: FloatArray  # (2,), mm, finger frame
    end_angle: float  # rad
    radius: Optional[float]  # mm
    energy: float  # N mm
    negative_eigenvalues: Optional[int]
    stable: Optional[bool]
    coefficients: FloatArray  # (elements, unknowns)
    points: FloatArray  # (n, 2), mm
    element_lengths: FloatArray  # (elements,), mm
    warnings: list[WarningDict]
    valid: bool
    report: Report
    elements: int
    model: str
    tip_error_estimate: Optional[float]  # mm, with tip_tol_mm: of refinement["tip"]
    refinement: Optional[Refinement]

class Finger:
    """A finger: the actuator (the paper's by default), an element model and
    a partition, ready to solve.

    ``elements``: a number of equal elements (default 8) or ``"auto"``.
    ``**actuator``: the scene file's ``[actuator.*]`` keys: ``lx``, ``ly``,
    ``lc``, ``h``, ``h1``, ``h2``, ``h3``, ``cx``, ``cy``, ``h3a``, ``h3b``
    (mm), ``shear_correction`` (the ``shear`` model's factor, default 5/6),
    ``plane_strain`` (default False), or whole sections as dicts:
    ``geometry``, ``channel``, ``rib_layout``, ``cl``, ``emc``, ``fluidic``,
    ``pemc`` (each also ``g13``, the ``shear`` model's transverse shear
    modulus), ``laminate``; ``cl_ribs``, the ribs on the constraining
    layer as a list of dicts (``x0``, ``x1``, ``width``, ``height``, mm).
    ``eps0`` is 0.25
    unless given, as ``eps0=`` or ``pemc={"eps0": ...}``; a key given twice
    (also ``h1=`` with ``geometry={"h1": ...}``) is a ``TypeError``.
    """

    def __init__(
        self,
        eps0: Optional[float] = None,
        elements: Elements = None,
        model: str = "ccm",
        ribs: bool = True,
        **actuator: Any,
    ) -> None: ...
    @staticmethod
    def from_scene(scene: Scene) -> "Finger":
        """The finger of a scene (TOML text or a path: an ``os.PathLike``, or
        a one-line ``str`` ending in ``.toml`` or containing ``/``; a missing
        file is ``FileNotFoundError``, a file over 4 MiB or a directory an
        ``OSError`` naming it); the scene's load, tip tolerance and
        solver settings become the defaults of `solve`."""
    def solve(
        self,
        pressure_kpa: Optional[float] = None,
        fx: Optional[float] = None,
        fz: Optional[float] = None,
        kappa: Optional[float] = None,
        tip_tol_mm: Optional[float] = None,
        *,
        shape: Optional[bool] = None,
        stability: Optional[bool] = None,
        guess: Optional[npt.ArrayLike] = None,
    ) -> FingerSolution:
        """Solves under a pressure (kPa) and a tip force (N, finger frame).
        Raises `InputError` naming the argument, `SolveError` on failure."""
    @property
    def model(self) -> str: ...
    @property
    def unknowns(self) -> list[str]: ...
    @property
    def eps0(self) -> float: ...
    @property
    def length(self) -> float: ...
    @property
    def ribs(self) -> bool: ...
    @property
    def elements(self) -> Union[int, Literal["auto"]]: ...
    @property
    def element_lengths(self) -> Optional[FloatArray]: ...
    @property
    def warnings(self) -> list[WarningDict]: ...

class Verdict(TypedDict):
    """A grasp's verdict: ``valid`` and ``invalid`` (the first reason, or
    None) as the grasp has them, and the parts: ``rules`` (the first of
    the paper's rules broken, ``{kind, message}``, or None), ``findings``
    (the finger's validity findings), ``stability`` (``{kind: stable |
    unstable | unknown | not_judged, ...}``) and ``path`` (``{from,
    steps}``: how the equilibrium was reached from rest)."""

    valid: bool
    invalid: Optional[dict[str, Any]]
    rules: Optional[dict[str, Any]]
    findings: list[WarningDict]
    stability: dict[str, Any]
    path: dict[str, Any]

class Grasp(TypedDict, total=False):
    """What the grasp methods of `Gripper` return: the keys of
    ``solution.json``'s ``grasp`` and the finger's equilibrium."""

    kind: str
    pressure_kpa: float
    beta_deg: float
    normal_force_n: float
    friction_n: float
    friction_limit_n: float
    lift_n: float
    size_mm: float
    tip_gap_mm: float
    height_mm: float
    tip_gripper_mm: list[float]
    tip_load_finger_n: list[float]
    valid: bool
    invalid: Optional[dict[str, str]]
    verdict: Verdict
    sphere_radius_mm: float
    sphere_center_gripper_mm: list[float]
    solution: FingerSolution
    points_gripper: FloatArray
    warnings: list[WarningDict]
    reversed: bool

class Gripper:
    """A gripper of identical fingers on a palm (one finger is analysed)."""

    def __init__(
        self,
        finger: Optional[Finger] = None,
        *,
        mounting_angle_deg: Optional[float] = None,
        overlap_mm: Optional[float] = None,
        palm_mm: Optional[float] = None,
        fingers: Optional[int] = None,
        mu: Optional[float] = None,
        strict: Optional[bool] = None,
        stability: bool = True,
    ) -> None: ...
    @staticmethod
    def from_scene(scene: Scene) -> "Gripper":
        """The gripper of a scene with a ``[gripper]`` section."""
    def solve(self) -> Optional[Grasp]:
        """Solves the scene's ``[gripper.grasp]`` (None: the scene has none)."""
    def grasp_size(self, d_mm: float, beta_deg: float = 0.0, pressure_kpa: float = 0.0) -> Grasp:
        """The normal force for grasping size ``d_mm`` at ``beta_deg`` with f = mu F."""
    def grasp_cuboid(
        self, d_mm: float = 100.0, friction_n: float = 0.3, pressure_kpa: float = 0.0
    ) -> Grasp:
        """Force control: the normal force holding a cuboid of size ``d_mm``."""
    def grasp_sphere(
        self,
        r_mm: float = 50.0,
        lift_n: float = 0.5,
        beta_deg: float = 20.0,
        pressure_kpa: float = 0.0,
    ) -> Grasp:
        """A sphere of radius ``r_mm`` held with lifting force ``lift_n``."""
    def sweep(self, kind: Literal["size", "cuboid", "sphere"], **params: ArrayLike) -> dict[str, Any]:
        """Grasps of one kind over broadcast parameters, warm-started in order:
        ``inputs``, ``normal_force_n``, ``friction_n``, ``lift_n``,
        ``size_mm``, ``tip_gap_mm``, ``height_mm``, ``tip_gripper`` (n x 2),
        ``valid``, ``reversed``, ``ok``, ``error``. At most 100000 points;
        strings and complex inputs are a ``TypeError``; Ctrl-C stops it and raises
        ``KeyboardInterrupt`` whose ``partial`` is this dict for the points
        solved so far (the rest not ``ok``)."""
    def info(self) -> dict[str, Any]:
        """``solution.json``'s ``gripper``: design and geometry."""
    def rest(self) -> FingerSolution:
        """The reference state (unloaded, zero pressure), with ``points_gripper``."""
    @property
    def l0(self) -> float: ...
    @property
    def palm(self) -> float: ...
    @property
    def overlap(self) -> float: ...
    @property
    def d_min(self) -> float: ...
    @property
    def d_max(self) -> float: ...
    @property
    def r_max(self) -> float: ...
    @property
    def mounting_angle_deg(self) -> float: ...
    @property
    def mu(self) -> float: ...
    @property
    def warnings(self) -> list[WarningDict]: ...

def models() -> list[dict[str, Any]]:
    """The element models: ``{name, spec, description, unknowns}``."""

def solve_scene(scene: Scene, name: Optional[str] = None) -> dict[str, Any]:
    """A scene solved as ``fpc solve`` solves it: the keys of its
    ``solution.json``, with ``tip_mm``, ``coefficients``, ``points_mm``,
    ``element_lengths_mm`` (and ``points_gripper_mm``) as numpy arrays.
    ``scene``: TOML text or a path (as for ``Finger.from_scene``)."""

def design(
    requirements: Scene, starts: int = 2, seed: int = 1, scene: Scene | None = None
) -> dict[str, Any]:
    """The gripper to build for a requirements TOML (text or path), as
    ``fpc design`` finds it: ``feasible``, ``best`` (``design`` =
    ``{eps0, mounting_angle_deg, overlap_mm, varied}`` as in design.json,
    ``margins``, ``worst``), ``sensitivities`` (``{requirement, gradient}``,
    the gradient as ``{eps0, mounting_angle_deg, overlap_mm}``),
    ``evaluations``, ``starts``, ``reproductions`` (each object's scene
    solved again: ``{file, valid, reproduced, detail, notes, ...}``, the
    notes naming what does not void the grasp, such as a reversed element
    outside strict mode) and ``scenes`` (``{name, toml}`` per object, for
    ``solve_scene``) and ``notes``. ``scene``: design from that scene's
    finger (model, actuator, load.kappa, [calibration]; its eps0 unless
    varied), as ``fpc design --scene``. ``starts`` <= 10000. Raises
    ``SceneError`` or ``InputError`` for bad requirements or scene,
    ``FileNotFoundError`` for a missing path (``OSError`` for a file over
    4 MiB or a directory); Ctrl-C interrupts."""

def compare(manifest: Union[str, PathLike[str]]) -> dict[str, Any]:
    """The model against the measurements of a manifest (docs/measurements.md),
    no parameter fitted, with the keys of ``fpc compare --json``
    (``chi_square``, ``points``, ``specimens`` with their ``tests`` and each
    row's ``predictions``), and in every test ``arrays``: per measured
    quantity, in file order, numpy arrays ``pressure_kpa``, ``measured``,
    ``sd``, ``predicted``, ``residual``, ``residual_sd`` (NaN without a
    prediction) and the list ``quantity``. Raises ``FileNotFoundError``
    for a missing manifest, ``MeasureError`` for bad measurement input,
    ``InputError`` for an actuator the model cannot build; Ctrl-C
    interrupts."""

def calibrate(
    manifest: Union[str, PathLike[str]],
    fit: Union[str, Sequence[str]],
    *,
    max_iterations: int = 100,
    cross_validate: bool = False,
    choose_model: bool = False,
) -> dict[str, Any]:
    """The parameters that fit the measurements of a manifest, as ``fpc
    calibrate`` finds them (docs/calibration.md): ``fit`` names them (a
    list, or ``"eps0,kappa"``; at most 16), ``max_iterations`` 1 to 1000.
    Returns the keys of calibration.json (``parameters``,
    ``identifiability``, ``chi_square_per_dof``, ``residuals``,
    ``reproduction``: the fit compared with the data again through
    ``compare``'s path, ``reproduced`` or not, ...), plus
    ``values`` and ``standard_errors`` as arrays in the order of
    ``parameters``, ``covariance`` and ``correlation`` as square arrays
    (None when not determined), and ``scenes`` (``{name, toml}``: each
    specimen's calibrated scene); with ``choose_model``, ``model_choice``
    (every element model with the ribs and without, in plane stress and
    in plane strain, ranked by held-out error). ``fit`` takes the
    ``shear`` model's ``shear_correction`` and ``cl.g13`` ... too. Raises ``FileNotFoundError``,
    ``MeasureError``, ``InputError`` (naming ``fit``, ``max_iterations`` or
    a parameter); Ctrl-C interrupts."""

def studies() -> list[dict[str, Any]]:
    """The paper's studies: ``{number, key, title, description}``."""

def run_study(
    study: Union[int, str],
    *,
    elements: Optional[int] = None,
    mu: Optional[float] = None,
    sweep_points: Optional[int] = None,
    angle_samples: Optional[int] = None,
    pressure_points: Optional[int] = None,
    strict: Optional[bool] = None,
    coarse: bool = False,
    **actuator: Any,
) -> dict[str, Any]:
    """Runs one study: ``tables`` ({table: {column: numpy array}}),
    ``units``, ``columns``, ``figure``, ``summary``, ``overview``, ``notes``,
    ``stops``, ``design_warnings``, ``points``, ``warnings_by_kind``,
    ``strict_dropped``. An option the study does not use (or
    ``pemc={"eps0": ...}``: each study sets its prestrain) is a
    ``TypeError``; bounds (``InputError`` beyond): ``sweep_points`` <= 2000,
    ``angle_samples`` <= 200 (study 5: their product times ``elements``
    <= 800000, i.e. 100000 grasps of 8 elements),
    ``pressure_points`` <= 10000. Ctrl-C
    interrupts."""

class BatchResult(TypedDict):
    shape: Tuple[int, ...]
    eps0: FloatArray
    pressure_kpa: FloatArray
    fx: FloatArray
    fz: FloatArray
    kappa: FloatArray
    tip: FloatArray  # (M, 2), mm
    end_angle: FloatArray  # (M,), rad
    tip_error: FloatArray  # (M,), mm: of tip with tip_tol_mm (then the extrapolated tip), else NaN
    status: npt.NDArray[np.int8]  # BATCH_STATUS[code]
    residual: FloatArray
    iterations: npt.NDArray[np.int64]
    valid: npt.NDArray[np.bool_]
    elements: npt.NDArray[np.int64]
    error: list[str]

def batch_solve(
    eps0: Optional[ArrayLike] = None,
    pressure_kpa: Optional[ArrayLike] = None,
    fx: Optional[ArrayLike] = None,
    fz: Optional[ArrayLike] = None,
    kappa: Optional[ArrayLike] = None,
    *,
    elements: Elements = None,
    model: str = "ccm",
    ribs: bool = True,
    tip_tol_mm: Optional[float] = None,
    warm_start: bool = False,
    threads: Optional[int] = None,
    **actuator: Any,
) -> BatchResult:
    """Many finger solves in parallel (rayon, the GIL released) over the
    broadcast inputs; equal to a loop of `Finger.solve` unless
    ``warm_start``. At most 1000000 points and 1024 threads (``InputError``
    beyond); strings and complex inputs, and ``pemc={"eps0": ...}`` (the prestrain is the
    ``eps0`` argument), are a ``TypeError``; Ctrl-C stops it and raises
    ``KeyboardInterrupt`` whose ``partial`` is this dict for the points
    solved so far (the rest have status 4, ``stopped``)."""

def _batch_reference(
    eps0: float,
    pressure_kpa: Sequence[float],
    fx: Sequence[float],
    fz: Sequence[float],
    elements: int = 8,
    threads: Optional[int] = None,
) -> Tuple[float, int]:
    """Benchmarks only: the same batch by a plain Rust loop; (seconds, solved)."""

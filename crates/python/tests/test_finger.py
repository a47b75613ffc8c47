"""`fpc.Finger`: defaults, the dict it returns, the actuator keywords,
partitions, tip tolerances, warm starts and scenes."""

import pathlib

import numpy as np
import pytest

import fpc
from conftest import REPO


def test_the_paper_finger_curls_and_is_stable():
    f = fpc.Finger()
    assert (f.eps0, f.elements, f.model, f.ribs, f.length) == (0.25, 8, "ccm", True, 110.0)
    assert f.unknowns == ["a1", "a3", "b1", "c2"]
    assert f.warnings == []
    r = f.solve()
    assert r["tip"].shape == (2,) and r["tip"].dtype == np.float64
    assert r["tip"][1] < 0  # curls towards the prestressed side
    assert r["coefficients"].shape == (8, 4)
    assert r["points"].shape == (8 * 16 + 1, 2)
    np.testing.assert_array_equal(r["points"][0], [0.0, 0.0])
    np.testing.assert_allclose(r["points"][-1], r["tip"], atol=1e-12)
    np.testing.assert_allclose(r["element_lengths"], [110 / 8] * 8)
    assert r["stable"] is True and r["negative_eigenvalues"] == 0
    assert r["valid"] is True and r["warnings"] == []
    assert r["report"]["residual_norm"] <= 1e-10 and r["report"]["coupled"] is False
    assert r["elements"] == 8 and r["model"] == "ccm"
    assert r["refinement"] is None and r["tip_error_estimate"] is None
    assert isinstance(r["energy"], float) and isinstance(r["radius"], float)


def test_a_loaded_solve_and_tip_only_output():
    f = fpc.Finger()
    r = f.solve(pressure_kpa=50, fx=0.5, fz=0.2)
    assert r["report"]["coupled"] is True
    # the iterations by phase add up: the unloaded start, then coupled Newton
    s = r["report"]["steps"]
    assert s["element"] > 0 and s["coupled"] > 0
    assert s["element"] + s["coupled"] + s["continuation"] == r["report"]["iterations"]
    t = f.solve(pressure_kpa=50, fx=0.5, fz=0.2, shape=False, stability=False)
    np.testing.assert_array_equal(t["tip"], r["tip"])
    assert t["points"].shape == (0, 2) and t["radius"] is None
    assert t["stable"] is None and t["negative_eigenvalues"] is None


def test_a_guess_starts_newton_nearby():
    f = fpc.Finger()
    near = f.solve(fx=0.45, fz=0.2)
    cold = f.solve(fx=0.5, fz=0.2)
    warm = f.solve(fx=0.5, fz=0.2, guess=near["coefficients"])
    np.testing.assert_allclose(warm["tip"], cold["tip"], atol=1e-8)
    assert warm["report"]["iterations"] < cold["report"]["iterations"]


def test_validity_findings_and_notes():
    r = fpc.Finger(eps0=0.4, elements=2).solve()
    assert r["valid"] is False
    kinds = {w["kind"] for w in r["warnings"]}
    assert "element_slope" in kinds
    slope = next(w for w in r["warnings"] if w["kind"] == "element_slope")
    assert set(slope) == {"kind", "message", "element", "value", "limit"}
    f = fpc.Finger(eps0=0.7)
    assert [w["kind"] for w in f.warnings] == ["eps0_outside_fit"]


def test_auto_partition_and_tip_tolerance():
    f = fpc.Finger(eps0=0.4, elements="auto")
    assert f.elements == "auto" and f.element_lengths is None
    r = f.solve()
    assert r["elements"] > 8 and r["valid"]
    t = fpc.Finger().solve(fx=0.3, tip_tol_mm=0.1)
    assert t["tip_error_estimate"] <= 0.1
    ref = t["refinement"]
    assert ref["extrapolated"] and ref["levels"][-1] == t["elements"]
    assert ref["tip"].shape == (2,)


def test_actuator_keywords():
    short = fpc.Finger(lx=90.0, cx=85.0)
    assert short.length == 90.0
    a = fpc.Finger().solve()["tip"]
    b = short.solve()["tip"]
    assert np.hypot(*b) < np.hypot(*a)
    # whole sections, with the scene's keys
    stiff = fpc.Finger(cl={"kind": "isotropic", "e": 600.0, "nu": 0.43}).solve()["tip"]
    assert not np.allclose(stiff, a)
    none = fpc.Finger(rib_layout={"kind": "none"}).solve()["tip"]
    assert not np.allclose(none, a)
    same = fpc.Finger(geometry={"lx": 110.0}, pemc={"p1": 1.598}, h=8.2).solve()["tip"]
    np.testing.assert_array_equal(same, a)
    np.testing.assert_array_equal(fpc.Finger(lx=np.float64(110.0)).solve()["tip"], a)


def test_from_scene_takes_text_paths_and_pathlike():
    path = REPO / "scenes" / "pressurised.toml"
    for arg in (path, str(path), path.read_text()):
        f = fpc.Finger.from_scene(arg)
        assert f.eps0 == 0.4
        r = f.solve()  # the scene's load: 100 kPa
        assert r["points"].shape == (8 * 32 + 1, 2)  # samples_per_element = 32
    unloaded = f.solve(pressure_kpa=0)
    assert not np.allclose(unloaded["tip"], r["tip"])
    assert fpc.Finger.from_scene("").solve()["tip"].tolist() == fpc.Finger().solve()["tip"].tolist()
    with pytest.raises(OSError):
        fpc.Finger.from_scene(pathlib.Path("/nonexistent/scene.toml"))


def test_models_and_docs():
    names = [m["name"] for m in fpc.models()]
    assert "ccm" in names and "quad" in names
    for obj in (fpc, fpc.Finger, fpc.Finger.solve, fpc.Finger.from_scene, fpc.Gripper,
                fpc.Gripper.grasp_cuboid, fpc.solve_scene, fpc.run_study, fpc.batch_solve,
                fpc.studies, fpc.models):
        assert obj.__doc__, obj
    assert repr(fpc.Finger(elements="auto")).startswith("fpc.Finger(")
    assert fpc.__version__

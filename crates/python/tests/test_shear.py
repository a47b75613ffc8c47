"""The shear model and the laminate's options from Python: a `shear`
finger built from keywords (shear correction, a layer's G13, plane
strain) equals `fpc solve` on the scene file that says the same (to
1e-12), and `fpc.calibrate` fits the shear correction of data made with
the shear model. Needs FPC_BIN (see conftest.py) for the CLI parity."""

import json

import numpy as np
import pytest

import fpc
from conftest import assert_same, run_cli

SCENE = """\
[model]
name = "shear"
[actuator.laminate]
shear_correction = 0.6
plane_strain = true
[actuator.cl]
g13 = 80.0
[actuator.pemc]
eps0 = 0.3
[load]
pressure_kpa = 30
fx = 0.4
fz = 0.2
"""

KEYWORDS = dict(
    eps0=0.3, model="shear", shear_correction=0.6, plane_strain=True, cl={"g13": 80.0}
)


def test_a_shear_finger_from_keywords_equals_fpc_solve(fpc_bin, tmp_path):
    scene = tmp_path / "shear.toml"
    scene.write_text(SCENE)
    run_cli(fpc_bin, "solve", scene, "--out", tmp_path / "out")
    want = json.loads((tmp_path / "out" / "solution.json").read_text())
    got = fpc.Finger(**KEYWORDS).solve(pressure_kpa=30, fx=0.4, fz=0.2)
    assert got["model"] == "shear"
    assert_same(got["tip"], want["tip_mm"])
    assert_same(got["end_angle"], want["end_angle_rad"])
    assert_same(got["energy"], want["energy_nmm"])
    assert_same(got["coefficients"], want["coefficients"])
    # the scene's text gives the same finger
    assert_same(fpc.Finger.from_scene(SCENE).solve()["tip"], want["tip_mm"])


def test_the_shear_data_change_only_the_shear_model():
    def tip(**kw):
        return fpc.Finger(eps0=0.3, **kw).solve(fx=0.4, fz=0.2)["tip"]

    # the paper's element reads neither the correction nor G13
    np.testing.assert_array_equal(tip(), tip(shear_correction=0.3, cl={"g13": 10.0}))
    # shear softens: a smaller correction moves the tip further from rest
    soft, stiff = tip(model="shear", shear_correction=0.3), tip(model="shear")
    rest = fpc.Finger(eps0=0.3).solve()["tip"]
    assert np.linalg.norm(soft - rest) > np.linalg.norm(stiff - rest)


def test_a_bad_shear_correction_names_its_key():
    with pytest.raises(fpc.InputError, match="actuator.laminate.shear_correction"):
        fpc.Finger(model="shear", shear_correction=-1.0)
    with pytest.raises(fpc.InputError, match="actuator.cl.g13"):
        fpc.Finger(model="shear", cl={"g13": 0.0})


def force_z(finger, pressure_kpa, displacement_mm=10.0):
    """The tip force along +Z (N) that moves the tip `displacement_mm`
    along +Z at `pressure_kpa` (study 8's force), by the secant method on
    ordinary solves."""
    z0 = finger.solve(pressure_kpa=pressure_kpa)["tip"][1]

    def miss(f):
        return finger.solve(pressure_kpa=pressure_kpa, fz=f)["tip"][1] - z0 - displacement_mm

    a, b = 0.1, 0.2
    ma, mb = miss(a), miss(b)
    for _ in range(50):
        a, b, ma = b, b - mb * (b - a) / (mb - ma), mb
        mb = miss(b)
        if abs(mb) < 1e-11:
            return b
    raise AssertionError(f"no force found at {pressure_kpa} kPa")


def test_calibrate_fits_the_shear_correction(tmp_path):
    # noise-free study 8 forces (10 mm along Z) of a shear finger with
    # ks = 0.5, found by the secant method on ordinary solves
    truth = fpc.Finger(eps0=0.25, model="shear", shear_correction=0.5)
    rows = ["pressure_kpa,axis,displacement_mm,force_n,sd_n,repeats"]
    for p in (0.0, 20.0, 40.0, 55.2):
        f = force_z(truth, p)
        rows.append(f"{p},Z,10,{float(f)!r},{1e-4 * abs(float(f))!r},1")
    (tmp_path / "force.csv").write_text("\n".join(rows) + "\n")
    m = tmp_path / "manifest.toml"
    m.write_text(
        '[shared.model]\nname = "shear"\n'
        '[[specimen]]\nname = "a"\n'
        '[[specimen.test]]\nkind = "force"\nfile = "force.csv"\n'
    )
    # from the default 5/6
    c = fpc.calibrate(m, ["shear_correction"])
    (p,) = c["parameters"]
    assert p["name"] == "actuator.laminate.shear_correction"
    assert abs(p["value"] - 0.5) < 1e-4, p
    assert "shear_correction" in c["scenes"][0]["toml"]


CL_RIBS_SCENE = """\
[actuator.pemc]
eps0 = 0.3
[actuator.cl_ribs]
list = [
  { x0 = 20.0, x1 = 35.0, width = 30.0, height = 0.6 },
  { x0 = 60.0, x1 = 61.5, width = 12.0, height = 1.0 },
]
[load]
pressure_kpa = 30
fx = 0.4
fz = 0.2
"""

CL_RIBS = [
    {"x0": 20.0, "x1": 35.0, "width": 30.0, "height": 0.6},
    {"x0": 60.0, "x1": 61.5, "width": 12.0, "height": 1.0},
]


def test_ribs_on_the_constraining_layer_from_keywords_equal_fpc_solve(fpc_bin, tmp_path):
    scene = tmp_path / "cl_ribs.toml"
    scene.write_text(CL_RIBS_SCENE)
    run_cli(fpc_bin, "solve", scene, "--out", tmp_path / "out")
    want = json.loads((tmp_path / "out" / "solution.json").read_text())
    for finger in (
        fpc.Finger(eps0=0.3, cl_ribs=CL_RIBS),
        fpc.Finger(eps0=0.3, cl_ribs={"list": CL_RIBS}),
    ):
        got = finger.solve(pressure_kpa=30, fx=0.4, fz=0.2)
        assert_same(got["tip"], want["tip_mm"])
        assert_same(got["energy"], want["energy_nmm"])
    # the ribs change the laminate: the same load puts the tip elsewhere
    plain = fpc.Finger(eps0=0.3).solve(pressure_kpa=30, fx=0.4, fz=0.2)
    assert np.linalg.norm(plain["tip"] - got["tip"]) > 1e-3


def test_a_bad_rib_on_the_constraining_layer_names_its_key():
    bad = [dict(CL_RIBS[0], height=-1.0)]
    with pytest.raises(fpc.InputError, match=r"actuator.cl_ribs.*height"):
        fpc.Finger(cl_ribs=bad)
    with pytest.raises(TypeError, match="cl_ribs must be a list of ribs"):
        fpc.Finger(cl_ribs=3.0)
    with pytest.raises(fpc.InputError, match="actuator.cl_ribs"):
        fpc.Finger(cl_ribs=[{"x0": 1.0}])

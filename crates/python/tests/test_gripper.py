"""`fpc.Gripper`: geometry, the three grasps and sweeps."""

import numpy as np
import pytest

import fpc


@pytest.fixture(scope="module")
def gripper():
    return fpc.Gripper()


def test_the_section5_gripper(gripper):
    assert gripper.mounting_angle_deg == pytest.approx(60.0)
    assert gripper.mu == 0.6
    assert gripper.overlap == pytest.approx(20.0)
    assert gripper.palm == pytest.approx(2 * (gripper.l0 - 20.0))
    assert gripper.d_min == 0.0 and gripper.d_max > 100.0 and gripper.r_max > 0
    info = gripper.info()
    assert info["mounting_angle_deg"] == 60.0 and info["fingers"] == 3
    rest = gripper.rest()
    assert rest["points_gripper"].shape == rest["points"].shape
    assert gripper.warnings == []


def test_grasps(gripper):
    c = gripper.grasp_cuboid(d_mm=100.0, friction_n=0.3, pressure_kpa=20.0)
    assert c["kind"] == "cuboid" and c["valid"] and c["invalid"] is None
    assert c["size_mm"] == pytest.approx(100.0, abs=1e-6)
    assert c["friction_n"] == pytest.approx(0.3, abs=1e-9)
    assert c["normal_force_n"] > 0
    assert c["solution"]["tip"].shape == (2,)
    assert c["points_gripper"].shape == c["solution"]["points"].shape
    s = gripper.grasp_size(d_mm=80.0, beta_deg=10.0)
    assert s["kind"] == "size" and s["friction_n"] == pytest.approx(0.6 * s["normal_force_n"])
    sp = gripper.grasp_sphere(r_mm=50.0, lift_n=0.5, beta_deg=20.0)
    assert sp["kind"] == "sphere" and sp["sphere_radius_mm"] == pytest.approx(50.0)
    assert sp["lift_n"] == pytest.approx(0.5, abs=1e-9)


def test_a_gripper_on_a_given_finger():
    g = fpc.Gripper(fpc.Finger(eps0=0.15, elements=6), mounting_angle_deg=72.0, palm_mm=40.0)
    assert g.palm == 40.0 and g.info()["elements"] == 6
    auto = fpc.Gripper(fpc.Finger(elements="auto"))
    assert auto.info()["elements"] >= 8


def test_a_sweep_equals_single_grasps_to_tolerance(gripper):
    d = np.linspace(60.0, 120.0, 7)
    sw = gripper.sweep("cuboid", d_mm=d, friction_n=0.3)
    assert sw["ok"].all(), sw["error"]
    np.testing.assert_array_equal(sw["inputs"]["d_mm"], d)
    np.testing.assert_allclose(sw["size_mm"], d, atol=1e-6)
    for i in (0, 3, 6):
        one = gripper.grasp_cuboid(d_mm=d[i], friction_n=0.3)
        assert sw["normal_force_n"][i] == pytest.approx(one["normal_force_n"], abs=1e-7)
    assert sw["tip_gripper"].shape == (7, 2)
    # a failing point does not stop the sweep
    sw = gripper.sweep("size", d_mm=[80.0, 1e4, 90.0])
    assert list(sw["ok"]) == [True, False, True]
    assert sw["error"][1].startswith("d_mm") and np.isnan(sw["normal_force_n"][1])
    sp = gripper.sweep("sphere", r_mm=50.0, beta_deg=[10.0, 20.0])
    assert sp["inputs"]["r_mm"].tolist() == [50.0, 50.0]

"""Errors map as documented: rejected input is `fpc.InputError`, a
`ValueError` whose message starts with the field (also in `.field`); scene
syntax errors are `fpc.SceneError` (a `ValueError` with `.line`, `.col`);
failed solves are `fpc.SolveError` (a `RuntimeError`)."""

import math

import pytest

import fpc


def field_error(call, field):
    with pytest.raises(ValueError) as e:
        call()
    err = e.value
    assert isinstance(err, fpc.InputError), type(err)
    assert err.field == field, str(err)
    assert str(err).startswith(field), str(err)
    return err


def test_the_exception_classes():
    assert issubclass(fpc.InputError, ValueError)
    assert issubclass(fpc.SceneError, ValueError)
    assert issubclass(fpc.SolveError, RuntimeError)
    assert issubclass(fpc.InternalError, RuntimeError)
    for cls in (fpc.InputError, fpc.SceneError, fpc.SolveError, fpc.InternalError):
        assert cls.__module__ == "fpc" and cls.__doc__


def test_actuator_values_name_their_scene_key():
    field_error(lambda: fpc.Finger(h1=5.0), "actuator.geometry.h1")
    field_error(lambda: fpc.Finger(eps0=math.nan), "actuator.pemc.eps0")
    field_error(lambda: fpc.Finger(cx=200.0), "actuator.channel.cx")
    field_error(lambda: fpc.Finger(cl={"e": -1.0, "nu": 0.3}), "actuator.cl.e")
    field_error(lambda: fpc.Finger(pemc={"p1": math.inf}), "actuator.pemc.p1")
    field_error(lambda: fpc.Finger(geometry={"lx": 100.0, "lxx": 3.0}), "actuator.geometry")
    err = field_error(lambda: fpc.Finger(rib_layout={"kind": "zigzag"}), "actuator.ribs")
    assert "zigzag" in str(err)


def test_arguments_name_themselves():
    field_error(lambda: fpc.Finger(elements=0), "elements")
    field_error(lambda: fpc.Finger(elements=5000), "elements")
    # a tip tolerance doubles the count up to 1000 elements: the library's
    # bound on its start is the argument's
    field_error(lambda: fpc.Finger(elements=600).solve(tip_tol_mm=0.1), "elements")
    field_error(lambda: fpc.Finger(elements="many"), "elements")
    field_error(lambda: fpc.Finger(model="nope"), "model")
    f = fpc.Finger()
    field_error(lambda: f.solve(pressure_kpa=-200), "pressure_kpa")
    field_error(lambda: f.solve(pressure_kpa=math.nan), "pressure_kpa")
    field_error(lambda: f.solve(kappa=0), "kappa")
    field_error(lambda: f.solve(fx=math.inf), "fx")
    field_error(lambda: f.solve(fz=math.nan), "fz")
    field_error(lambda: f.solve(tip_tol_mm=-1), "tip_tol_mm")
    field_error(lambda: f.solve(guess=[[0.0] * 4] * 3), "guess")
    field_error(lambda: f.solve(guess=[[math.nan] * 4] * 8), "guess")


def test_wrong_types_and_keywords_are_type_errors():
    with pytest.raises(TypeError, match="unexpected keyword argument 'lxx'"):
        fpc.Finger(lxx=3.0)
    with pytest.raises(TypeError):
        fpc.Finger(elements=2.5)
    with pytest.raises(TypeError):
        fpc.Finger(geometry=3.0)
    with pytest.raises(TypeError):
        fpc.Finger().solve(pressure_kpa="high")


def test_a_failed_solve_is_a_solve_error():
    with pytest.raises(fpc.SolveError) as e:
        fpc.Finger().solve(fx=1e6)
    err = e.value
    assert isinstance(err, RuntimeError)
    assert err.kind == "not_converged"
    assert err.iterations > 0 and err.relative_residual > 0 and err.reason
    assert str(err).startswith("solve failed")


def test_a_grasp_off_the_path_from_rest_is_a_solve_error():
    g = fpc.Gripper()
    # a friction of 5 kN folds the finger before the object is touched
    with pytest.raises(fpc.SolveError) as e:
        g.grasp_cuboid(d_mm=100.0, friction_n=5000.0)
    err = e.value
    assert err.kind == "not_on_path", str(err)
    assert err.target == "friction_n" and err.value == 5000.0
    assert "fold" in str(err)


def test_a_grasp_outside_the_rules_is_returned_invalid_with_its_reason():
    # a friction pulling the object out is reached from rest, and broken
    grasp = fpc.Gripper().grasp_cuboid(d_mm=100.0, friction_n=-50.0)
    assert grasp["valid"] is False
    assert "friction" in str(grasp["invalid"])


def test_scene_errors():
    with pytest.raises(fpc.SceneError) as e:
        fpc.solve_scene("[load]\npresure_kpa = 3\n")
    assert (e.value.line, e.value.col) == (2, 1)
    assert "presure_kpa" in str(e.value)
    assert isinstance(e.value, ValueError)
    field_error(lambda: fpc.solve_scene("[actuator.geometry]\nh1 = 9\n"), "actuator.geometry.h1")
    field_error(lambda: fpc.solve_scene("[gripper]\noverlap_mm = 500\n"), "gripper.overlap_mm")
    field_error(lambda: fpc.Finger.from_scene("[load]\npressure_kpa = -300\n"), "load.pressure_kpa")
    field_error(lambda: fpc.Gripper.from_scene(""), "gripper")
    with pytest.raises(fpc.SolveError):
        fpc.solve_scene("[load]\nfx = 1e6\n")
    with pytest.raises(TypeError):
        fpc.solve_scene(42)


def test_gripper_and_study_errors():
    field_error(lambda: fpc.Gripper(overlap_mm=500.0), "gripper.overlap_mm")
    field_error(lambda: fpc.Gripper(mounting_angle_deg=200.0), "gripper.mounting_angle_deg")
    field_error(lambda: fpc.Gripper(mu=0.0), "gripper.mu")
    field_error(lambda: fpc.Gripper(overlap_mm=10.0, palm_mm=20.0), "gripper.palm_mm")
    field_error(lambda: fpc.Gripper(mu=math.nan), "gripper.mu")
    g = fpc.Gripper()
    # the grasp methods' errors name their arguments (angles in degrees)
    field_error(lambda: g.grasp_size(d_mm=1e4), "d_mm")
    err = field_error(lambda: g.grasp_size(d_mm=80.0, beta_deg=95.0), "beta_deg")
    assert str(err) == "beta_deg = 95: must lie in [-90, 90] degrees"
    field_error(lambda: g.grasp_sphere(beta_deg=90.0), "beta_deg")
    field_error(lambda: g.grasp_sphere(r_mm=-1.0), "r_mm")
    field_error(lambda: g.grasp_sphere(r_mm=1e4), "r_mm")
    field_error(lambda: g.grasp_cuboid(friction_n=math.nan), "friction_n")
    field_error(lambda: g.sweep("cube"), "kind")
    with pytest.raises(TypeError):
        g.sweep("size", r_mm=[1.0])
    field_error(lambda: fpc.run_study(9), "study")
    field_error(lambda: fpc.run_study("nope"), "study")
    field_error(lambda: fpc.run_study(1, sweep_points=1), "study.sweep_points")

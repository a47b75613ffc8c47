"""Every rejected argument is named in the words the caller used: the
keyword as written, in its own unit, whatever the call (a single solve, a
grasp, a sweep, a batch, a study)."""

import numpy as np
import pytest

import fpc


@pytest.fixture(scope="module")
def gripper():
    return fpc.Gripper()


def named_input_error(call, field, start):
    with pytest.raises(fpc.InputError) as e:
        call()
    assert e.value.field == field, str(e.value)
    assert str(e.value).startswith(start), str(e.value)
    return e.value


@pytest.mark.parametrize("kind", ["size", "cuboid", "sphere"])
def test_a_grasp_pressure_below_vacuum_names_pressure_kpa_in_kpa(gripper, kind):
    call = {
        "size": lambda: gripper.grasp_size(100.0, pressure_kpa=-500),
        "cuboid": lambda: gripper.grasp_cuboid(pressure_kpa=-500),
        "sphere": lambda: gripper.grasp_sphere(pressure_kpa=-500),
    }[kind]
    err = named_input_error(call, "pressure_kpa", "pressure_kpa = -500")
    # the same words as a finger's solve
    with pytest.raises(fpc.InputError) as single:
        fpc.Finger().solve(pressure_kpa=-500)
    assert str(err) == str(single.value)


def test_a_library_bound_names_the_keyword_as_written():
    f = fpc.Finger()
    # kappa's lower bound is checked here, its upper bound by the library:
    # both name the keyword
    named_input_error(lambda: f.solve(kappa=0), "kappa", "kappa = 0: must be positive")
    named_input_error(lambda: f.solve(kappa=101), "kappa", "kappa = 101: must be at most 100")
    named_input_error(lambda: f.solve(kappa=1e300), "kappa", "kappa = 1e300")
    r = fpc.batch_solve(kappa=[0, 101, 1e300])
    assert list(r["status"]) == [1, 1, 1]
    for error, start in zip(r["error"], ["kappa = 0:", "kappa = 101:", "kappa = 1e300:"]):
        assert error.startswith(start), error
    # a Gripper's keywords are named as its other ones are (and as a scene
    # writes them): gripper.<keyword>
    for palm, shown in [(1e300, "1e300"), (-5.0, "-5")]:
        named_input_error(
            lambda: fpc.Gripper(palm_mm=palm), "gripper.palm_mm", f"gripper.palm_mm = {shown}"
        )
    # a scene keeps its keys
    with pytest.raises(fpc.InputError) as e:
        fpc.solve_scene("[load]\nkappa = 101\n")
    assert e.value.field == "load.kappa", str(e.value)


def test_a_sweep_reports_the_pressure_in_kpa(gripper):
    s = gripper.sweep("cuboid", pressure_kpa=[-500])
    assert not s["ok"][0]
    assert s["error"][0].startswith("pressure_kpa = -500"), s["error"][0]


def conversion_error(call, kind, name):
    """`call` raises `kind` (and not a subclass swap) whose message names
    the argument `name` as the caller wrote it."""
    with pytest.raises(kind) as e:
        call()
    assert type(e.value) is kind, type(e.value)
    assert f"argument '{name}'" in str(e.value), str(e.value)
    return e.value


def test_a_wrong_type_names_the_argument(gripper):
    f = fpc.Finger(elements=4)
    c = f.solve(pressure_kpa=20)["coefficients"]
    cases = [
        (lambda: fpc.Finger(eps0="0.3"), "eps0"),
        (lambda: fpc.Finger(ribs=1), "ribs"),
        (lambda: fpc.Finger(model=1), "model"),
        (lambda: f.solve(pressure_kpa=np.array([5.0, 6.0])), "pressure_kpa"),
        (lambda: f.solve(shape=1), "shape"),
        (lambda: f.solve(kappa="x"), "kappa"),
        (lambda: gripper.grasp_size("x"), "d_mm"),
        (lambda: gripper.grasp_cuboid(friction_n=[0.3]), "friction_n"),
        (lambda: gripper.grasp_sphere(lift_n="x"), "lift_n"),
        (lambda: gripper.sweep(3), "kind"),
        (lambda: fpc.Gripper(mu="x"), "mu"),
        (lambda: fpc.Gripper("x"), "finger"),
        (lambda: fpc.Gripper(stability="yes"), "stability"),
        (lambda: fpc.batch_solve(threads="x"), "threads"),
        (lambda: fpc.batch_solve(warm_start=1), "warm_start"),
        (lambda: fpc.run_study(1, mu="x"), "mu"),
        (lambda: fpc.run_study(1, coarse="x"), "coarse"),
        (lambda: fpc.solve_scene("", name=3), "name"),
        # strings are not numbers, in an array argument either
        (lambda: f.solve(guess="abc"), "guess"),
        (lambda: gripper.sweep("size", d_mm="100"), "d_mm"),
        (lambda: gripper.sweep("size", d_mm=["a"]), "d_mm"),
        (lambda: gripper.sweep("cuboid", friction_n=[{}]), "friction_n"),
        (lambda: fpc.batch_solve(eps0="0.3"), "eps0"),
        (lambda: fpc.batch_solve(pressure_kpa=[b"1"]), "pressure_kpa"),
        (lambda: fpc.run_study(7.0), "study"),
        (lambda: fpc.run_study(True), "study"),
        # an actuator keyword of one value is an argument like any other
        (lambda: fpc.Finger(plane_strain="yes"), "plane_strain"),
        (lambda: fpc.Finger(plane_strain=1), "plane_strain"),
        (lambda: fpc.Finger(shear_correction="x"), "shear_correction"),
        (lambda: fpc.Finger(lx="100"), "lx"),
        (lambda: fpc.batch_solve(h1="9"), "h1"),
    ]
    for call, name in cases:
        conversion_error(call, TypeError, name)
    # a coefficient array of the wrong dimensionality is refused by name
    named_input_error(lambda: f.solve(guess=c[None]), "guess", "guess: has 3 dimensions")


def test_an_int_that_does_not_fit_names_the_argument():
    f = fpc.Finger()
    conversion_error(lambda: f.solve(fx=10**400), OverflowError, "fx")
    conversion_error(lambda: fpc.Gripper(fingers=-1), OverflowError, "fingers")
    conversion_error(lambda: fpc.batch_solve(threads=-1), OverflowError, "threads")
    conversion_error(lambda: fpc.run_study(1, sweep_points=-1), OverflowError, "sweep_points")
    # as the README says: an int that does not fit a count is an OverflowError
    conversion_error(lambda: fpc.Finger(elements=10**30), OverflowError, "elements")


def test_the_documented_defaults_stay_visible_and_none_takes_them(gripper):
    import inspect

    assert "model='ccm', ribs=True" in str(inspect.signature(fpc.Finger))
    assert "pressure_kpa=0.0" in str(inspect.signature(fpc.Gripper.grasp_cuboid))
    assert "warm_start=False" in str(inspect.signature(fpc.batch_solve))
    a = gripper.grasp_cuboid(d_mm=None)
    b = gripper.grasp_cuboid()
    assert a["normal_force_n"] == b["normal_force_n"]


def test_a_sweep_converts_its_inputs_as_batch_solve_does(gripper):
    # a string is a wrong type, never parsed as a number
    sweep = conversion_error(lambda: gripper.sweep("size", d_mm="100"), TypeError, "d_mm")
    batch = conversion_error(
        lambda: fpc.batch_solve(pressure_kpa="100"), TypeError, "pressure_kpa"
    )
    assert str(sweep).replace("d_mm", "pressure_kpa") == str(batch)
    # a list numpy cannot make an array of is a value error naming it
    ragged = [[90.0], [90.0, 100.0]]
    named_input_error(
        lambda: gripper.sweep("size", d_mm=ragged), "d_mm", "d_mm: not an array of numbers"
    )
    named_input_error(lambda: fpc.batch_solve(fx=ragged), "fx", "fx: not an array of numbers")
    named_input_error(
        lambda: fpc.Finger().solve(guess=ragged), "guess", "guess: not an array of numbers"
    )
    # numbers of any numeric type are numbers
    ints = {"pressure_kpa": np.array([20, 10], dtype=np.int16), "kappa": np.uint8([2, 3])}
    a = fpc.batch_solve(eps0=[0.35, 0.1], fz=[False, True], **ints)
    floats = {"pressure_kpa": [20.0, 10.0], "kappa": [2.0, 3.0]}
    b = fpc.batch_solve(eps0=[0.35, 0.1], fz=[0.0, 1.0], **floats)
    assert (a["status"] == 0).all(), a["error"]
    np.testing.assert_array_equal(a["tip"], b["tip"])
    named_input_error(
        lambda: gripper.sweep("cuboid", d_mm=[90.0, 100.0], friction_n=[0.1, 0.2, 0.3]),
        "d_mm",
        "d_mm, friction_n, pressure_kpa: shapes do not broadcast",
    )
    with pytest.raises(TypeError, match="complex"):
        gripper.sweep("size", d_mm=[1j])


def test_a_mistyped_keyword_lists_the_functions_own_options_and_the_nearest():
    with pytest.raises(TypeError) as e:
        fpc.run_study(7, sweep_point=3)
    m = str(e.value)
    assert "unexpected keyword argument 'sweep_point'" in m, m
    assert "did you mean 'sweep_points'?" in m, m
    assert "pressure_points" in m and "h1" in m, m
    with pytest.raises(TypeError) as e:
        fpc.batch_solve(warmstart=True)
    m = str(e.value)
    assert "did you mean 'warm_start'?" in m and "threads" in m, m
    # nothing near: no guess, but still every keyword
    with pytest.raises(TypeError) as e:
        fpc.Finger(zzzzzzzzzz=1)
    m = str(e.value)
    assert "did you mean" not in m and "elements" in m and "rib_layout" in m, m


def test_rib_lists_are_bounded_by_their_length_before_conversion():
    rib = {"x0": 1.0, "x1": 2.0, "width": 1.0}
    named_input_error(
        lambda: fpc.Finger(rib_layout={"kind": "list", "list": [rib] * 10001}),
        "actuator.ribs",
        "actuator.ribs = 10001: lists 10001 ribs, more than 10000",
    )
    cl = {"x0": 1.0, "x1": 2.0, "width": 0.001, "height": 0.1}
    named_input_error(
        lambda: fpc.Finger(cl_ribs=[cl] * 10001), "actuator.cl_ribs", "actuator.cl_ribs = 10001"
    )
    # the length is checked before any entry is converted: entries that
    # would not convert are never looked at
    for kw in (
        {"cl_ribs": [object()] * 300_000},
        {"cl_ribs": {"list": [object()] * 300_000}},
        {"rib_layout": {"kind": "list", "list": [object()] * 300_000}},
    ):
        with pytest.raises(fpc.InputError, match="lists 300000 ribs"):
            fpc.Finger(**kw)


def test_a_rule_between_two_keys_names_the_one_given():
    # lx given, cx left at its default (105 mm): the error is on lx, and
    # quotes the default it conflicts with
    with pytest.raises(fpc.InputError) as e:
        fpc.Finger(lx=50)
    assert e.value.field == "actuator.geometry.lx"
    assert str(e.value).startswith(
        "actuator.geometry.lx = 50: conflicts with the default of a key not given "
        "(actuator.channel.cx = 105: "
    ), str(e.value)
    # both given: the rule's own key, as before
    with pytest.raises(fpc.InputError) as e:
        fpc.Finger(lx=50, cx=60)
    assert e.value.field == "actuator.channel.cx"
    assert "default" not in str(e.value)

"""Every rejected argument is named in the words the caller used: the
keyword as written, in its own unit, whatever the call (a single solve, a
grasp, a sweep, a batch, a study)."""


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


def test_a_sweep_reports_the_pressure_in_kpa(gripper):
    s = gripper.sweep("cuboid", pressure_kpa=[-500])
    assert not s["ok"][0]
    assert s["error"][0].startswith("pressure_kpa = -500"), s["error"][0]

"""`fpc.design`: the optimiser's claim holds when its scenes are re-solved
through the ordinary scene path, infeasible requirements say what fails,
and bad requirements raise the documented errors."""

import pytest

import fpc

CUBOID = """
[[object]]
kind = "cuboid"
size_mm = [70.0, 100.0]
lift_n = 0.6
[vary]
eps0 = [0.1, 0.45]
"""


def test_a_feasible_design_and_its_scenes_reproduce_the_grasps():
    d = fpc.design(CUBOID, starts=0)
    assert d["feasible"] is True
    design = d["best"]["design"]
    eps0, angle, overlap = design["eps0"], design["mounting_angle_deg"], design["overlap_mm"]
    assert 0.1 <= eps0 <= 0.45
    # only eps0 is varied: the other variables stay at the paper's defaults
    assert (angle, overlap) == (60.0, 20.0)
    margins = d["best"]["margins"]
    assert margins and all(m["margin"] >= 0 for m in margins)
    assert d["best"]["worst"] == min(m["margin"] for m in margins)
    assert d["scenes"], d.keys()
    for s in d["scenes"]:
        # each scene holds its object at the design: re-solved independently
        solved = fpc.solve_scene(s["toml"], name=s["name"])
        assert solved["grasp"]["valid"], (s["name"], solved["grasp"])
        assert solved["scene"]["actuator"]["pemc"]["eps0"] == pytest.approx(eps0, rel=1e-12)
    # the library's own re-solve of each scene, with the notes it reports
    assert [r["file"] for r in d["reproductions"]] == [s["name"] for s in d["scenes"]]
    for r in d["reproductions"]:
        assert r["reproduced"] and r["valid"], r
        assert isinstance(r["notes"], list), r


def test_infeasible_requirements_name_the_failing_one():
    d = fpc.design(CUBOID.replace("lift_n = 0.6", "lift_n = 50.0"), starts=0)
    assert d["feasible"] is False
    worst = min(d["best"]["margins"], key=lambda m: m["margin"])
    assert worst["margin"] < 0 and "object[0]" in worst["requirement"]


def test_bad_requirements_raise_the_documented_errors(tmp_path):
    with pytest.raises(fpc.SceneError) as e:
        fpc.design(CUBOID + "colour = 3\n")
    assert e.value.line == 8 and "colour" in str(e.value)
    p = tmp_path / "req.toml"
    p.write_text(CUBOID.replace("lift_n = 0.6", "lift_n = -1.0"))
    with pytest.raises(fpc.InputError) as e:
        fpc.design(p)
    assert "lift_n" in e.value.field
    # bounded before any work: 10**8 starts would run for days
    with pytest.raises(fpc.InputError) as e:
        fpc.design(CUBOID, starts=10**8)
    assert e.value.field == "design.random_starts"

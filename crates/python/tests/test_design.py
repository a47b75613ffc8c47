"""`fpc.design`: the optimiser's claim holds when its scenes are re-solved
through the ordinary scene path, infeasible requirements say what fails,
and bad requirements raise the documented errors."""

import json
import subprocess

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
    # located where the file writes the value
    lines = p.read_text().splitlines()
    at = next(i for i, l in enumerate(lines) if "lift_n = -1.0" in l)
    assert (e.value.line, e.value.col) == (at + 1, lines[at].index("-1.0") + 1)
    # bounded before any work: 10**8 starts would run for days
    with pytest.raises(fpc.InputError) as e:
        fpc.design(CUBOID, starts=10**8)
    assert e.value.field == "design.random_starts"


SCENE = "[actuator.cl]\ne = 350.0\n[actuator.pemc]\neps0 = 0.3\n"
ANGLE = CUBOID.replace("eps0 = [0.1, 0.45]", "mounting_angle_deg = [60.0, 80.0]")


def test_a_design_from_a_scene_uses_its_finger():
    scene, angle = SCENE, ANGLE
    d = fpc.design(angle, starts=0, scene=scene)
    assert d["best"]["design"]["eps0"] == 0.3
    assert any("the finger is the scene" in n for n in d["notes"]), d["notes"]
    for s in d["scenes"]:
        solved = fpc.solve_scene(s["toml"], name=s["name"])
        assert solved["scene"]["actuator"]["cl"]["e"] == 350.0
    # a scene with an unknown key raises SceneError with its line
    with pytest.raises(fpc.SceneError) as e:
        fpc.design(angle, scene="[actuator.pemc]\neps00 = 0.3\n")
    assert e.value.line == 2


def test_a_design_from_a_scene_is_fpc_design_scenes(tmp_path, fpc_bin):
    scene, angle = SCENE, ANGLE
    d = fpc.design(angle, starts=0, scene=scene)
    (tmp_path / "req.toml").write_text(angle)
    (tmp_path / "finger.toml").write_text(scene)
    out = subprocess.run(
        [fpc_bin, "design", str(tmp_path / "req.toml"), "--scene", str(tmp_path / "finger.toml"),
         "--starts", "0", "--json", "--out", str(tmp_path / "out")],
        capture_output=True, text=True, check=True,
    )
    cli = json.loads(out.stdout)
    assert cli["design"]["mounting_angle_deg"] == d["best"]["design"]["mounting_angle_deg"]
    assert cli["worst_margin"] == d["best"]["worst"]

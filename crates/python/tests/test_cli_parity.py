"""Python results equal the CLI's JSON for the same scenes and flags
(to 1e-12): `fpc solve SCENE --out DIR` (solution.json) and
`fpc finger --json ...`. Needs FPC_BIN (see conftest.py)."""

import json

import numpy as np
import pytest

import fpc
from conftest import SCENES, assert_same, cli_json, run_cli

assert SCENES, "the repository's scenes/ directory has scene files"


def solution_json(fpc_bin, scene, tmp_path):
    out = tmp_path / scene.stem
    run_cli(fpc_bin, "solve", scene, "--out", out)
    return json.loads((out / "solution.json").read_text())


@pytest.mark.parametrize("scene", SCENES, ids=lambda p: p.stem)
def test_solve_scene_equals_solution_json(fpc_bin, scene, tmp_path):
    want = solution_json(fpc_bin, scene, tmp_path)
    # how the file was made (fpc version, git commit, command line) is the
    # CLI's record, not part of the result
    assert set(want.pop("provenance")) >= {"fpc_version", "command"}
    got = fpc.solve_scene(scene)
    # every key, every value: the arrays as numpy arrays of the right shape
    assert_same(got, want)
    assert got["tip_mm"].shape == (2,)
    assert got["coefficients"].shape == (want["elements"], len(want["coefficients"][0]))
    assert got["points_mm"].shape == (len(want["points_mm"]), 2)
    # the text of the scene gives the same answer (named "scene")
    text = fpc.solve_scene(scene.read_text())
    assert text["scene_name"] == "scene"
    np.testing.assert_array_equal(text["coefficients"], got["coefficients"])


@pytest.mark.parametrize(
    "scene", [s for s in SCENES if "[gripper]" not in s.read_text()], ids=lambda p: p.stem
)
def test_finger_from_scene_equals_solution_json(fpc_bin, scene, tmp_path):
    want = solution_json(fpc_bin, scene, tmp_path)
    got = fpc.Finger.from_scene(scene).solve()
    assert_same(got["tip"], want["tip_mm"])
    assert_same(got["end_angle"], want["end_angle_rad"])
    assert_same(got["energy"], want["energy_nmm"])
    assert_same(got["coefficients"], want["coefficients"])
    assert_same(got["points"], want["points_mm"])
    assert_same(got["element_lengths"], want["element_lengths_mm"])
    assert_same(got["warnings"], want["warnings"])
    assert_same(got["report"], want["report"])
    assert_same(got["tip_error_estimate"], want["tip_error_estimate_mm"])
    assert got["valid"] == want["validity"]
    assert got["elements"] == want["elements"]


@pytest.mark.parametrize(
    "scene", [s for s in SCENES if "[gripper.grasp]" in s.read_text()], ids=lambda p: p.stem
)
def test_gripper_from_scene_equals_solution_json(fpc_bin, scene, tmp_path):
    want = solution_json(fpc_bin, scene, tmp_path)
    g = fpc.Gripper.from_scene(scene)
    got = g.solve()
    extra = {"solution", "points_gripper", "warnings", "reversed"}
    assert_same({k: v for k, v in got.items() if k not in extra}, want["grasp"])
    assert_same(got["solution"]["tip"], want["tip_mm"])
    assert_same(got["solution"]["coefficients"], want["coefficients"])
    assert_same(got["points_gripper"], want["points_gripper_mm"])
    assert_same(g.info(), want["gripper"])


# (flags of `fpc finger`, Finger(...) keywords, solve(...) keywords)
FINGER_CASES = [
    ([], {}, {}),
    (["--eps0", "0.4", "--pressure-kpa", "100"], {"eps0": 0.4}, {"pressure_kpa": 100}),
    (["--fx", "0.5", "--fz", "0.2", "--elements", "16"], {"elements": 16}, {"fx": 0.5, "fz": 0.2}),
    (
        ["--no-ribs", "--kappa", "1", "--pressure-kpa", "30", "--eps0", "0.15"],
        {"ribs": False, "eps0": 0.15},
        {"kappa": 1.0, "pressure_kpa": 30},
    ),
    (["--elements", "auto", "--pressure-kpa", "100"], {"elements": "auto"}, {"pressure_kpa": 100}),
    (["--tip-tol-mm", "0.1", "--fx", "0.3"], {}, {"tip_tol_mm": 0.1, "fx": 0.3}),
    (
        ["--tip-tol-mm", "0.5", "--elements", "4", "--fz", "-0.2"],
        {"elements": 4},
        {"tip_tol_mm": 0.5, "fz": -0.2},
    ),
    (["--model", "quad", "--fx", "0.2", "--elements", "6"], {"model": "quad", "elements": 6}, {"fx": 0.2}),
    (["--eps0", "0.7", "--elements", "2", "--pressure-kpa", "60"], {"eps0": 0.7, "elements": 2}, {"pressure_kpa": 60}),
]


@pytest.mark.parametrize("flags,finger,load", FINGER_CASES, ids=lambda c: " ".join(c) if isinstance(c, list) else None)
def test_finger_equals_fpc_finger_json(fpc_bin, flags, finger, load):
    want = cli_json(fpc_bin, "finger", "--json", *flags)
    got = fpc.Finger(**finger).solve(**load)
    pairs = {
        "tip": "tip_mm",
        "end_angle": "end_angle_rad",
        "radius": "radius_mm",
        "energy": "energy_nmm",
        "negative_eigenvalues": "negative_eigenvalues",
        "stable": "stable",
        "coefficients": "coefficients",
        "points": "points_mm",
        "element_lengths": "element_lengths_mm",
        "warnings": "warnings",
        "report": "report",
        "elements": "elements",
        "model": "model",
        "tip_error_estimate": "tip_error_estimate_mm",
    }
    for ours, theirs in pairs.items():
        assert_same(got[ours], want[theirs], ours)
    if "refinement" in want:
        r, w = got["refinement"], want["refinement"]
        assert_same(
            {**r, "tip_mm": r["tip"], "end_angle_rad": r["end_angle"], "level_tips_mm": r["level_tips"]},
            {**w, "tip": w["tip_mm"], "end_angle": w["end_angle_rad"], "level_tips": w["level_tips_mm"]},
        )
    else:
        assert got["refinement"] is None

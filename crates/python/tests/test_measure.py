"""fpc.compare: the model against a lab's measurements (no fitting), the
same numbers as `fpc compare --json`, its arrays consistent with its
records, and bad input as Python's own errors."""

import copy
import json
import math
import os
import pathlib
import shutil

import numpy as np
import pytest

import fpc
from conftest import REPO, assert_same, cli_json, run_cli

MANIFEST = REPO / "examples" / "calibration" / "manifest.toml"


def test_compare_matches_the_cli(fpc_bin, tmp_path):
    c = fpc.compare(MANIFEST)
    cli = cli_json(fpc_bin, "compare", MANIFEST, "--out", tmp_path, "--json")
    for k in ("figures", "provenance"):
        cli.pop(k)
    plain = copy.deepcopy(c)
    for s in plain["specimens"]:
        for t in s["tests"]:
            t.pop("arrays")
    assert_same(plain, cli)


def test_arrays_hold_every_residual_in_file_order():
    c = fpc.compare(os.fspath(MANIFEST))
    total = 0.0
    points = 0
    for s in c["specimens"]:
        for t in s["tests"]:
            a = t["arrays"]
            rows = [(p, r) for p in t["predictions"] for r in p["residuals"]]
            assert len(a["quantity"]) == len(rows) > 0
            for name in ("pressure_kpa", "measured", "sd", "predicted", "residual", "residual_sd"):
                assert a[name].shape == (len(rows),), name
            assert a["quantity"] == [r["quantity"] for _, r in rows]
            assert np.array_equal(a["pressure_kpa"], [p["pressure_kpa"] for p, _ in rows])
            ok = ~np.isnan(a["predicted"])
            # residuals are measured - predicted, in units and in sd
            np.testing.assert_allclose(
                a["residual"][ok], a["measured"][ok] - a["predicted"][ok], rtol=0, atol=1e-12
            )
            np.testing.assert_allclose(
                a["residual_sd"][ok], a["residual"][ok] / a["sd"][ok], rtol=1e-14
            )
            total += float(np.sum(a["residual_sd"][ok] ** 2))
            points += int(ok.sum())
    # the chi-square is the sum of the squared residuals in sd
    assert math.isclose(c["chi_square"], total, rel_tol=1e-12)
    assert c["points"] == points
    # synthetic data from the model with Gaussian noise: about one per point
    assert 0.5 * points < c["chi_square"] < 2.0 * points


def test_bad_measurements_name_file_line_column_and_field(tmp_path):
    d = tmp_path / "set"
    shutil.copytree(MANIFEST.parent, d)
    csv = d / "eps0-0.4_radius.csv"
    lines = csv.read_text().splitlines()
    # the third data row's sd becomes negative
    header = next(i for i, l in enumerate(lines) if l.startswith("pressure_kpa"))
    row = header + 3
    cells = lines[row].split(",")
    cells[2] = "-1"
    lines[row] = ",".join(cells)
    csv.write_text("\n".join(lines) + "\n")
    with pytest.raises(fpc.MeasureError) as e:
        fpc.compare(d / "manifest.toml")
    assert isinstance(e.value, ValueError)
    assert e.value.file.endswith("eps0-0.4_radius.csv")
    assert e.value.line == row + 1
    assert e.value.col == 3
    assert e.value.field == "sd_mm"


def test_a_missing_manifest_is_file_not_found(tmp_path):
    with pytest.raises(FileNotFoundError) as e:
        fpc.compare(tmp_path / "nothing.toml")
    assert e.value.filename.endswith("nothing.toml")
    with pytest.raises(TypeError):
        fpc.compare(3)


TRUTH = {
    "actuator.pemc.eps0[eps0-0.15]": 0.15,
    "actuator.pemc.eps0[eps0-0.25]": 0.25,
    "actuator.pemc.eps0[eps0-0.4]": 0.4,
    "load.kappa": 2.5,
}


def test_calibrate_recovers_the_synthetic_truth_and_matches_the_cli(fpc_bin, tmp_path):
    c = fpc.calibrate(MANIFEST, "eps0,kappa")
    names = [p["name"] for p in c["parameters"]]
    assert sorted(names) == sorted(TRUTH)
    # the truth the data were made with (examples/calibration/README.md)
    for p, v, se in zip(c["parameters"], c["values"], c["standard_errors"]):
        assert v == p["value"] and se == p["standard_error"]
        assert abs(v - TRUTH[p["name"]]) < 3 * se, p
    cov, corr = c["covariance"], c["correlation"]
    assert cov.shape == corr.shape == (4, 4)
    np.testing.assert_allclose(cov, cov.T, rtol=0, atol=1e-15 * np.abs(cov).max())
    np.testing.assert_allclose(np.sqrt(np.diag(cov)), c["standard_errors"], rtol=1e-12)
    np.testing.assert_allclose(np.diag(corr), 1.0, rtol=1e-12)
    assert c["identifiability"]["verdict"] == "identifiable"
    # checked through fpc compare's path before it was reported
    r = c["reproduction"]
    assert r["reproduced"] is True and r["largest_difference_sd"] <= 1e-6, r
    assert r["chi_square"] == pytest.approx(c["chi_square"], rel=1e-9)
    # the CLI's calibration.json: the same fit
    cli = cli_json(fpc_bin, "calibrate", MANIFEST, "--fit", "eps0,kappa", "--out", tmp_path, "--json")
    for k in ("scenes", "provenance"):
        cli.pop(k)
    plain = {k: v for k, v in c.items() if k in cli}
    assert set(plain) == set(cli), set(cli) ^ set(plain)
    assert_same(plain, cli, tol=1e-9)
    # each calibrated scene solves with its specimen's fitted prestrain
    assert [s["name"] for s in c["scenes"]] == ["eps0-0.15", "eps0-0.25", "eps0-0.4"]
    for s in c["scenes"]:
        solved = fpc.solve_scene(s["toml"], name=s["name"])
        fitted = c["values"][names.index(f"actuator.pemc.eps0[{s['name']}]")]
        assert solved["scene"]["actuator"]["pemc"]["eps0"] == pytest.approx(fitted, rel=1e-12)


def test_calibrate_refuses_bad_options_by_name():
    with pytest.raises(fpc.InputError) as e:
        fpc.calibrate(MANIFEST, [])
    assert e.value.field == "fit"
    with pytest.raises(fpc.InputError) as e:
        fpc.calibrate(MANIFEST, ["eps0"], max_iterations=0)
    assert e.value.field == "max_iterations"
    with pytest.raises(fpc.InputError) as e:
        fpc.calibrate(MANIFEST, ["eps0"], max_iterations=10**6)
    assert e.value.field == "max_iterations"
    with pytest.raises(TypeError):
        fpc.calibrate(MANIFEST, 3)
    with pytest.raises(FileNotFoundError):
        fpc.calibrate(MANIFEST.parent / "missing.toml", "eps0")


def test_a_calibrated_scene_carries_its_error_bars_as_fpc_solve_does(fpc_bin, tmp_path):
    c = fpc.calibrate(MANIFEST, "eps0,kappa")
    s = c["scenes"][-1]
    scene = tmp_path / f"{s['name']}.toml"
    scene.write_text(s["toml"])
    solved = fpc.solve_scene(scene)
    u = solved["uncertainty"]
    assert u["method"] == "first_order"
    assert len(u["tip_mm"]) == 2 and all(x > 0 for x in u["tip_mm"]), u
    assert u["radius_mm"] > 0, u
    run_cli(fpc_bin, "solve", scene, "--out", tmp_path / "out")
    cli = json.loads((tmp_path / "out" / "solution.json").read_text())
    assert_same(u, cli["uncertainty"], tol=1e-9)


def test_choose_model_ranks_the_candidates_as_the_cli_does(fpc_bin, tmp_path):
    # one specimen's radii from the shipped set: a small fit
    shutil.copy(MANIFEST.parent / "eps0-0.4_radius.csv", tmp_path / "radius.csv")
    m = tmp_path / "manifest.toml"
    m.write_text(
        '[[specimen]]\nname = "a"\n[specimen.own.actuator.pemc]\neps0 = 0.38\n'
        '[[specimen.test]]\nkind = "radius"\nfile = "radius.csv"\n'
    )
    c = fpc.calibrate(m, ["eps0"], choose_model=True)
    choice = c["model_choice"]
    # with and without ribs, in plane stress and in plane strain
    assert len(choice["candidates"]) == 4 * len(fpc.models())
    assert {k["plane_strain"] for k in choice["candidates"]} == {False, True}
    errs = [k["held_out_rms_sd"] for k in choice["candidates"]]
    assert errs[choice["best"]] == min(errs)
    cli = cli_json(fpc_bin, "calibrate", m, "--fit", "eps0", "--choose-model", "--json",
                   "--out", tmp_path / "out")
    assert_same(choice, cli["model_choice"], tol=1e-9)
    assert "model_choice" not in fpc.calibrate(m, ["eps0"])

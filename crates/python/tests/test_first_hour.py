"""A newcomer's first hour: a path that does not exist is FileNotFoundError,
results are named, unknown or conflicting arguments are errors, every
count is bounded before any work, Ctrl-C stops long calls, and the bench
script fails in one line."""

import os
import pathlib
import subprocess
import sys
import textwrap
import time

import numpy as np
import pytest

import fpc

from conftest import REPO, cli_json

HERE = pathlib.Path(__file__).resolve().parent

CUBOID = """
[[object]]
kind = "cuboid"
size_mm = [70.0, 100.0]
lift_n = 0.6
[vary]
eps0 = [0.1, 0.45]
"""

# ------------------------------------------------ 1. paths that do not exist


# every call that reads a scene or requirements file
scene_calls = pytest.mark.parametrize(
    "call",
    [
        fpc.Finger.from_scene,
        fpc.solve_scene,
        fpc.Gripper.from_scene,
        fpc.design,
    ],
    ids=["Finger.from_scene", "solve_scene", "Gripper.from_scene", "design"],
)


@scene_calls
@pytest.mark.parametrize(
    "missing", ["pressurised.toml", "no/such/dir/scene", "scenes/nope.TOML"]
)
def test_a_missing_path_is_file_not_found_naming_it(call, missing):
    with pytest.raises(FileNotFoundError) as e:
        call(missing)
    assert missing in str(e.value)
    assert e.value.filename == missing


def test_a_missing_pathlike_is_file_not_found(tmp_path):
    p = tmp_path / "absent.toml"
    with pytest.raises(FileNotFoundError) as e:
        fpc.Finger.from_scene(p)
    assert str(p) in str(e.value)


def test_existing_paths_and_one_line_text_still_work(tmp_path):
    scene = (REPO / "scenes" / "pressurised.toml").read_text()
    by_text = fpc.Finger.from_scene(scene)
    by_path = fpc.Finger.from_scene(str(REPO / "scenes" / "pressurised.toml"))
    assert by_text.eps0 == by_path.eps0 == 0.4
    # a one-line TOML document whose value looks like a path stays text
    f = fpc.Finger.from_scene("actuator.pemc.eps0 = 0.3  # as in a/b.toml")
    assert f.eps0 == 0.3
    # a file without the .toml suffix is read when it exists
    p = tmp_path / "scene"
    p.write_text(scene)
    assert fpc.Finger.from_scene(str(p)).eps0 == 0.4


@scene_calls
def test_a_file_beyond_the_scene_limit_is_refused_naming_it_and_the_limit(call, tmp_path):
    # one byte over 4 MiB, as `fpc solve` refuses it
    big = tmp_path / "big.toml"
    big.write_text("#" * (4 * 1024 * 1024) + "\n")
    with pytest.raises(OSError) as e:
        call(big)
    assert type(e.value) is OSError, type(e.value)
    assert e.value.filename == str(big)
    assert str(big) in str(e.value)
    assert "larger than 4 MiB (4194304 bytes), the limit for a scene file" in str(e.value)
    # a device that never ends is refused the same way, not read whole
    for device in ["/dev/zero", "/dev/urandom"]:
        if os.path.exists(device):
            with pytest.raises(OSError, match="larger than 4 MiB") as e:
                call(device)
            assert e.value.filename == device


def test_a_file_at_the_scene_limit_is_read(tmp_path):
    p = tmp_path / "at_limit.toml"
    p.write_text("actuator.pemc.eps0 = 0.3\n" + "#" * (4 * 1024 * 1024 - 26) + "\n")
    assert p.stat().st_size == 4 * 1024 * 1024
    assert fpc.Finger.from_scene(p).eps0 == 0.3


@scene_calls
def test_a_directory_or_bad_text_is_an_os_error_naming_the_path(call, tmp_path):
    with pytest.raises(IsADirectoryError) as e:
        call(tmp_path)
    assert e.value.filename == str(tmp_path)
    assert str(tmp_path) in str(e.value)
    bad = tmp_path / "bad.toml"
    bad.write_bytes(b"a = 1\n\xff")
    with pytest.raises(OSError, match="not UTF-8 text") as e:
        call(bad)
    assert e.value.filename == str(bad)


# ------------------------------------------------ 2. named results


def test_design_best_design_has_design_json_keys(fpc_bin, tmp_path):
    req = tmp_path / "req.toml"
    req.write_text(CUBOID)
    d = fpc.design(req, starts=0)
    j = cli_json(fpc_bin, "design", req, "--starts", 0, "--json", "--out", tmp_path / "out")
    design = d["best"]["design"]
    assert isinstance(design, dict)
    assert set(design) == set(j["design"]), (design, j["design"])
    for k, v in j["design"].items():
        if isinstance(v, float):
            assert design[k] == pytest.approx(v, rel=1e-12), k
        else:
            assert design[k] == v, k
    assert design["varied"] == ["eps0"]
    # the sensitivities name the variable each derivative is taken by
    for s in d["sensitivities"]:
        assert set(s["gradient"]) == {"eps0", "mounting_angle_deg", "overlap_mm"}
    by_req = {s["requirement"]: s["gradient"] for s in d["sensitivities"]}
    for s in j["sensitivities"]:
        g = by_req[s["requirement"]]
        # design.json names them too
        assert set(s["gradient"]) == {"eps0", "mounting_angle_deg", "overlap_mm"}
        for name, v in s["gradient"].items():
            assert g[name] == pytest.approx(v, rel=1e-9, abs=1e-12), (s["requirement"], name)


# ------------------------------------------------ 3. unknown and conflicting arguments


@pytest.mark.parametrize(
    "study,kw",
    [
        (7, {"sweep_points": 40}),
        (7, {"angle_samples": 8}),
        (7, {"mu": 0.5}),
        (8, {"strict": True}),
        (1, {"pressure_points": 5}),
        (4, {"sweep_points": 40}),
        (6, {"sweep_points": 40}),
    ],
)
def test_an_option_the_study_does_not_use_is_a_type_error(study, kw):
    with pytest.raises(TypeError) as e:
        fpc.run_study(study, coarse=True, **kw)
    assert next(iter(kw)) in str(e.value)


def test_an_option_the_study_uses_is_accepted_and_changes_it():
    a = fpc.run_study(7, coarse=True, pressure_points=3)
    b = fpc.run_study(7, coarse=True, pressure_points=5)
    assert a["points"] != b["points"]


def test_eps0_given_twice_is_a_type_error():
    with pytest.raises(TypeError) as e:
        fpc.Finger(eps0=0.3, pemc={"eps0": 0.4})
    assert "eps0" in str(e.value)
    with pytest.raises(TypeError) as e:
        fpc.Finger(h1=1.0, geometry={"h1": 1.2})
    assert "h1" in str(e.value)
    with pytest.raises(TypeError):
        fpc.batch_solve(lx=100.0, geometry={"lx": 90.0})


def test_a_prestrain_the_call_would_ignore_is_a_type_error():
    # batch_solve's points and each study set the prestrain themselves
    with pytest.raises(TypeError) as e:
        fpc.batch_solve(pemc={"eps0": 0.4})
    assert "eps0" in str(e.value)
    with pytest.raises(TypeError) as e:
        fpc.run_study(7, coarse=True, pemc={"eps0": 0.4})
    assert "eps0" in str(e.value)


def test_eps0_in_pemc_alone_is_used():
    assert fpc.Finger(pemc={"eps0": 0.4}).eps0 == 0.4
    assert fpc.Finger().eps0 == 0.25


def test_unknown_keywords_are_type_errors():
    for call in (
        lambda: fpc.Finger(colour=1),
        lambda: fpc.run_study(7, colour=1),
        lambda: fpc.batch_solve(colour=1),
        lambda: fpc.design(CUBOID, colour=1),
        lambda: fpc.Finger().solve(colour=1),
        lambda: fpc.Gripper().sweep("size", colour=1),
    ):
        with pytest.raises(TypeError):
            call()


@pytest.mark.parametrize(
    "call",
    [
        lambda: fpc.batch_solve(pressure_kpa=np.array([1.0 + 2.0j])),
        lambda: fpc.batch_solve(eps0=0.25 + 0j),
        lambda: fpc.batch_solve(fx=[0.1, 1j]),
        lambda: fpc.Gripper().sweep("size", d_mm=np.array([90 + 1j])),
        lambda: fpc.Finger(elements=2).solve(
            guess=np.zeros((2, len(fpc.Finger().unknowns)), dtype=complex)
        ),
    ],
    ids=["batch array", "batch scalar", "batch list", "sweep", "guess"],
)
def test_complex_arrays_are_refused(call):
    with pytest.raises(TypeError) as e:
        call()
    assert "complex" in str(e.value)


# ------------------------------------------------ 4. bounded work


@pytest.mark.parametrize(
    "study,kw,field",
    [
        (1, {"sweep_points": 10**12}, "study.sweep_points"),
        (5, {"angle_samples": 10**9}, "study.angle_samples"),
        (5, {"angle_samples": 200, "sweep_points": 2000}, "study.sweep_points"),
        (7, {"pressure_points": 10**12}, "study.pressure_points"),
    ],
)
def test_study_counts_are_bounded_before_any_work(study, kw, field):
    t = time.perf_counter()
    with pytest.raises(fpc.InputError) as e:
        fpc.run_study(study, **kw)
    assert e.value.field == field
    assert time.perf_counter() - t < 5


def test_batch_and_sweep_sizes_are_bounded_before_any_allocation():
    t = time.perf_counter()
    with pytest.raises(fpc.InputError) as e:
        # 10**10 points if broadcast: refused from the shapes alone
        fpc.batch_solve(pressure_kpa=np.zeros((100_000, 1)), fx=np.zeros((1, 100_000)))
    assert e.value.field == "points"
    with pytest.raises(fpc.InputError) as e:
        fpc.batch_solve(threads=10**6)
    assert e.value.field == "threads"
    with pytest.raises(fpc.InputError) as e:
        fpc.Gripper().sweep("size", d_mm=np.zeros((1000, 1)), beta_deg=np.zeros(1000))
    assert e.value.field == "points"
    assert time.perf_counter() - t < 5


def test_huge_and_negative_counts_are_clean_errors():
    for kw in ({"sweep_points": 10**30}, {"sweep_points": -1}, {"elements": 10**18}):
        with pytest.raises((ValueError, OverflowError, TypeError)):
            fpc.run_study(1, **kw)
    with pytest.raises((ValueError, OverflowError)):
        fpc.design(CUBOID, starts=10**30)


# ------------------------------------------------ 5. Ctrl-C


def _interrupted(code, after_s=1.0, timeout=120):
    """Runs `code` in a fresh interpreter that gets SIGINT `after_s` into
    it. Prints "INTERRUPTED", the seconds from the signal to
    KeyboardInterrupt, and the CPU seconds the process spends in the next
    second (about 1 or more while an abandoned computation still runs).
    The interpreter raises KeyboardInterrupt on SIGINT whatever it
    inherited: a test run started in the background of a non-interactive
    shell inherits SIGINT ignored, and Python then keeps it ignored."""
    script = textwrap.dedent(
        f"""
        import os, signal, threading, time
        signal.signal(signal.SIGINT, signal.default_int_handler)
        import numpy as np
        import fpc
        t = {{}}
        def fire():
            t["sent"] = time.perf_counter()
            os.kill(os.getpid(), signal.SIGINT)
        threading.Timer({after_s}, fire).start()
        try:
            {code}
            print("FINISHED")
        except KeyboardInterrupt:
            latency = time.perf_counter() - t["sent"]
            time.sleep(0.2)
            c0 = time.process_time()
            time.sleep(1.0)
            print("INTERRUPTED", latency, time.process_time() - c0)
        """
    )
    p = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=timeout
    )
    assert p.returncode == 0, p.stderr
    return p.stdout


def _partial(code):
    """Runs `code` (which catches KeyboardInterrupt and prints what it
    kept) in a fresh interpreter that gets SIGINT 1 s into it; returns
    its output."""
    script = textwrap.dedent(
        """
        import os, signal, threading
        signal.signal(signal.SIGINT, signal.default_int_handler)
        import numpy as np
        import fpc
        threading.Timer(1.0, lambda: os.kill(os.getpid(), signal.SIGINT)).start()
        """
    ) + textwrap.dedent(code)
    p = subprocess.run(
        [sys.executable, "-c", script], capture_output=True, text=True, timeout=300
    )
    assert p.returncode == 0, p.stderr
    return p.stdout


def test_ctrl_c_stops_a_batch():
    out = _interrupted(
        "fpc.batch_solve(pressure_kpa=np.linspace(0, 300, 1_000_000), tip_tol_mm=1e-3)"
    )
    assert out.startswith("INTERRUPTED"), out
    assert float(out.split()[1]) < 5, out


def test_ctrl_c_keeps_the_points_a_batch_solved():
    code = """
    p = np.linspace(0.0, 300.0, 1_000_000)
    try:
        fpc.batch_solve(pressure_kpa=p, tip_tol_mm=1e-3)
        print("FINISHED")
    except KeyboardInterrupt as e:
        b = e.partial
        st = b["status"]
        done = np.flatnonzero(st == 0)
        left = np.flatnonzero(st == 4)
        i = int(done[len(done) // 2])
        one = fpc.batch_solve(pressure_kpa=[p[i]], tip_tol_mm=1e-3)
        print("PARTIAL", len(st), len(done), len(left), len(done) + len(left),
              bool(np.isnan(b["tip"][left]).all()),
              all(b["error"][k] == "stopped by Ctrl-C before this point" for k in left[:100]),
              float(np.abs(b["tip"][i] - one["tip"][0]).max()), fpc.BATCH_STATUS[4])
    """
    out = _partial(code)
    words = out.split()
    assert words[0] == "PARTIAL", out
    n, done, left, both = (int(w) for w in words[1:5])
    assert n == 1_000_000 and both == n and done > 0 and left > 0, out
    assert words[5] == "True" and words[6] == "True", out
    # the kept point is the answer a batch of that point alone gives
    assert float(words[7]) == 0.0, out
    assert words[8] == "stopped", out


def test_ctrl_c_stops_a_study():
    out = _interrupted("fpc.run_study(5, sweep_points=500, angle_samples=200)")
    assert out.startswith("INTERRUPTED"), out
    assert float(out.split()[1]) < 5, out
    # the study itself stopped: an abandoned study would spend a CPU second
    # or more per second; half of one leaves room for the solves in flight
    # to finish their step on a loaded machine (0.31 s seen under load)
    assert float(out.split()[2]) < 0.5, out


def test_ctrl_c_keeps_the_points_a_sweep_solved():
    # 100000 cuboid grasps at alternating pressures (each point a new load
    # family, so each starts from rest) take about 13 s here (about 10 000
    # in the first second): the signal, after 1 s, lands early in them. The exception's `partial` is the sweep's dict; a solved
    # point is checked again by a single grasp through the ordinary path.
    code = """
    g = fpc.Gripper()
    try:
        g.sweep("cuboid", d_mm=np.linspace(60.0, 120.0, 100_000), friction_n=0.3,
                pressure_kpa=np.tile([0.0, 20.0], 50_000))
        print("FINISHED")
    except KeyboardInterrupt as e:
        p = e.partial
        ok, err = p["ok"], p["error"]
        stopped = [m == "stopped by Ctrl-C before this point" for m in err]
        first = stopped.index(True)
        last = first - 1
        one = g.grasp_cuboid(d_mm=float(p["inputs"]["d_mm"][last]), friction_n=0.3,
                             pressure_kpa=float(p["inputs"]["pressure_kpa"][last]))
        print("PARTIAL", len(ok), first, int(ok[:first].sum()), all(stopped[first:]),
              int(ok[first:].sum()), bool(np.isnan(p["normal_force_n"][first:]).all()),
              abs(p["normal_force_n"][last] - one["normal_force_n"]))
    """
    out = _partial(code)
    words = out.split()
    assert words[0] == "PARTIAL", out
    n, first, solved = int(words[1]), int(words[2]), int(words[3])
    assert n == 100_000, out
    # some points solved (every one of them), not all
    assert 0 < first < n and solved == first, out
    assert words[4] == "True" and words[5] == "0" and words[6] == "True", out
    assert float(words[7]) < 1e-7, out


# a design that takes about 13 s on the CI machine (the sphere's envelope at
# every evaluation), so the interrupt after 1 s always lands inside it
HEAVY_DESIGN = """
[[object]]
kind = "cuboid"
size_mm = [70.0, 100.0]
lift_n = 0.6
[[object]]
kind = "sphere"
radius_mm = [40.0, 60.0]
lift_n = 0.5
[vary]
eps0 = [0.1, 0.45]
"""


def test_ctrl_c_stops_a_design():
    out = _interrupted(f"fpc.design({HEAVY_DESIGN!r}, starts=2000)")
    assert out.startswith("INTERRUPTED"), out
    assert float(out.split()[1]) < 5, out
    assert float(out.split()[2]) < 0.3, out


# ------------------------------------------------ 6. the bench script


def test_bench_with_a_wrong_binary_fails_in_one_line(tmp_path):
    env = dict(os.environ, FPC_LAB_BIN=str(tmp_path / "no-such-fpc-lab"))
    p = subprocess.run(
        [sys.executable, str(HERE.parent / "bench" / "bench.py")],
        capture_output=True,
        text=True,
        env=env,
        timeout=60,
    )
    assert p.returncode == 2, p.stderr
    assert "Traceback" not in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1, p.stderr
    assert "no-such-fpc-lab" in p.stderr

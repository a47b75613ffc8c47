"""The fuzz loop of test_fuzz.py, run in its own interpreter (a crash, an
abort or a hang there fails the test instead of killing pytest):

    python fuzz_calls.py SEED CALLS

Calls every public function of `fpc` CALLS times with one or two of its
arguments (or an unknown keyword) replaced by an extreme value, and
requires each call to return or raise a clean Python exception: any
``Exception`` but ``fpc.InternalError`` (a caught panic: a bug) and
``SystemError``. Each call has 60 s (faulthandler ends the process with the
stuck call's traceback). Prints one line per call before it runs, and
``FUZZ OK`` at the end."""

import faulthandler
import math
import pathlib
import random
import sys
import time

import numpy as np

import fpc

REPO = pathlib.Path(__file__).resolve().parents[3]
SCENE = str(REPO / "scenes" / "cuboid_grasp.toml")
CUBOID = """
[[object]]
kind = "cuboid"
size_mm = [70.0, 100.0]
lift_n = 0.6
[vary]
eps0 = [0.1, 0.45]
"""

EXTREMES = [
    0, -1, 1, 2, 10**18, -(10**18), 10**30, 0.0, -0.0, 1e-300, 1e308, -1e308,
    math.nan, math.inf, -math.inf, 1 + 2j, True, False, None, "", "x", "auto",
    "size", "1e3", [], [1.0, math.nan], {}, {"lx": -1}, {"eps0": math.inf},
    object(), b"bytes", np.float64(math.nan), np.int64(-5), np.array([]),
    np.array([1.0, -1.0]), np.array([[1e300]]), np.array([1 + 1j]),
    np.zeros((3, 0)), "no/such/file.toml", "[[[", "x = ", CUBOID,
]

F = fpc.Finger(elements=2)
G = fpc.Gripper()

# (name, callable, {argument: a valid value}); the fuzz replaces some
CALLS = [
    ("Finger", fpc.Finger, {"eps0": 0.25, "elements": 4, "model": "ccm", "ribs": True, "h1": 1.0, "pemc": {"eps0": 0.3}}),
    ("Finger.from_scene", fpc.Finger.from_scene, {"scene": SCENE}),
    ("Finger.solve", F.solve, {"pressure_kpa": 10.0, "fx": 0.1, "fz": 0.1, "kappa": 2.5, "tip_tol_mm": None, "shape": False, "stability": False, "guess": None}),
    ("solve_scene", fpc.solve_scene, {"scene": SCENE, "name": "x"}),
    ("Gripper", fpc.Gripper, {"finger": None, "mounting_angle_deg": 60.0, "overlap_mm": 20.0, "palm_mm": None, "fingers": 3, "mu": 0.6, "strict": False, "stability": True}),
    ("Gripper.from_scene", fpc.Gripper.from_scene, {"scene": SCENE}),
    ("grasp_size", G.grasp_size, {"d_mm": 100.0, "beta_deg": 0.0, "pressure_kpa": 0.0}),
    ("grasp_cuboid", G.grasp_cuboid, {"d_mm": 100.0, "friction_n": 0.3, "pressure_kpa": 0.0}),
    ("grasp_sphere", G.grasp_sphere, {"r_mm": 50.0, "lift_n": 0.5, "beta_deg": 20.0, "pressure_kpa": 0.0}),
    ("sweep", G.sweep, {"kind": "size", "d_mm": [90.0, 100.0], "beta_deg": 0.0}),
    ("run_study", fpc.run_study, {"study": 7, "coarse": True, "elements": 4, "pressure_points": 3}),
    ("studies", fpc.studies, {}),
    ("models", fpc.models, {}),
    ("design", fpc.design, {"requirements": CUBOID, "starts": 0, "seed": 1}),
    ("batch_solve", fpc.batch_solve, {"eps0": [0.2, 0.3], "pressure_kpa": 10.0, "fx": 0.0, "fz": 0.0, "kappa": 2.5, "elements": 4, "model": "ccm", "ribs": True, "tip_tol_mm": None, "warm_start": False, "threads": 1}),
]


def main(seed, calls):
    rng = random.Random(seed)
    worst = (0.0, "")
    for i in range(calls):
        name, f, base = CALLS[i % len(CALLS)] if i < len(CALLS) else rng.choice(CALLS)
        kwargs = dict(base)
        changed = []
        for _ in range(rng.choice([1, 1, 2])):
            if kwargs and rng.random() < 0.9:
                key = rng.choice(sorted(kwargs))
            else:
                key = rng.choice(["colour", "sweep_points", "eps0", "elements", "h1"])
            kwargs[key] = rng.choice(EXTREMES)
            changed.append(key)
        shown = ", ".join(f"{k}={kwargs[k]!r:.40}" for k in changed)
        print(f"{i}: {name}({shown})", flush=True)
        faulthandler.dump_traceback_later(60, exit=True)
        t = time.perf_counter()
        try:
            f(**kwargs)
        except (fpc.InternalError, SystemError) as e:
            print(f"FUZZ FAIL {name}({shown}): {type(e).__name__}: {e}", flush=True)
            sys.exit(1)
        except Exception:  # noqa: BLE001 - any clean exception is an answer
            pass
        faulthandler.cancel_dump_traceback_later()
        dt = time.perf_counter() - t
        worst = max(worst, (dt, f"{name}({shown})"))
    print(f"slowest call: {worst[0]:.2f} s {worst[1]}")
    print("FUZZ OK", flush=True)


if __name__ == "__main__":
    main(int(sys.argv[1]), int(sys.argv[2]))

"""Speed of the Python module against the Rust library.

    python crates/python/bench/bench.py [--fpc-lab PATH] [--points N] [--json]

1. Per-call overhead of a single solve: the standard cases of `fpc-lab timing`
   (default actuator, N = 8, tip-only output) timed from Python through
   `Finger.solve(..., shape=False, stability=False)`, against the Rust
   medians that `fpc-lab timing --json` measures in-process. Needs the
   `fpc-lab` binary (--fpc-lab or FPC_LAB_BIN); without it only the Python
   side is timed.
2. Batch throughput on all cores: `fpc.batch_solve` over N tip-loaded
   points (cold solves, as `Finger.solve` does them) against
   `fpc._batch_reference`, the same points solved by a plain rayon loop in
   Rust (one reused Solver per chunk, no Python objects), timed inside Rust.
   The target is batch >= 80 % of the reference.
"""

import argparse
import json
import os
import platform
import statistics
import subprocess
import sys
import time

import numpy as np

import fpc

FX, FZ = 0.939782, 0.521707  # the tip load of `fpc-lab timing`'s loaded cases (N)


def fail(message):
    """One line on stderr and exit status 2 (a usage error), no traceback."""
    print(message, file=sys.stderr)
    sys.exit(2)


def median_call_us(f, budget_s=0.4, min_runs=31):
    f()
    samples = []
    start = time.perf_counter()
    while time.perf_counter() - start < budget_s or len(samples) < min_runs:
        t = time.perf_counter_ns()
        f()
        samples.append((time.perf_counter_ns() - t) / 1e3)
    return statistics.median(samples), len(samples)


def rust_timing(binary):
    if not binary:
        return None
    out = subprocess.run([binary, "timing", "--json", "--budget-ms", "400"], capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def per_call(rust):
    f25, f40 = fpc.Finger(eps0=0.25), fpc.Finger(eps0=0.4)
    tip = dict(shape=False, stability=False)
    unloaded = f25.solve(**tip)["coefficients"]
    near = f25.solve(fx=0.95 * FX, fz=0.95 * FZ, **tip)["coefficients"]
    cases = {
        "unloaded": lambda: f25.solve(**tip),
        "pressure": lambda: f40.solve(pressure_kpa=386.0, **tip),
        "loaded_cold": lambda: f25.solve(fx=FX, fz=FZ, guess=unloaded, **tip),
        "loaded_warm": lambda: f25.solve(fx=FX, fz=FZ, guess=near, **tip),
        # for reference: the default output (shape sampled, eigenvalues counted)
        "loaded_full_output": lambda: f25.solve(fx=FX, fz=FZ, guess=unloaded),
    }
    rows = {}
    for name, f in cases.items():
        py_us, runs = median_call_us(f)
        r_us = rust[name]["median_us"] if rust and name in rust else None
        rows[name] = {
            "python_us": py_us,
            "runs": runs,
            "rust_us": r_us,
            "overhead_us": None if r_us is None else py_us - r_us,
        }
    return rows


def batch(points, repeats=5):
    rng = np.random.default_rng(1)
    s = rng.uniform(0.5, 1.0, points)
    fx, fz = s * FX, s * FZ
    p = np.zeros(points)
    out = {}
    for label, threads in (("all_cores", None), ("one_thread", 1)):
        ours, ref = [], []
        for _ in range(repeats):
            t = time.perf_counter()
            r = fpc.batch_solve(eps0=0.25, pressure_kpa=p, fx=fx, fz=fz, threads=threads)
            ours.append(time.perf_counter() - t)
            assert (r["status"] == 0).all()
            secs, solved = fpc._batch_reference(0.25, p.tolist(), fx.tolist(), fz.tolist(), 8, threads)
            assert solved == points
            ref.append(secs)
        t_ours, t_ref = min(ours), min(ref)
        out[label] = {
            "points": points,
            "batch_solves_per_s": points / t_ours,
            "rust_reference_solves_per_s": points / t_ref,
            "ratio": t_ref / t_ours,
        }
    t = time.perf_counter()
    fpc.batch_solve(eps0=0.25, pressure_kpa=p, fx=fx, fz=fz, warm_start=True)
    out["all_cores_warm_start_solves_per_s"] = points / (time.perf_counter() - t)
    return out


def cpu():
    try:
        text = subprocess.run(["lscpu"], capture_output=True, text=True).stdout
        model = next(l.split(":", 1)[1].strip() for l in text.splitlines() if l.startswith("Model name"))
    except (OSError, StopIteration):
        model = platform.processor()
    return {"model": model, "cores": os.cpu_count()}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--fpc-lab", default=os.environ.get("FPC_LAB_BIN"), help="the fpc-lab binary (for `fpc-lab timing`)")
    ap.add_argument("--points", type=int, default=20000)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    if args.fpc_lab and not (os.path.isfile(args.fpc_lab) and os.access(args.fpc_lab, os.X_OK)):
        fail(f"bench.py: the fpc-lab binary {args.fpc_lab!r} (--fpc-lab or FPC_LAB_BIN) is not an executable file")
    if args.points < 1:
        fail(f"bench.py: --points must be at least 1, got {args.points}")
    try:
        rust = rust_timing(args.fpc_lab)
    except (OSError, subprocess.CalledProcessError, ValueError) as e:
        fail(f"bench.py: `{args.fpc_lab} timing --json` failed: {str(e).splitlines()[0] if str(e) else type(e).__name__}")
    result = {"cpu": cpu(), "rust_build": rust and rust.get("build"), "per_call": per_call(rust), "batch": batch(args.points)}
    if args.json:
        print(json.dumps(result, indent=2))
        return
    c = result["cpu"]
    print(f"CPU: {c['model']}, {c['cores']} cores; fpc-lab timing build: {result['rust_build']}")
    print("\nsingle solve, tip-only output (median per call)")
    print(f"{'case':<20}{'python us':>11}{'rust us':>10}{'overhead us':>13}")
    for name, r in result["per_call"].items():
        rust_us = "-" if r["rust_us"] is None else f"{r['rust_us']:.2f}"
        over = "-" if r["overhead_us"] is None else f"{r['overhead_us']:.2f}"
        print(f"{name:<20}{r['python_us']:>11.2f}{rust_us:>10}{over:>13}")
    print("\nbatch, tip-loaded cold solves (best of 5)")
    for label in ("all_cores", "one_thread"):
        b = result["batch"][label]
        print(
            f"{label:<11} {b['points']} points: batch_solve {b['batch_solves_per_s']:,.0f}/s, "
            f"Rust reference {b['rust_reference_solves_per_s']:,.0f}/s, ratio {100 * b['ratio']:.1f} %"
        )
    print(f"all cores, warm_start=True: {result['batch']['all_cores_warm_start_solves_per_s']:,.0f}/s")


if __name__ == "__main__":
    main()

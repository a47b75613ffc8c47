"""A parameter sweep with Dask: `fpc.batch_solve` is the unit of work.

    python examples/python/dask_sweep.py [--points N] [--workers W] [--threads-in-process]
    python examples/python/dask_sweep.py --scheduler tcp://HOST:8786   # a running cluster

The sweep (prestrain x pressure x tip force) is cut into chunks; each chunk
is one `fpc.batch_solve` call on a Dask worker, which solves its points in
parallel in Rust with the GIL released. The chunks come back as dicts of
numpy arrays and are concatenated in order. Cold solves (the default) make
the result independent of how the sweep is cut: it equals one
`batch_solve` over every point, which the script checks.

The cluster is local (dask.distributed.LocalCluster on 127.0.0.1, no
dashboard) unless --scheduler names a running one: the same code then runs
on its workers (each needs this fpc module installed). Needs
dask[distributed]; without it the script says so and exits 0, or 1 with
--require-dask (CI).
"""

import argparse
import contextlib
import sys
import time

try:
    from dask.distributed import Client, LocalCluster
except ImportError:
    print("dask_sweep.py: dask.distributed is not installed; skipped (pip install 'dask[distributed]')")
    sys.exit(1 if "--require-dask" in sys.argv else 0)

import numpy as np

import fpc

KEYS = ("eps0", "pressure_kpa", "fx", "fz")


def solve_chunk(chunk, threads):
    """The unit of work: one batch over 1-D arrays of the same length."""
    import fpc  # imported on the worker

    r = fpc.batch_solve(**chunk, threads=threads)
    return {k: r[k] for k in ("tip", "end_angle", "status", "iterations", "valid")} | {
        "error": np.array(r["error"], dtype=object)
    }


def grid(points):
    """A sweep of about `points` points, flattened to 1-D arrays."""
    n = max(2, round((points / 3) ** (1 / 3)))
    eps0, p, fx = np.meshgrid(fpc.PAPER_EPS0, np.linspace(0, 60, n), np.linspace(0, 0.6, n * n), indexing="ij")
    fz = 0.2 * np.ones_like(fx)
    return {k: v.ravel() for k, v in zip(KEYS, (eps0, p, fx, fz))}


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--points", type=int, default=6000, help="about this many solves")
    ap.add_argument("--workers", type=int, default=2, help="Dask worker processes")
    ap.add_argument("--chunk", type=int, default=500, help="points per task")
    ap.add_argument(
        "--threads-in-process",
        action="store_true",
        help="thread workers in this process (batch_solve releases the GIL) instead of processes",
    )
    ap.add_argument("--scheduler", help="address of a running Dask scheduler (default: a local cluster)")
    ap.add_argument("--require-dask", action="store_true", help="fail (status 1) when dask is not installed")
    args = ap.parse_args()

    sweep = grid(args.points)
    m = len(sweep["eps0"])
    chunks = [{k: v[i : i + args.chunk] for k, v in sweep.items()} for i in range(0, m, args.chunk)]

    if args.scheduler:
        cluster = contextlib.nullcontext()
        client = Client(args.scheduler, timeout=30)
    else:
        cluster = LocalCluster(
            n_workers=1 if args.threads_in_process else args.workers,
            threads_per_worker=args.workers if args.threads_in_process else 1,
            processes=not args.threads_in_process,
            host="127.0.0.1",
            dashboard_address=None,
        )
        client = Client(cluster)
    with cluster, client:
        # one rayon thread per task: Dask runs the tasks side by side
        client.map(solve_chunk, chunks[:1], threads=1)[0].result()  # warm up the workers
        start = time.perf_counter()
        futures = client.map(solve_chunk, chunks, threads=1)
        parts = client.gather(futures)
        elapsed = time.perf_counter() - start

    result = {k: np.concatenate([p[k] for p in parts]) for k in parts[0]}
    ok = result["status"] == 0
    print(f"{m} solves in {len(chunks)} tasks on {args.workers} workers: {elapsed:.2f} s, {m / elapsed:,.0f} solves/s")
    print(f"solved {ok.sum()}, failed {(~ok).sum()}, within the model {result['valid'].sum()}")

    # the same sweep in one call, on this machine's cores
    start = time.perf_counter()
    whole = fpc.batch_solve(**sweep)
    one = time.perf_counter() - start
    print(f"one batch_solve over every point: {one:.2f} s, {m / one:,.0f} solves/s")
    # point by point: the same answer, status, verdict and work
    for key in ("tip", "end_angle", "status", "iterations", "valid"):
        np.testing.assert_array_equal(result[key], whole[key], err_msg=key)
    assert list(result["error"]) == list(whole["error"])
    print("the Dask result equals the single batch exactly, point by point")

    i = np.argmax(np.where(ok, -result["tip"][:, 1], -np.inf))
    print(
        "lowest tip: Z = {:.2f} mm at eps0 = {}, {:.0f} kPa, fx = {:.3f} N".format(
            result["tip"][i, 1], sweep["eps0"][i], sweep["pressure_kpa"][i], sweep["fx"][i]
        )
    )


if __name__ == "__main__":
    main()

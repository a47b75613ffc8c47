"""Shared fixtures: the repository's paths and the `fpc` command-line binary.

The CLI comparisons need the binary built from the same source
(`cargo build -p fpc-cli`); .ci/run sets FPC_BIN to it. Without FPC_BIN
those tests are skipped.
"""

import json
import math
import os
import pathlib
import subprocess

import numpy as np
import pytest

REPO = pathlib.Path(__file__).resolve().parents[3]
SCENES = sorted((REPO / "scenes").glob("*.toml"))


@pytest.fixture(scope="session")
def fpc_bin():
    path = os.environ.get("FPC_BIN")
    if not path:
        pytest.skip("FPC_BIN is not set (the path of a built `fpc` binary)")
    if not os.path.isfile(path):
        pytest.fail(f"FPC_BIN={path} is not a file")
    return path


def run_cli(fpc_bin, *args, cwd=None):
    """Runs the CLI; returns its stdout (fails the test on a non-zero exit)."""
    p = subprocess.run(
        [fpc_bin, *map(str, args)], capture_output=True, text=True, cwd=cwd
    )
    assert p.returncode == 0, f"fpc {' '.join(map(str, args))}: {p.stderr}"
    return p.stdout


def cli_json(fpc_bin, *args):
    return json.loads(run_cli(fpc_bin, *args))


def assert_same(a, b, path="", tol=1e-12):
    """`a` (from Python, numpy arrays allowed) equals `b` (parsed JSON):
    the same keys and strings, numbers within `tol` (relative above 1)."""
    if isinstance(a, np.ndarray):
        a = a.tolist()
    if isinstance(b, dict):
        assert isinstance(a, dict), f"{path}: {type(a)} is not a dict"
        assert set(a) == set(b), f"{path}: keys {sorted(set(a) ^ set(b))} differ"
        for k in b:
            assert_same(a[k], b[k], f"{path}.{k}", tol)
    elif isinstance(b, list):
        assert isinstance(a, (list, tuple)), f"{path}: {type(a)} is not a list"
        assert len(a) == len(b), f"{path}: length {len(a)} != {len(b)}"
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same(x, y, f"{path}[{i}]", tol)
    elif isinstance(b, bool) or b is None or isinstance(b, str):
        assert a == b, f"{path}: {a!r} != {b!r}"
    elif isinstance(b, (int, float)):
        assert isinstance(a, (int, float)) and not isinstance(a, bool), f"{path}: {a!r}"
        if math.isnan(b):
            assert math.isnan(a), f"{path}: {a} is not NaN"
        else:
            assert abs(a - b) <= tol * max(1.0, abs(b)), f"{path}: {a!r} != {b!r}"
    else:
        raise AssertionError(f"{path}: unexpected JSON value {b!r}")

"""Fuzz: extreme values (0, -1, 10**18, nan, inf, complex, wrong types,
unknown keywords) through every public function's signature, seeded. Each
call must give an answer or a clean Python exception, never a crash, an
abort, a hang or a caught panic (fpc.InternalError). The loop runs in a
subprocess (fuzz_calls.py) with a 60 s limit per call."""

import pathlib
import subprocess
import sys

import pytest

HERE = pathlib.Path(__file__).resolve().parent


@pytest.mark.parametrize("seed", [1, 2])
def test_extreme_arguments_give_answers_or_clean_exceptions(seed):
    p = subprocess.run(
        [sys.executable, str(HERE / "fuzz_calls.py"), str(seed), "600"],
        capture_output=True,
        text=True,
        timeout=900,
    )
    last = p.stdout.strip().splitlines()[-3:]
    assert p.returncode == 0, (
        f"exit status {p.returncode} (negative: killed by a signal) after\n"
        + "\n".join(last)
        + "\n"
        + p.stderr[-3000:]
    )
    assert "FUZZ OK" in p.stdout, p.stdout[-2000:]

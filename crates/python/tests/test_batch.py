"""`fpc.batch_solve`: broadcasting, the results of a loop of single solves
exactly, failures per point, warm starts, threads, and the GIL released."""

import os
import subprocess
import sys
import threading
import time

import numpy as np
import pytest

import fpc


def loop(eps0, pressure_kpa, fx, fz, elements=None):
    """The same points by `Finger.solve`, one at a time."""
    tips, status, errors = [], [], []
    fingers = {}
    for e, p, x, z in zip(eps0, pressure_kpa, fx, fz):
        try:
            f = fingers.setdefault(e, fpc.Finger(eps0=e, elements=elements))
            r = f.solve(pressure_kpa=p, fx=x, fz=z, shape=False, stability=False)
            tips.append(r["tip"])
            status.append(0)
            errors.append("")
        except fpc.InputError as err:
            tips.append([np.nan, np.nan])
            status.append(1)
            errors.append(str(err))
        except fpc.SolveError as err:
            tips.append([np.nan, np.nan])
            status.append(2)
            errors.append(str(err))
    return np.array(tips), np.array(status), errors


def test_a_batch_equals_a_loop_of_single_solves_exactly():
    eps0 = np.array([0.15, 0.25, 0.4])[:, None]
    fx = np.linspace(-0.4, 0.6, 5)
    r = fpc.batch_solve(eps0=eps0, pressure_kpa=20.0, fx=fx, fz=0.1)
    assert r["shape"] == (3, 5)
    assert r["tip"].shape == (15, 2)
    assert (r["status"] == 0).all(), r["error"]
    e, p, x, z = np.broadcast_arrays(eps0, 20.0, fx, 0.1)
    for name, v in [("eps0", e), ("pressure_kpa", p), ("fx", x), ("fz", z)]:
        np.testing.assert_array_equal(r[name], v.ravel())
    tips, status, _ = loop(e.ravel(), p.ravel(), x.ravel(), z.ravel())
    np.testing.assert_array_equal(r["tip"], tips)  # bit for bit
    np.testing.assert_array_equal(r["status"], status)
    assert r["valid"].dtype == bool and r["valid"].all()
    assert (r["iterations"] > 0).all() and (r["residual"] <= 1e-10).all()
    assert (r["elements"] == 8).all()
    assert r["error"] == [""] * 15


@pytest.mark.parametrize("threads", [1, 2])
def test_many_prestrains_equal_single_solves_exactly(threads):
    # 24 distinct prestrains (each chunk builds its own finger), and one
    # prestrain of many points whose chunks each build it again
    eps0 = np.concatenate([np.linspace(0.1, 0.4, 24), np.full(40, 0.3)])
    fx = np.resize(np.linspace(-0.3, 0.5, 7), eps0.size)
    r = fpc.batch_solve(eps0=eps0, pressure_kpa=15.0, fx=fx, fz=0.1, threads=threads)
    tips, status, errors = loop(eps0, np.full(eps0.size, 15.0), fx, np.full(eps0.size, 0.1))
    assert (status == 0).all(), errors
    np.testing.assert_array_equal(r["tip"], tips)  # bit for bit
    np.testing.assert_array_equal(r["status"], status)


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="RLIMIT_AS")
def test_many_distinct_prestrains_fit_in_memory():
    # 250000 distinct prestrains, each point's load refused before any
    # solve: were a finger (tens of kB) kept per prestrain, as once, this
    # would need 5 GB or more; under an address-space limit of 3 GB the
    # batch must finish, one finger per chunk alive at a time (the
    # documented bound, a million, then fits too)
    code = """
import resource
resource.setrlimit(resource.RLIMIT_AS, (3 << 30, 3 << 30))
import numpy as np, fpc
r = fpc.batch_solve(eps0=np.linspace(0.1, 0.4, 250_000), kappa=-1.0, threads=2)
assert (r["status"] == 1).all()
assert r["error"][0].startswith("kappa = -1: must be positive"), r["error"][0]
"""
    # one BLAS thread: its buffers are not counted against the limit
    env = dict(os.environ, OPENBLAS_NUM_THREADS="1", OMP_NUM_THREADS="1", MKL_NUM_THREADS="1")
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=env)
    assert run.returncode == 0, run.stderr[-2000:]


@pytest.mark.parametrize("threads", [1, 2, 3])
def test_the_result_does_not_depend_on_the_threads(threads):
    p = np.linspace(0, 120, 13)
    ref = fpc.batch_solve(eps0=[0.25, 0.4], pressure_kpa=p[:, None], fz=-0.1, threads=1)
    r = fpc.batch_solve(eps0=[0.25, 0.4], pressure_kpa=p[:, None], fz=-0.1, threads=threads)
    np.testing.assert_array_equal(r["tip"], ref["tip"])
    np.testing.assert_array_equal(r["end_angle"], ref["end_angle"])
    np.testing.assert_array_equal(r["iterations"], ref["iterations"])


def test_failed_points_are_reported_per_point():
    fx = np.array([0.2, 1e6, 0.3, np.nan])
    p = np.array([0.0, 0.0, -500.0, 0.0])
    r = fpc.batch_solve(eps0=0.25, pressure_kpa=p, fx=fx)
    names = [fpc.BATCH_STATUS[s] for s in r["status"]]
    assert names == ["ok", "not_converged", "input_error", "input_error"], r["error"]
    assert r["error"][0] == ""
    assert r["error"][1].startswith("solve failed"), r["error"][1]
    assert r["error"][2].startswith("pressure_kpa = -500"), r["error"][2]
    assert r["error"][3].startswith("fx = NaN"), r["error"][3]
    assert np.isnan(r["tip"][1:]).all() and not r["valid"][1:].any()
    tips, status, errors = loop([0.25] * 4, p, fx, [0.0] * 4)
    np.testing.assert_array_equal(r["status"], status)
    np.testing.assert_array_equal(r["tip"], tips)
    assert r["error"] == errors  # the same messages as the exceptions


def test_a_prestrain_the_actuator_rejects_fails_its_points_only():
    r = fpc.batch_solve(eps0=[0.25, np.nan, 0.4])
    assert list(r["status"]) == [0, 1, 0]
    assert r["error"][1].startswith("actuator.pemc.eps0"), r["error"][1]


def test_warm_starts_agree_to_the_solver_tolerance():
    fx = np.linspace(0, 0.9, 19)
    cold = fpc.batch_solve(eps0=[0.25, 0.4], fx=fx[:, None], fz=0.3)
    warm = fpc.batch_solve(eps0=[0.25, 0.4], fx=fx[:, None], fz=0.3, warm_start=True)
    assert (warm["status"] == 0).all(), warm["error"]
    # the same equilibria to the residual tolerance (the curled eps0 = 0.4
    # finger amplifies a 1e-11 relative residual to ~1e-7 mm at its tip)
    np.testing.assert_allclose(warm["tip"], cold["tip"], rtol=0, atol=1e-6)
    assert warm["iterations"].sum() < cold["iterations"].sum()


def test_elements_auto_tip_tolerance_model_and_actuator():
    r = fpc.batch_solve(eps0=0.4, pressure_kpa=[0, 100], elements="auto")
    f = fpc.Finger(eps0=0.4, elements="auto")
    for i, p in enumerate([0, 100]):
        s = f.solve(pressure_kpa=p)
        np.testing.assert_array_equal(r["tip"][i], s["tip"])
        assert r["elements"][i] == s["elements"]
    # with a tip tolerance the batch gives the refinement's best tip, the
    # one the tolerance is about, with its estimate and every level's
    # iterations (and no re-solve of the finest level for the shape or the
    # eigenvalues: the refinement is the same)
    r = fpc.batch_solve(fx=[0.1, 0.2], tip_tol_mm=0.5)
    s = fpc.Finger().solve(fx=0.2, tip_tol_mm=0.5, shape=False, stability=False)
    np.testing.assert_array_equal(r["tip"][1], s["refinement"]["tip"])
    assert r["tip_error"][1] == s["tip_error_estimate"] <= 0.5
    assert r["iterations"][1] == sum(s["refinement"]["level_iterations"])
    assert np.isnan(fpc.batch_solve(fx=0.2)["tip_error"][0])
    r = fpc.batch_solve(fx=0.2, model="quad", elements=6, lx=100.0, cx=95.0)
    s = fpc.Finger(model="quad", elements=6, lx=100.0, cx=95.0).solve(fx=0.2)
    np.testing.assert_array_equal(r["tip"][0], s["tip"])


def test_scalars_give_one_point_and_empty_inputs_none():
    r = fpc.batch_solve()
    assert r["shape"] == () and r["tip"].shape == (1, 2) and r["status"][0] == 0
    np.testing.assert_array_equal(r["tip"][0], fpc.Finger().solve()["tip"])
    r = fpc.batch_solve(fx=np.zeros(0))
    assert r["shape"] == (0,) and r["tip"].shape == (0, 2) and r["error"] == []


def test_bad_arguments_name_their_field():
    with pytest.raises(fpc.InputError) as e:
        fpc.batch_solve(fx=[1, 2], fz=[1, 2, 3])
    assert e.value.field == "eps0"  # the first of the broadcast inputs
    assert "broadcast" in str(e.value)
    with pytest.raises(ValueError, match=r"^threads") as e:
        fpc.batch_solve(threads=0)
    assert e.value.field == "threads"
    with pytest.raises(fpc.InputError, match=r"^elements"):
        fpc.batch_solve(elements=0)
    # a point's message names the argument too
    r = fpc.batch_solve(elements=600, tip_tol_mm=0.1)
    assert r["error"][0].startswith("elements = 600: must lie in [1, 500]"), r["error"]
    with pytest.raises(fpc.InputError, match=r"^model"):
        fpc.batch_solve(model="nope")
    with pytest.raises(fpc.InputError, match=r"^actuator\.geometry\.h1"):
        fpc.batch_solve(h1=9.0)


def test_the_gil_is_released_while_solving():
    stamps = []
    stop = threading.Event()

    def tick():
        while not stop.is_set():
            stamps.append(time.perf_counter())
            time.sleep(0.0005)

    t = threading.Thread(target=tick)
    t.start()
    try:
        time.sleep(0.01)
        # a batch long enough to tell on a fast machine: double it until
        # one call lasts 50 ms (the solves got faster than any fixed size)
        points = 4000
        while True:
            start = time.perf_counter()
            fpc.batch_solve(eps0=0.25, fx=np.linspace(0, 0.5, points), fz=0.2, threads=1)
            end = time.perf_counter()
            if end - start > 0.05 or points >= 256000:
                break
            points *= 2
    finally:
        stop.set()
        t.join()
    assert end - start > 0.02, f"the batch of {points} points is long enough to tell"
    # a thread holding the GIL for the whole call would let no tick in
    inside = [s for s in stamps if start + 0.005 < s < end - 0.005]
    assert inside, f"no tick during {end - start:.3f} s of solving"


def misaligned(values):
    """A float64 array at an odd address (as unpickled buffers can be)."""
    values = np.asarray(values, dtype=np.float64)
    buf = np.zeros(values.nbytes + 1, dtype=np.uint8)
    a = np.frombuffer(buf.data, dtype=np.float64, count=values.size, offset=1)
    a[...] = values.ravel()
    assert not a.flags.aligned
    return a.reshape(values.shape)


def test_any_array_layout_is_accepted():
    fx = np.linspace(0.0, 0.5, 6)
    ref = fpc.batch_solve(fx=fx, fz=0.2)
    for arg in (misaligned(fx), fx[::-1][::-1], np.asfortranarray(fx), fx.tolist(), tuple(fx)):
        r = fpc.batch_solve(fx=arg, fz=0.2)
        np.testing.assert_array_equal(r["tip"], ref["tip"])
    grid = np.linspace(0.0, 0.5, 6).reshape(2, 3)
    r = fpc.batch_solve(fx=np.asfortranarray(grid), fz=0.2)
    np.testing.assert_array_equal(r["fx"], grid.ravel())
    f = fpc.Finger()
    k = f.solve(fx=0.1)["coefficients"]
    a = f.solve(fx=0.2, guess=k)
    b = f.solve(fx=0.2, guess=misaligned(k))
    np.testing.assert_array_equal(a["tip"], b["tip"])
    c = f.solve(fx=0.2, guess=np.asfortranarray(k))
    np.testing.assert_array_equal(a["tip"], c["tip"])

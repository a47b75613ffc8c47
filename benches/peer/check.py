#!/usr/bin/env python3
"""Check the CasADi peer against fpc: the same equilibrium, to a tight tolerance.

Builds the peer at N = 8 into a temporary directory (or uses --build DIR
if it holds a driver already), runs its driver with a few repetitions, solves
the same case with `fpc solve` (a scene file), and compares the tip and every
element unknown. Exits 1 on a disagreement, 2 when it cannot run.

Usage:  python3 benches/peer/check.py --fpc PATH/TO/fpc [--build DIR]
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent

# The tip agrees to this (mm) ...
TIP_TOL_MM = 1e-8
# ... and every element unknown to this, relative to the largest unknown of
# its kind over the finger (a1, a3, b1, c2 differ in units and scale).
K_RTOL = 1e-8

FX, FZ = 0.939782, 0.521707


def fail(msg, code=2):
    print(f"check.py: {'FAIL' if code == 1 else 'error'}: {msg}", file=sys.stderr)
    sys.exit(code)


def run(cmd, what, **kw):
    try:
        r = subprocess.run(cmd, capture_output=True, text=True, **kw)
    except OSError as e:
        fail(f"cannot run {what} ({cmd[0]}): {e}")
    if r.returncode != 0:
        fail(f"{what} failed (exit {r.returncode}):\n{r.stdout}{r.stderr}")
    return r.stdout


def peer_answer(driver, reps):
    out = run([str(driver), str(reps)], "the peer driver", cwd=driver.parent)
    tip, k = [None, None], []
    for line in out.splitlines():
        w = line.split()
        if not w:
            continue
        if w[0] == "tip_x_mm":
            tip[0] = float(w[1])
        elif w[0] == "tip_z_mm":
            tip[1] = float(w[1])
        elif w[0] == "element":
            k.append([float(v) for v in w[2:6]])
    if None in tip or not k:
        fail(f"the peer driver printed no tip or state:\n{out}")
    return tip, k, out


# The same case as an fpc scene (README "Scene files"), solved to a relative
# residual of 1e-14 instead of the default 1e-11: at the default, fpc stops
# about 7e-8 mm from the exact equilibrium of the N = 8 equations, which
# the peer's Newton (quadratic to round-off) reaches.
SCENE = f"""\
[actuator.pemc]
eps0 = 0.25
[actuator.ribs]
kind = "paper"
[partition]
elements = 8
[load]
pressure_kpa = 0.0
kappa = 2.5
fx = {FX!r}
fz = {FZ!r}
[solve]
rtol = 1e-14
"""


def fpc_answer(fpc, tmp):
    scene = Path(tmp) / "peer_case.toml"
    scene.write_text(SCENE)
    cmd = [str(fpc), "solve", str(scene), "--out", str(Path(tmp) / "fpc-out")]
    run(cmd, "fpc solve")
    path = Path(tmp) / "fpc-out" / "solution.json"
    try:
        j = json.loads(path.read_text())
        tip, k = j["tip_mm"], j["coefficients"]
    except (OSError, json.JSONDecodeError, KeyError) as e:
        fail(f"cannot read the tip and coefficients from {path}: {e}")
    return tip, [list(map(float, row)) for row in k], j.get("report", {})


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--fpc", type=Path, default=os.environ.get("FPC_BIN"),
                    help="the fpc binary (default $FPC_BIN)")
    ap.add_argument("--build", type=Path, help="a peer build directory to reuse or fill")
    ap.add_argument("--reps", type=int, default=20, help="timed solves per case (default 20)")
    args = ap.parse_args()
    if args.fpc is None:
        fail("give the fpc binary with --fpc PATH or FPC_BIN (cargo build -p fpc-cli builds it)")
    if not args.fpc.is_file():
        fail(f"no fpc binary at {args.fpc} (cargo build -p fpc-cli builds it)")

    with tempfile.TemporaryDirectory(prefix="fpc-peer-check-") as tmp:
        build = args.build or Path(tmp)
        driver = build / "driver"
        if not driver.is_file():
            run([sys.executable, str(HERE / "build_peer.py"), "--build", str(build), "--elements", "8"],
                "build_peer.py")
        ptip, pk, pout = peer_answer(driver, args.reps)
        ftip, fk, freport = fpc_answer(args.fpc, tmp)

    if len(pk) != len(fk) or any(len(r) != 4 for r in fk):
        fail(f"the states differ in shape: peer {len(pk)} elements, fpc {len(fk)}", 1)
    dtip = max(abs(a - b) for a, b in zip(ptip, ftip))
    scale = [max(abs(r[j]) for r in fk) for j in range(4)]
    dk = max(abs(p[j] - f[j]) / scale[j] for p, f in zip(pk, fk) for j in range(4))
    timing = {w[0]: w[1] for w in (l.split() for l in pout.splitlines()) if len(w) == 2}
    print(f"fpc:  fpc solve (eps0 0.25, N = 8, Fx {FX}, Fz {FZ}, rtol 1e-14), "
          f"residual {freport.get('residual_norm', float('nan')):.2e}")
    print(f"  tip ({ftip[0]:.12f}, {ftip[1]:.12f}) mm")
    print(f"peer: N = 8, {timing.get('cold_iterations')} Newton iterations cold, "
          f"residual {timing.get('cold_residual')}")
    print(f"  tip ({ptip[0]:.12f}, {ptip[1]:.12f}) mm")
    print(f"largest tip difference {dtip:.2e} mm (tolerance {TIP_TOL_MM:.0e}); "
          f"largest unknown difference {dk:.2e} of its kind's scale (tolerance {K_RTOL:.0e})")
    if dtip > TIP_TOL_MM or dk > K_RTOL:
        fail("the peer and fpc disagree", 1)
    print("check.py: the peer and fpc agree")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Build the CasADi performance peer of fpc (a measuring instrument, not part of fpc).

The total potential energy of the N-element CCM finger of docs/model.md
(default actuator, ribs on, kappa = 2.5) is written out symbolically in
CasADi SX: the laminate energy of every element (M3-M6) with the
prestressed layer (M5), the gas work (M7, M8), the chain (M9, M10) and the
tip load (M11, M12). CasADi differentiates the whole system (gradient and
dense Hessian), its code generator writes C, gcc -O3 compiles it together
with driver.c, a small dense Newton that times the cold and warm solves of
`fpc-lab timing`. The result is DIR/driver; `DIR/driver REPS` prints
`cold_solve_us` / `warm_solve_us` and the solution.

Usage:  python3 benches/peer/build_peer.py --build DIR [--elements N]
"""

import argparse
import math
import os
import shutil
import subprocess
import sys
import tempfile
import time
from pathlib import Path

HERE = Path(__file__).resolve().parent


def fail(msg):
    print(f"build_peer.py: error: {msg}", file=sys.stderr)
    sys.exit(2)


try:
    import casadi as ca
except ImportError:
    fail("casadi is not installed; install it with `python3 -m pip install casadi numpy` (a venv is best)")
try:
    import numpy as np
except ImportError:
    fail("numpy is not installed; install it with `python3 -m pip install casadi numpy`")


# ---------------------------------------------------------------------------
# The default actuator (docs/model.md, section 3). Lengths mm, moduli MPa.

LX, LY, H = 110.0, 31.75, 8.2
H1, H2, H3 = 3.7, 1.8, 2.2
CX, CY, H3A, H3B = 105.0, 26.0, 0.8, 1.2
W1, W2, T = 8.0, 6.0, 2.0
EPS0 = 0.25
PSI = (1.598, 2.306, 2.29, 0.698)  # p1..p4 of (M5)
PEMC_E2 = 250.0
KAPPA = 2.5

# the standard case of `fpc-lab timing` (N, finger frame)
FX, FZ = 0.939782, 0.521707


def q_isotropic(e, nu):
    """(Q11, Q12, Q22) of (M3) for an isotropic lamina."""
    d = 1.0 - nu * nu
    return (e / d, nu * e / d, e / d)


def q_orthotropic(e1, e2, nu12):
    """(Q11, Q12, Q22) of (M3)."""
    nu21 = nu12 * e2 / e1
    d = 1.0 - nu12 * nu21
    return (e1 / d, nu12 * e2 / d, e2 / d)


Q_CL = q_isotropic(305.0, 0.43)
Q_EMC = q_orthotropic(1.5, 250.0, 0.0)
Q_FL = q_isotropic(1.2, 0.48)


def boxes():
    """The boxes of the whole finger in X_ref: (x0, x1, z0, z1, width, kind, q).

    kind is 'lin' (plane-stress density with stiffnesses q), 'pre' (the
    prestressed layer) or 'gas' (the gas volume's region, signed width).
    """
    ch = (-H3B, H3A)
    out = [
        (0.0, LX, H1, H / 2, LY, "lin", Q_CL),
        (0.0, LX, H2, H1, LY, "lin", Q_EMC),
        (0.0, LX, -H3, H2, LY, "lin", Q_FL),
        (0.0, LX, -H / 2, -H3, LY, "pre", None),
        # the channel is a void cut from the fluidic layer (M6) ...
        (0.0, CX, *ch, -CY, "lin", Q_FL),
        (0.0, CX, *ch, CY, "gas", None),
        # ... into which the ribs (decision D5) put material back
        (0.0, CX, *ch, T, "lin", Q_FL),
        (0.0, CX, *ch, -T, "gas", None),
    ]
    k = 1
    while k * W1 + T / 2 <= CX:
        x0, x1 = k * W1 - T / 2, k * W1 + T / 2
        out.append((x0, x1, *ch, 2 * W2, "lin", Q_FL))
        out.append((x0, x1, *ch, -2 * W2, "gas", None))
        k += 1
    return out


# ---------------------------------------------------------------------------
# Polynomials in (x, z) with SX coefficients: {(i, j): coefficient of x^i z^j}.


def pmul(a, b):
    out = {}
    for (i, j), u in a.items():
        for (k, l), v in b.items():
            key = (i + k, j + l)
            out[key] = out[key] + u * v if key in out else u * v
    return out


def padd(a, b, scale=1.0):
    out = dict(a)
    for key, v in b.items():
        out[key] = out[key] + scale * v if key in out else scale * v
    return out


def integrate(poly, moments):
    """sum_ij c_ij * moments[i, j]: the polynomial integrated with weighted box moments."""
    total = 0
    for (i, j), c in poly.items():
        m = moments[i, j]
        if m != 0.0:
            total = total + c * float(m)
    return total


MAX_DEG = 11


def box_moments(x0, x1, z0, z1, w):
    """w * integral over [x0, x1] x [z0, z1] of x^i z^j, for i, j < MAX_DEG."""
    i = np.arange(MAX_DEG)
    mx = (x1 ** (i + 1) - x0 ** (i + 1)) / (i + 1)
    mz = (z1 ** (i + 1) - z0 ** (i + 1)) / (i + 1)
    return w * np.outer(mx, mz)


def element_moments(s, length):
    """The element's box moments folded by material coefficient, in local x."""
    m = {key: np.zeros((MAX_DEG, MAX_DEG)) for key in ("q11", "q12", "q22", "pre", "gas")}
    for x0, x1, z0, z1, w, kind, q in boxes():
        a, b = max(x0, s), min(x1, s + length)
        if b <= a:
            continue
        mom = box_moments(a - s, b - s, z0, z1, w)
        if kind == "lin":
            m["q11"] += q[0] * mom
            m["q12"] += q[1] * mom
            m["q22"] += q[2] * mom
        else:
            m[kind] += mom
    return m


def element_energy(k, length, pressure, moments):
    """Psi_i - kappa P V_i of one element (M4-M8) at raw unknowns k = (a1, a3, b1, c2)."""
    a1, a3, b1, c2 = k[0], k[1], k[2], k[3]
    # (M2): eps_x = a1 + (3 a3 + 2 c2^2) x^2 - 2 z c2, eps_y = b1
    ex = {(0, 0): a1, (2, 0): 3 * a3 + 2 * c2 * c2, (0, 1): -2 * c2}
    ex2 = pmul(ex, ex)
    m = moments
    # linear laminae and ribs (M4), the channel void with a negative width
    lin = (
        0.5 * integrate(ex2, m["q11"])
        + b1 * integrate(ex, m["q12"])
        + 0.5 * b1 * b1 * float(m["q22"][0, 0])
    )
    # prestressed layer (M5): psi(eps0 + eps_x) + 1/2 E2 eps_y^2
    s = padd(ex, {(0, 0): EPS0})
    psi, power = {}, s
    for n, (p, sign) in enumerate(zip(PSI, (1, -1, 1, -1)), start=2):
        power = pmul(power, s)
        psi = padd(psi, power, sign * p / n)
    pre = integrate(psi, m["pre"]) + 0.5 * PEMC_E2 * b1 * b1 * float(m["pre"][0, 0])
    # gas volume (M7) and its potential (M8)
    volume = (1 + b1) * integrate(padd(ex, {(0, 0): 1.0}), m["gas"])
    return lin + pre - KAPPA * pressure * volume


def build_model(n):
    """SX functions of the scaled unknowns y (4N) and the load p = (P [MPa], Fx, Fz)."""
    length = LX / n
    unscale = [1.0, 1.0 / length**2, 1.0, 1.0 / length]  # scaled a1, a3 L^2, b1, c2 L
    y = ca.SX.sym("y", 4 * n)
    p = ca.SX.sym("p", 3)
    energy = 0
    theta = 0
    tip_x, tip_z = 0, 0
    for i in range(n):
        k = [y[4 * i + j] * unscale[j] for j in range(4)]
        energy = energy + element_energy(k, length, p[0], element_moments(i * length, length))
        a1, a3, c2 = k[0], k[1], k[3]
        # (M9), (M10)
        xe = (1 + a1) * length + a3 * length**3
        ze = c2 * length**2
        tip_x = tip_x + ca.cos(theta) * xe - ca.sin(theta) * ze
        tip_z = tip_z + ca.sin(theta) * xe + ca.cos(theta) * ze
        theta = theta + ca.atan2(2 * c2 * length, (1 + a1) + 3 * a3 * length**2)
    total = energy - p[1] * tip_x - p[2] * tip_z  # (M11), (M12)
    hess, grad = ca.hessian(total, y)
    fns = [
        ca.Function("ccm_all", [y, p], [total, grad, ca.densify(hess)]),
        ca.Function("ccm_energy", [y, p], [total]),
        ca.Function("ccm_tip", [y], [ca.vertcat(tip_x, tip_z)]),
    ]
    return fns, unscale


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--build", type=Path,
                    default=Path(os.environ.get("TMPDIR", tempfile.gettempdir())) / "fpc-peer",
                    help="directory for the generated C and the driver (default $TMPDIR/fpc-peer)")
    ap.add_argument("--elements", type=int, default=8, help="N, equal elements (default 8)")
    ap.add_argument("--cc", default=os.environ.get("CC", "gcc"), help="C compiler (default $CC or gcc)")
    ap.add_argument("--cflags", default="-O3", help="compiler flags (default -O3)")
    args = ap.parse_args()
    if not 1 <= args.elements <= 256:
        fail(f"--elements must lie in [1, 256], got {args.elements}")
    if shutil.which(args.cc) is None:
        fail(f"the C compiler `{args.cc}` is not on PATH (set --cc or CC)")
    out = args.build
    out.mkdir(parents=True, exist_ok=True)

    t0 = time.perf_counter()
    fns, unscale = build_model(args.elements)
    all_fn = fns[0]
    # stiffness scale of fpc's stopping rule: the largest (scaled) Hessian
    # diagonal of the unstrained, unloaded finger
    _, _, h0 = all_fn(np.zeros(4 * args.elements), np.zeros(3))
    stiffness = float(np.max(np.abs(np.diag(np.array(h0)))))
    t1 = time.perf_counter()

    cg = ca.CodeGenerator("ccm_gen.c", {"with_header": True})
    for f in fns:
        cg.add(f)
    cg.generate(str(out) + os.sep)
    with open(out / "peer_case.h", "w") as fh:
        fh.write("/* written by build_peer.py: the finger and the case */\n")
        fh.write(f"#define PEER_N {args.elements}\n")
        fh.write(f"#define PEER_STIFFNESS {stiffness!r}\n")
        fh.write(f"#define PEER_FX {FX!r}\n#define PEER_FZ {FZ!r}\n")
        fh.write("static const double PEER_UNSCALE[4] = {%s};\n" % ", ".join(repr(u) for u in unscale))
    shutil.copyfile(HERE / "driver.c", out / "driver.c")
    t2 = time.perf_counter()
    cmd = [args.cc, *args.cflags.split(), "-o", "driver", "driver.c", "ccm_gen.c", "-lm"]
    r = subprocess.run(cmd, cwd=out, capture_output=True, text=True)
    if r.returncode != 0:
        fail(f"`{' '.join(cmd)}` failed in {out}:\n{r.stderr}")
    t3 = time.perf_counter()
    print(f"N = {args.elements}: model and derivatives {t1 - t0:.1f} s, C generation {t2 - t1:.1f} s, "
          f"{args.cc} {args.cflags} {t3 - t2:.1f} s ({(out / 'ccm_gen.c').stat().st_size // 1024} KiB of C)")
    print(f"built {out / 'driver'}; run `{out / 'driver'} 2000` or `fpc-lab timing --peer {out}`")


if __name__ == "__main__":
    main()

"""Reproduces the paper's Sec. 6.2 figure (study 7 of docs/model.md): the
unloaded finger shapes for the three prestrains of the paper's samples, and
the curvature of the curl (the inverse of its radius, signed by its side)
against the channel pressure.

    python examples/python/paper_figure.py [OUT.png]

Needs the `fpc` module (pip install ./crates/python) and matplotlib; without
matplotlib it says so and exits 0. Writes paper_figure.png by default.
"""

import sys

try:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
except ImportError:
    print("paper_figure.py: matplotlib is not installed; skipped (pip install matplotlib)")
    sys.exit(0)

import numpy as np

import fpc


def main(out="paper_figure.png"):
    fig, (shapes, radius) = plt.subplots(1, 2, figsize=(11, 4.5))

    # (a) the unloaded shapes: one Finger.solve per prestrain
    for eps0 in fpc.PAPER_EPS0:
        r = fpc.Finger(eps0=eps0).solve()
        x, z = r["points"].T
        shapes.plot(x, z, label=f"eps0 = {eps0}")
        shapes.plot(*r["tip"], "o", color=shapes.lines[-1].get_color())
    shapes.axhline(0.0, color="grey", lw=0.8, ls="--")
    shapes.set_aspect("equal")
    shapes.set_xlabel("X (mm)")
    shapes.set_ylabel("Z (mm)")
    shapes.set_title("unloaded fingers (N = 8)")
    shapes.legend()

    # (b) the study's table: the signed curvature of the fitted circle
    # against pressure (radius = 1 / |curvature|; the sign is the side of
    # the curl, so the curve crosses zero where pressure straightens the
    # finger and the radius diverges)
    study = fpc.run_study("curvature")
    t = study["tables"]["study7"]
    ok = t["status"] == "ok"
    for eps0 in np.unique(t["eps0"][ok]):
        rows = ok & (t["eps0"] == eps0)
        order = np.argsort(t["pressure_kpa"][rows])
        radius.plot(
            t["pressure_kpa"][rows][order],
            1e3 * t["curvature_per_mm"][rows][order],
            marker=".",
            label=f"eps0 = {eps0}",
        )
    radius.axhline(0.0, color="grey", lw=0.8, ls="--")
    radius.set_xlabel("pressure (kPa)")
    radius.set_ylabel("curvature of the fitted circle (1/m)")
    radius.set_title(study["title"])
    radius.legend()

    fig.suptitle("fpc: the paper's Sec. 6.2 (study 7)")
    fig.tight_layout()
    fig.savefig(out, dpi=120)
    print(f"wrote {out}")


if __name__ == "__main__":
    main(*sys.argv[1:2])

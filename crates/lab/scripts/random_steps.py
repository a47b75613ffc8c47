"""Where a finger solve's Newton iterations go, on seeded random fingers
like those of issue 23 (eps0 0.1-0.5, 0-350 kPa, tip loads up to 1.5 N
per axis, N = 1, 8, 16): the report's `steps` (the unloaded start's
element iterations, the coupled Newton steps, those in continuation, and
the chord, shifted and damped steps among them), as order statistics.

    python3 crates/lab/scripts/random_steps.py target/release/fpc

docs/stress.md ("Where the iterations go") keeps the table.
"""

import json
import math
import random
import subprocess
import sys

CASES = 150


def quantile(v, f):
    v = sorted(v)
    return v[min(len(v), max(1, math.ceil(f * len(v)))) - 1]


def main(fpc):
    rng = random.Random(1)
    print("| N | solved | total median / p99 | coupled median / p90 / p99 / max | start median / p99 | chord median | shifted p99 | damped p99 |")
    print("|---|---|---|---|---|---|---|---|")
    for n in (1, 8, 16):
        reports, failed = [], 0
        for _ in range(CASES):
            eps0, kpa = rng.uniform(0.1, 0.5), rng.uniform(0, 350)
            fx, fz = rng.uniform(-1.5, 1.5), rng.uniform(-1.5, 1.5)
            out = subprocess.run(
                [fpc, "finger", "--eps0", f"{eps0}", "--pressure-kpa", f"{kpa}",
                 "--fx", f"{fx}", "--fz", f"{fz}", "--elements", str(n), "--json"],
                capture_output=True, text=True,
            )
            if out.returncode != 0:
                failed += 1
                continue
            reports.append(json.loads(out.stdout)["report"])
        steps = [r["steps"] for r in reports]
        total = [r["iterations"] for r in reports]
        coupled = [s["coupled"] + s["continuation"] for s in steps]
        start = [s["element"] for s in steps]
        print(
            f"| {n} | {len(reports)}/{len(reports) + failed} "
            f"| {quantile(total, .5)} / {quantile(total, .99)} "
            f"| {quantile(coupled, .5)} / {quantile(coupled, .9)} / {quantile(coupled, .99)} / {max(coupled)} "
            f"| {quantile(start, .5)} / {quantile(start, .99)} "
            f"| {quantile([s['chord'] for s in steps], .5)} "
            f"| {quantile([s['shifted'] for s in steps], .99)} "
            f"| {quantile([s['damped'] for s in steps], .99)} |"
        )


if __name__ == "__main__":
    main(sys.argv[1] if len(sys.argv) > 1 else "fpc")

#!/usr/bin/env python3
"""The tables of docs/stress.md's "Results" section, from the JSON reports
of `fpc-lab stress --json --all-cases` (one file per seed).

Usage: python3 crates/lab/scripts/stress_tables.py REPORT.json...

Prints Markdown: one row per seed, the totals, legal cases by partition
and by element model, the outside cases by relative load, stack scale,
pressure and curl, and the counts the section's bullets quote.
"""

import json
import sys
from collections import Counter


def pct(a, b):
    return f"{100.0 * a / b:.2f} %" if b else "-"


def row(cells):
    return "| " + " | ".join(str(c) for c in cells) + " |"


def converged(c):
    return c["outcome"] != "failed" and c["outcome"] != "rejected"


def tally(cases):
    """cases, converged, with findings, failed"""
    n = len(cases)
    ok = [c for c in cases if converged(c)]
    warned = sum(1 for c in ok if c["findings"])
    failed = sum(1 for c in cases if c["outcome"] == "failed")
    return n, len(ok), warned, failed


def binned(title, cases, key, edges, label):
    print(f"| {title} | outside cases | converged | with findings | failed |")
    print("|---|---|---|---|---|")
    for lo, hi in edges:
        sel = [c for c in cases if lo <= key(c) < hi or (lo == hi == key(c))]
        n, ok, warned, failed = tally(sel)
        print(row([label(lo, hi), n, f"{ok} ({pct(ok, n)})", warned, f"{failed} ({pct(failed, n)})"]))
    print()


# The generator's strip: the default length and width (mm), which it does
# not vary (a drawn partition's lengths add up to LX).
LX, LY = 110.0, 31.75


def conditions(c, env):
    """Whether each condition of the envelope holds."""
    i = c["inputs"]
    longest = max(i["lengths_mm"]) / LX if i["lengths_mm"] else 0.0
    return {
        "thickness": i["h_mm"] <= env["max_thickness_over_lx"] * LX
        and i["h_mm"] <= env["max_thickness_over_ly"] * LY,
        "eps0": i["eps0"] <= env["max_eps0"],
        "P": i["pressure_kpa"] <= env["max_pressure_kpa"],
        "curl": abs(i["curl"]) <= env["max_curl"],
        "load": i["load_strain"] <= env["max_load_strain_over_eps0"] * i["eps0"],
        "part": i["partition"] == "auto" or longest <= env["max_element_fraction"] * (1 + 1e-12),
        "jitter": not i["jittered"],
    }


def margins(cases, env):
    """Each condition relaxed alone, the others held."""
    inf = float("inf")
    bins = {
        "eps0": (lambda i: i["eps0"], [0, 0.3, 0.4, 0.45, 0.5, 0.55, inf]),
        "P": (lambda i: i["pressure_kpa"], [0, 300, 350, 400, 450, 500, 550, inf]),
        "curl": (lambda i: abs(i["curl"]), [0, 5, 6, 6.5, 7, 7.5, 8, 9, 10, 15, inf]),
        "load": (lambda i: i["load_strain"] / i["eps0"], [0, 0.05, 0.1, 0.15, 0.2, 0.25, 0.3, 0.5, 1, inf]),
        "part": (lambda i: inf if i["partition"] == "auto" else sum(i["lengths_mm"]) / max(i["lengths_mm"]),
                 [0, 2, 4, 6, 8, 10, 12, 16, inf, inf]),
        "jitter": (lambda i: 1 if i["jittered"] else 0, [0, 1, 2]),
        "thickness": (lambda i: i["h_mm"] / LX, [0, 0.05, 0.1, 0.15, 0.2, inf]),
    }
    for c in cases:
        if c["inputs"]["lengths_mm"]:
            assert abs(sum(c["inputs"]["lengths_mm"]) - LX) < 1e-9 * LX, "the strip's length moved"
    held = [(c, conditions(c, env)) for c in cases]
    inside = sum(1 for c, ok in held if all(ok.values()))
    assert inside == sum(1 for c in cases if c["inside_envelope"]), "the conditions differ from the harness's"
    for name, (key, edges) in bins.items():
        sel = [c for c, ok in held if all(v for k, v in ok.items() if k != name)]
        print(f"| {name} relaxed: bin | cases | converged, no findings | with findings | failed | findings |")
        print("|---|---|---|---|---|---|")
        for lo, hi in zip(edges, edges[1:]):
            if name == "part" and lo == inf:
                b = [c for c in sel if c["inputs"]["partition"] == "auto"]
                label = "auto"
            else:
                b = [c for c in sel if lo <= key(c["inputs"]) < hi and not (name == "part" and c["inputs"]["partition"] == "auto")]
                label = f"[{lo:g}, {hi:g})" if name != "jitter" else ("no" if lo == 0 else "yes")
            n, ok, warned, failed = tally(b)
            kinds = Counter(f for c in b if converged(c) for f in set(c["findings"]))
            print(row([label, n, f"{ok - warned} ({pct(ok - warned, n)})", warned, failed,
                       ", ".join(f"{k} {v}" for k, v in sorted(kinds.items()))]))
        print()


def main(paths):
    reports = [json.load(open(p)) for p in paths]
    reports.sort(key=lambda r: r["seed"])
    cases = [c for r in reports for c in r["cases"]]
    legal = [c for c in cases if c["outcome"] != "rejected"]
    inside = [c for c in legal if c["inside_envelope"]]
    outside = [c for c in legal if not c["inside_envelope"]]

    print("| seed | cases | inside | inside converged | inside warned | outside | outside converged "
          "| outside warned | outside failed (MaxIterations / StepTolerance / other) | panics "
          "| silently wrong | wrong stability | stability checked (dense) | time (s) |")
    print("|" + "---|" * 14)
    total = Counter()
    for r in reports:
        ins, out = r["inside_envelope"], r["outside_envelope"]
        reasons = out["failed_by_reason"]
        mi, st = reasons.get("MaxIterations", 0), reasons.get("StepTolerance", 0)
        other = out["failed"] - mi - st
        print(row([r["seed"], r["cases_run"], ins["cases"],
                   f"{ins['converged']} ({pct(ins['converged'], ins['cases'])})", ins["warned"],
                   out["cases"], f"{out['converged']} ({pct(out['converged'], out['cases'])})",
                   out["warned"], f"{out['failed']} ({mi} / {st} / {other})", r["panics"],
                   r["silently_wrong"], r["wrong_stability"], r["stability_checked"],
                   round(r["elapsed_s"])]))
        for k, v in [("cases", r["cases_run"]), ("in", ins["cases"]), ("in_ok", ins["converged"]),
                     ("in_w", ins["warned"]), ("out", out["cases"]), ("out_ok", out["converged"]),
                     ("out_w", out["warned"]), ("out_f", out["failed"]), ("mi", mi), ("st", st),
                     ("other", other), ("panics", r["panics"]), ("sw", r["silently_wrong"]),
                     ("ws", r["wrong_stability"]), ("dense", r["stability_checked"]),
                     ("time", r["elapsed_s"])]:
            total[k] += v
    t = total
    print(row(["**total**", f"**{t['cases']}**", f"**{t['in']}**",
               f"**{t['in_ok']} ({pct(t['in_ok'], t['in'])})**", f"**{t['in_w']}**", f"**{t['out']}**",
               f"**{t['out_ok']} ({pct(t['out_ok'], t['out'])})**", f"**{t['out_w']}**",
               f"**{t['out_f']} ({t['mi']} / {t['st']} / {t['other']})**", f"**{t['panics']}**",
               f"**{t['sw']}**", f"**{t['ws']}**", f"**{t['dense']}**", f"**{round(t['time'])}**"]))
    print()

    print("| | cases | converged | converged without findings | with findings | failed |")
    print("|---|---|---|---|---|---|")
    for name, sel in [("inside the envelope", inside), ("outside the envelope", outside), ("all", legal)]:
        n, ok, warned, failed = tally(sel)
        print(row([name, n, f"{ok} ({pct(ok, n)})", ok - warned, warned, f"{failed} ({pct(failed, n)})"]))
    print()

    def group_table(title, key, order):
        print(f"| {title} | cases | converged | with findings | failed | inside | inside converged cleanly |")
        print("|---|---|---|---|---|---|---|")
        for g in order:
            sel = [c for c in legal if key(c) == g]
            n, ok, warned, failed = tally(sel)
            ins = [c for c in sel if c["inside_envelope"]]
            clean = sum(1 for c in ins if converged(c) and not c["findings"])
            print(row([g, n, f"{ok} ({pct(ok, n)})", warned, failed, len(ins), clean]))
        print()

    part = lambda c: "auto" if c["inputs"]["partition"] == "auto" else str(c["inputs"]["elements"])
    ns = sorted({part(c) for c in legal}, key=lambda k: (k == "auto", int(k) if k != "auto" else 0))
    group_table("N", part, ns)
    model = lambda c: c["inputs"]["model"]
    group_table("model", model, sorted({model(c) for c in legal}))

    inf = float("inf")
    binned("relative load f", outside, lambda c: c["inputs"]["relative_load"],
           [(0, 0), (1e-300, 0.01), (0.01, 0.1), (0.1, 1), (1, 3), (3, 10), (10, inf)],
           lambda lo, hi: "0 (none)" if hi == 0 else "(0, 0.01)" if lo < 1e-100 else f"[{lo:g}, {hi:g})")
    binned("stack scale s", outside, lambda c: c["inputs"]["thickness_scale"],
           [(0.3, 0.5), (0.5, 0.7), (0.7, 1), (1, 1.5), (1.5, 2), (2, inf)],
           lambda lo, hi: f"[{lo:g}, {hi:g})")
    binned("pressure kPa", outside, lambda c: c["inputs"]["pressure_kpa"],
           [(0, 0), (1e-300, 100), (100, 200), (200, 300), (300, 400), (400, 500), (500, inf)],
           lambda lo, hi: "0" if hi == 0 else "(0, 100)" if lo < 1e-100 else f"[{lo:g}, {hi:g})")
    binned("\\|curl\\|", outside, lambda c: abs(c["inputs"]["curl"]),
           [(0, 3), (3, 6.5), (6.5, 10), (10, 20), (20, inf)], lambda lo, hi: f"[{lo:g}, {hi:g})")

    margins(legal, reports[0]["envelope"])

    failed = [c for c in legal if c["outcome"] == "failed"]
    print("failures by reason:", dict(Counter(c["reason"] for c in failed)))
    print("failed without a tip load (decoupled element solves):",
          sum(1 for c in failed if c["inputs"]["relative_load"] == 0), "with one:",
          sum(1 for c in failed if c["inputs"]["relative_load"] != 0))
    print("failed by partition:", dict(Counter(part(c) for c in failed)))
    findings = Counter(f for c in outside if converged(c) for f in set(c["findings"]))
    print("findings outside (converged cases, once per kind):", dict(findings.most_common()))
    print("findings inside:", [(r["seed"], c["index"], c["findings"]) for r in reports
                               for c in r["cases"] if c["inside_envelope"] and c["findings"]])
    rejected = Counter()
    for r in reports:
        rejected.update(r["rejected_draws_by_field"])
    print("rejected draws:", sum(r["rejected_draws"] for r in reports), dict(rejected))
    autos = [c for c in legal if part(c) == "auto"]
    ends = Counter("failed" if c["outcome"] == "failed" else
                   "stopped at a fold" if "partition_fold" in c["notes"] else
                   "kept the last partition after a failed split" if "partition_split_failed" in c["notes"] else
                   "beyond the slope limit" if "element_slope" in c["findings"] else
                   "within the slope limit" for c in autos)
    print("automatic partitions end:", dict(ends.most_common()))
    missed = Counter(f for c in cases for f in c["missed_findings"])
    print("findings missed at 32 samples:", sum(1 for c in cases if c["missed_findings"]), dict(missed))
    worst = max(reports, key=lambda r: r["largest_residual"])
    print("largest residual:", worst["largest_residual"], "seed", worst["seed"], "case",
          worst["largest_residual_case"])
    cond = [r for r in reports if r["worst_conditioning"] is not None]
    if cond:
        w = min(cond, key=lambda r: r["worst_conditioning"])
        print("worst lmin/G:", w["worst_conditioning"], "seed", w["seed"], "case", w["worst_conditioning_case"])
    print("unstable:", sum(r["unstable"] for r in reports), "stability unknown:",
          sum(r["stability_unknown"] for r in reports), "budget stopped a run:",
          any(r["stopped_early"] for r in reports))
    secs = sorted(c["seconds"] or 0 for c in cases)
    slow = max(((r["seed"], c) for r in reports for c in r["cases"]), key=lambda x: x[1]["seconds"] or 0)
    print(f"case seconds: mean {1e3 * sum(secs) / len(secs):.2f} ms, median {1e3 * secs[len(secs) // 2]:.2f} ms, "
          f"p99 {1e3 * secs[int(0.99 * len(secs))]:.1f} ms, slowest {slow[1]['seconds']:.2f} s "
          f"(seed {slow[0]} case {slow[1]['index']}, {part(slow[1])}, {slow[1]['outcome']})")
    steps = sorted(c["steps"]["coupled"] for c in legal
                   if converged(c) and c.get("steps") and c["steps"]["coupled"] > 0)
    if steps:
        q = lambda p: steps[min(len(steps) - 1, int(p * len(steps)))]
        print(f"coupled steps: n {len(steps)} median {q(0.5)} p90 {q(0.9)} p99 {q(0.99)} max {steps[-1]}")
    print("seconds per run:", round(sum(r["elapsed_s"] for r in reports), 1))


if __name__ == "__main__":
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    main(sys.argv[1:])

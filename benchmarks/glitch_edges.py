"""One glitch, wherever it is: R, the reported sample and the verdict (issue 26, glitch26).

    python benchmarks/glitch_edges.py                       # this tree
    python benchmarks/glitch_edges.py --against /tmp/base   # and another tree (before)

Three parts, each seeded:

1. the brief's record: a slow walk (steps of std 1e-3) + white noise std 4e-4, 3000
   samples, seed 0, and one 0.22 glitch at sample 0, 1, 5, 300 or n-1 (or none): R, its
   interval, the outlying sample reported, the verdict's class;
2. real_audit2's airspeed-like record (600 samples, walk std 0.01, noise 4e-4, a -0.22
   glitch) at samples 0, 1, 5, 300 with ``auto`` alone and the coloured span (5);
3. a scan: 60 records (white noise, or white noise + ``synth.motion_bursts``), one glitch of
   20-300 sigma at 10 places near either edge and one inside away from the bursts: the
   largest |R_edge - R_inside| over the glitch's own share delta^2 / n, and how often
   R_edge is outside R_inside's ci95 and the glitch is not reported at its sample.

Each tree runs in a child process (``PYTHONPATH``); results: benchmarks/results/glitch_edges.md.
"""

from __future__ import annotations

import argparse
import json
import os
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "benchmarks" / "results" / "glitch_edges.md"


def _child() -> dict:  # noqa: C901 (one measurement script)
    import numpy as np

    import noisevar
    from noisevar.estimators.auto.core import auto_estimate, auto_part, auto_spans
    from noisevar.synth import motion_bursts

    def first_at(r) -> int | None:
        for k in r.notes:
            m = re.search(r"outlying samples? \([^;]*; the first at sample (\d+)", k)
            if m:
                return int(m.group(1))
        return None

    rng = np.random.default_rng(0)
    n = 3000
    x = np.cumsum(rng.normal(0, 1e-3, n)) + rng.normal(0, 4e-4, n)
    brief = []
    for k in (None, 0, 1, 5, 300, n - 1):
        y = x.copy()
        if k is not None:
            y[k] += 0.22
        r = noisevar.estimate(y)
        v = r.diagnostics.verdict
        lead = "outliers hold R; " if "outlying and hold" in v else ""  # said after the finding
        v = v.split("; without them, ")[-1]
        brief.append(
            {"at": k, "R": r.variance, "ci": list(r.ci95), "first": first_at(r),
             "verdict": lead + v.split(":")[0] + ":" + v.split(":")[1][:40]}
        )  # fmt: skip

    air = []
    for k in (0, 1, 5, 300):
        r2 = np.random.default_rng(0)
        z = np.cumsum(r2.normal(0.0, 0.01, 600)) + r2.normal(0.0, 4e-4, 600)
        z[k] -= 0.22
        air.append(
            {"at": k, "R": noisevar.estimate(z).variance,
             "auto": auto_estimate(z).variance, "span5": auto_estimate(z, span=5).variance}
        )  # fmt: skip

    scan = {"share": [], "outside": 0, "missed": 0, "cases": 0}
    for seed in range(60):
        g = np.random.default_rng(1000 + seed)
        m = int(g.integers(1500, 4000))
        motion = motion_bursts(m, g) if seed % 2 else np.zeros(m)
        base = g.normal(size=m) + motion
        delta = g.uniform(20, 300) * g.choice([-1.0, 1.0])
        still = np.convolve(motion != 0, np.ones(301), mode="same") == 0
        still[:200] = still[-200:] = False
        mid = int(g.choice(np.flatnonzero(still)))
        for span in (None, 5):
            y = base.copy()
            y[mid] += delta
            ri = auto_estimate(y, span=span)
            for k in (0, 1, 2, 3, 5, 8, m - 4, m - 3, m - 2, m - 1):
                y = base.copy()
                y[k] += delta
                r = auto_estimate(y, span=span)
                scan["share"].append(abs(r.variance - ri.variance) / (delta**2 / m))
                scan["outside"] += not ri.ci95[0] <= r.variance <= ri.ci95[1]
                spans = auto_spans(span, 3, 5.0, m)
                scan["missed"] += k not in auto_part(y, spans, 3, 5.0).outliers
                scan["cases"] += 1
    share = np.asarray(scan.pop("share"))
    scan |= {"max": float(share.max()), "p95": float(np.quantile(share, 0.95))}
    return {"brief": brief, "air": air, "scan": scan, "cpu": time.process_time()}


def _run(tree: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(tree))
    out = subprocess.run(
        [sys.executable, __file__, "--child"], env=env, capture_output=True, text=True, check=True
    )
    return json.loads(out.stdout.strip().splitlines()[-1])


def _table(name: str, res: dict) -> list[str]:
    lines = [f"### {name}", "", "| glitch at | R | ci95 | first outlier reported | verdict |"]
    lines.append("|---|---|---|---|---|")
    for b in res["brief"]:
        at = "none" if b["at"] is None else b["at"]
        lines.append(
            f"| {at} | {b['R']:.3g} | {b['ci'][0]:.3g} - {b['ci'][1]:.3g} | {b['first']} "
            f"| {b['verdict']} |"
        )
    lines += ["", "| airspeed-like, glitch at | estimate() R | auto R | auto span 5 R |"]
    lines.append("|---|---|---|---|")
    for a in res["air"]:
        lines.append(f"| {a['at']} | {a['R']:.3g} | {a['auto']:.3g} | {a['span5']:.3g} |")
    s = res["scan"]
    lines += [
        "",
        f"Scan ({s['cases']} cases: 60 records x 10 edge places x spans auto / 5): "
        f"|R_edge - R_inside| / (delta^2/n) max {s['max']:.2f}, 95th percentile "
        f"{s['p95']:.2f}; R_edge outside R_inside's ci95 in {s['outside']}; glitch not "
        f"reported at its sample in {s['missed']}. CPU {res['cpu']:.0f} s.",
        "",
    ]
    return lines


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    ap.add_argument("--against", type=Path, help="another tree to run the same on (before)")
    args = ap.parse_args()
    if args.child:
        print(json.dumps(_child()))
        return
    load = os.getloadavg()[0]
    lines = [
        "# One glitch, wherever it is (issue 26, glitch26)",
        "",
        f"`python benchmarks/glitch_edges.py{' --against DIR' if args.against else ''}`, "
        f"load {load:.1f}.",
        "",
    ]
    if args.against:
        lines += _table(f"before ({args.against})", _run(args.against))
    lines += _table("this tree", _run(ROOT))
    OUT.write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()

"""R when the whiteness test sits near the coloured-noise threshold (issue 26, item 4).

    python benchmarks/colour_edge.py [--seeds 20]

A seeded family of AR(1) records (φ 0.08, 0.10, 0.12, 0.15; n 300, 600, 1000, 2000;
``z = slow sine + AR(1)`` of innovation σ = 1) whose whiteness p-value falls either side of
``COLOURED_P`` = 1e-4. For each record, R of the whole record and of the record without its
first 1, 2 or 3 samples: a record *moves* when one of these R lies outside the other's
ci95 (either way). Coverage: the whole record's ci95 against the per-sample variance
``1 / (1 - φ²)`` and against the white innovation's variance 1. Run before (the abrupt
switch, ``EDGE_FACTOR`` = 1) and after (``EDGE_FACTOR`` as shipped). Also: how far log10 p
moves when 1-3 samples are dropped (the band's width), and CPU seconds. Results go to
benchmarks/results/colour_edge.md.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.signal import lfilter

import noisevar
from noisevar.estimators import interval

OUT = Path(__file__).resolve().parent / "results" / "colour_edge.md"
PHIS = (0.08, 0.10, 0.12, 0.15)
NS = (300, 600, 1000, 2000)
NEAR = (1e-6, 1e-2)  # a record is near the threshold when a version's p is in here


def record(phi: float, n: int, seed: int) -> np.ndarray:
    """A slow sine plus AR(1) noise of innovation σ = 1 (seeded)."""
    rng = np.random.default_rng([seed, n, int(phi * 1000)])
    t = np.arange(n)
    signal = 5.0 * np.sin(2 * np.pi * t / (n / rng.uniform(1.5, 3.0)) + rng.uniform(0, 6))
    return signal + lfilter([1.0], [1.0, -phi], rng.normal(size=n))


def run(seeds: int, factor: float) -> tuple[list[dict], float]:
    """Every record of the family at band ``factor``: the rows and the CPU seconds."""
    interval.EDGE_FACTOR = factor
    rows = []
    cpu = time.process_time()
    for phi in PHIS:
        for n in NS:
            for seed in range(seeds):
                z = record(phi, n, seed)
                ests = [noisevar.estimate(z[k:]) for k in range(4)]
                p = [e.diagnostics.whiteness.p_value for e in ests]
                r = [e.variance for e in ests]
                ci = [e.ci95 for e in ests]
                moved = any(
                    not (ci[0][0] <= r[k] <= ci[0][1] and ci[k][0] <= r[0] <= ci[k][1])
                    for k in (1, 2, 3)
                )
                rows.append({
                    "phi": phi, "n": n, "p": p, "moved": moved,
                    "cover_sample": ci[0][0] <= 1 / (1 - phi**2) <= ci[0][1],
                    "cover_white": ci[0][0] <= 1.0 <= ci[0][1],
                    "near": any(NEAR[0] <= q <= NEAR[1] for q in p),
                    "straddles": min(p) < 1e-4 <= max(p),
                })  # fmt: skip
    return rows, time.process_time() - cpu


def pct(rows: list[dict], key: str) -> str:
    """The percentage of ``rows`` whose ``key`` is true, with the count."""
    k = sum(r[key] for r in rows)
    return f"{100 * k / max(len(rows), 1):.1f} % ({k}/{len(rows)})"


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=20)
    args = ap.parse_args()
    shipped = interval.EDGE_FACTOR
    lines = [
        "# R near the coloured-noise threshold (benchmarks/colour_edge.py)",
        "",
        f"AR(1) + slow sine, φ {PHIS}, n {NS}, {args.seeds} seeds each "
        f"({len(PHIS) * len(NS) * args.seeds} records, 4 estimates each). "
        "moved: R of the record and R without its first 1-3 samples outside each other's "
        "ci95. near: a version's whiteness p in [1e-6, 1e-2]; straddles: the versions' p on "
        "both sides of 1e-4.",
        "",
        "| band | records | moved | moved (near) | moved (straddles) | covers 1/(1-φ²) "
        "| covers 1 (white part) | CPU s |",
        "|---|---|---|---|---|---|---|---|",
    ]
    spread = []
    for label, factor in (("before (switch)", 1.0), (f"after (x{shipped:g})", shipped)):
        rows, cpu = run(args.seeds, factor)
        near = [r for r in rows if r["near"]]
        strad = [r for r in rows if r["straddles"]]
        lines.append(
            f"| {label} | {len(rows)} | {pct(rows, 'moved')} | {pct(near, 'moved')} "
            f"| {pct(strad, 'moved')} | {pct(rows, 'cover_sample')} "
            f"| {pct(rows, 'cover_white')} | {cpu:.1f} |"
        )
        spread = [abs(np.log10(q) - np.log10(r["p"][0])) for r in near for q in r["p"][1:] if q > 0]
    q = np.percentile(spread, [50, 90, 95, 99])
    lines += [
        "",
        f"|log10 p(dropped) - log10 p(record)| on the near records ({len(spread)} pairs): "
        f"median {q[0]:.2f}, 90 % {q[1]:.2f}, 95 % {q[2]:.2f}, 99 % {q[3]:.2f} "
        f"(the band: log10 {shipped:g} = {np.log10(shipped):.2f} either side).",
    ]
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

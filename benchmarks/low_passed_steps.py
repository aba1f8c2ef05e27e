"""Level steps in noise low-passed by the sensor (issue 26): are they jumps, and does R stay?

    python benchmarks/low_passed_steps.py            # 40 seeds per cell, n = 20,000

AR(1) noise of lag-one correlation ``a`` (unit variance), with 20 level steps of ``size``
noise standard deviations at random places (or none). Per cell: the share of the record
left out "around level jumps" on the noise alone, how many of the 20 steps are jumps (left
out), and R with the steps over R without them (median and worst; inside R's own ci95).
Writes ``benchmarks/results/low_passed_steps.md``.
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.signal import lfilter

import noisevar

OUT = Path(__file__).resolve().parent / "results" / "low_passed_steps.md"
N, STEPS = 20_000, 20


def record(a: float, seed: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = lfilter([1.0], [1.0, -a], rng.normal(size=N)) * np.sqrt(1.0 - a * a)
    return x, np.sort(rng.choice(np.arange(200, N - 200), STEPS, replace=False))


def found(e: noisevar.VarianceEstimate, at: np.ndarray) -> int:
    """How many of the steps ``at`` lie in the samples left out around jumps."""
    return 0 if e.jumps is None else int(np.count_nonzero(e.jumps[at]))


def cell(a: float, size: float, seeds: int) -> dict:
    left, hits, ratio, inside = [], [], [], []
    for s in range(seeds):
        x, at = record(a, s)
        plain = noisevar.estimate(x)
        left.append(0.0 if plain.jumps is None else plain.jumps.mean())
        z = x + size * np.searchsorted(at, np.arange(N), side="right")
        e = noisevar.estimate(z)
        hits.append(found(e, at))
        ratio.append(e.variance / plain.variance)
        inside.append(plain.ci95[0] <= e.variance <= plain.ci95[1])
    r = np.array(ratio)
    return {
        "a": a, "size": size, "left": float(np.mean(left)), "hits": float(np.mean(hits)),
        "median": float(np.median(r)), "worst": float(r[np.argmax(np.abs(np.log(r)))]),
        "inside": float(np.mean(inside)),
    }  # fmt: skip


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    t0 = time.time()
    cells = [(a, size) for a in (0.0, 0.5, 0.8, 0.9, 0.95, 0.98) for size in (50.0, 1e4)]
    rows = [cell(a, size, args.seeds) for a, size in cells]
    lines = [
        "# Level steps in low-passed noise (issue 26)",
        "",
        f"`python benchmarks/low_passed_steps.py --seeds {args.seeds}`: AR(1) noise of lag-one "
        f"correlation a (unit variance), n = {N}, {STEPS} level steps of the size given (noise "
        f"standard deviations); {args.seeds} seeds per row; {time.time() - t0:.0f} s.",
        "",
        "| a | step | left out as jumps, noise alone | steps found (of 20) | R with / without the "
        "steps: median | worst | inside R's ci95 |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['a']} | {r['size']:g} | {r['left']:.1%} | {r['hits']:.1f} | "
            f"{r['median']:.4g} | {r['worst']:.4g} | {r['inside']:.0%} |"
        )
    args.out.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

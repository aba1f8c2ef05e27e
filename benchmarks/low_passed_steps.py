"""Level steps in noise low-passed by the sensor (issue 26): are they jumps, and does R stay?

    python benchmarks/low_passed_steps.py            # 40 seeds per cell
    python benchmarks/low_passed_steps.py --sizes 20000:20 1000:2

AR(1) noise of lag-one correlation ``a`` (unit variance), with level steps of ``size``
noise standard deviations at random places (or none): per record size ``n:steps``, 20 in
20,000 samples (a grid of 78 blocks) and 2 in 1,000 (a record shorter than 2,048 samples,
whose grid has 3 blocks). Per cell: the share of the record
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
SIZES = ("20000:20", "1000:2")


def record(a: float, seed: int, n: int, steps: int) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = lfilter([1.0], [1.0, -a], rng.normal(size=n)) * np.sqrt(1.0 - a * a)
    edge = min(200, n // 10)
    return x, np.sort(rng.choice(np.arange(edge, n - edge), steps, replace=False))


def found(e: noisevar.VarianceEstimate, at: np.ndarray) -> int:
    """How many of the steps ``at`` lie in the samples left out around jumps."""
    return 0 if e.jumps is None else int(np.count_nonzero(e.jumps[at]))


def cell(a: float, size: float, seeds: int, n: int, steps: int) -> dict:
    left, hits, ratio, inside = [], [], [], []
    for s in range(seeds):
        x, at = record(a, s, n, steps)
        plain = noisevar.estimate(x)
        left.append(0.0 if plain.jumps is None else plain.jumps.mean())
        z = x + size * np.searchsorted(at, np.arange(n), side="right")
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


def table(n: int, steps: int, seeds: int) -> list[str]:
    t0 = time.time()
    cells = [(a, size) for a in (0.0, 0.5, 0.8, 0.9, 0.95, 0.98) for size in (50.0, 1e4)]
    rows = [cell(a, size, seeds, n, steps) for a, size in cells]
    lines = [
        f"n = {n}, {steps} level steps of the size given (noise standard deviations); "
        f"{seeds} seeds per row; {time.time() - t0:.0f} s.",
        "",
        f"| a | step | left out as jumps, noise alone | steps found (of {steps}) | R with / "
        "without the steps: median | worst | inside R's ci95 |",
        "|---|---|---|---|---|---|---|",
    ]
    for r in rows:
        lines.append(
            f"| {r['a']} | {r['size']:g} | {r['left']:.1%} | {r['hits']:.1f} | "
            f"{r['median']:.4g} | {r['worst']:.4g} | {r['inside']:.0%} |"
        )
    return [*lines, ""]


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=40)
    ap.add_argument("--sizes", nargs="+", default=list(SIZES), help="n:steps per table")
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args()
    lines = [
        "# Level steps in low-passed noise (issue 26)",
        "",
        f"`python benchmarks/low_passed_steps.py --seeds {args.seeds} --sizes "
        f"{' '.join(args.sizes)}`: AR(1) noise of lag-one correlation a (unit variance).",
        "",
    ]
    for size in args.sizes:
        n, steps = (int(v) for v in size.split(":"))
        lines += table(n, steps, args.seeds)
    args.out.write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()

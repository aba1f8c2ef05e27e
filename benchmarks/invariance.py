"""Invariance of R on motion-burst records: transforms that change nothing must not move R.

    python benchmarks/invariance.py [--records 200] [--n 20000] [--seed 1]

Each record is white noise (σ = 1) on a slow signal, with one to three bursts of motion
(a fast oscillation, jerky steps, or taps that ring; random amplitude and length). For
each transform (reversal, dropping 1, 2 or 3 leading samples, sign flip, scale x1e3, an
offset, a linear trend) the benchmark counts the records whose transformed R lies inside
the original R's ci95 (the issue 26 target: at least 95 % for every transform). Results
go to benchmarks/results/invariance.md.
"""

from __future__ import annotations

import argparse
from collections.abc import Callable
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

import noisevar
from noisevar import synth

OUT = Path(__file__).resolve().parent / "results" / "invariance.md"


def burst_record(n: int, rng: np.random.Generator) -> NDArray:
    """White noise (σ = 1) on a slow sine, with 1-3 bursts of motion (synth.motion_bursts)."""
    t = np.arange(n)
    z = 3.0 * np.sin(2 * np.pi * t / rng.uniform(2000, 8000)) + rng.normal(0.0, 1.0, n)
    return z + synth.motion_bursts(n, rng)


def transforms(n: int) -> dict[str, Callable[[NDArray], NDArray]]:
    ramp = np.linspace(0.0, 50.0, n)
    return {
        "reversed": lambda z: z[::-1],
        "drop 1": lambda z: z[1:],
        "drop 2": lambda z: z[2:],
        "drop 3": lambda z: z[3:],
        "sign": lambda z: -z,
        "scale x1e3": lambda z: 1e3 * z,
        "offset +1e4": lambda z: z + 1e4,
        "linear trend": lambda z: z + ramp[: z.size],
    }


def run(records: int, n: int, seed: int) -> dict[str, float]:
    rng = np.random.default_rng(seed)
    inside = {k: 0 for k in transforms(n)}
    for _ in range(records):
        z = burst_record(n, rng)
        est = noisevar.estimate(z)
        lo, hi = est.ci95
        for name, f in transforms(n).items():
            scale = 1e6 if name == "scale x1e3" else 1.0
            v = noisevar.estimate(f(z)).variance / scale
            inside[name] += lo <= v <= hi
    return {k: v / records for k, v in inside.items()}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=200)
    ap.add_argument("--n", type=int, default=20000)
    ap.add_argument("--seed", type=int, default=1)
    a = ap.parse_args()
    share = run(a.records, a.n, a.seed)
    lines = [
        "# Invariance of R on motion-burst records",
        "",
        f"`python benchmarks/invariance.py --records {a.records} --n {a.n} --seed {a.seed}`",
        "",
        "| transform | R inside the original's ci95 | target | pass |",
        "|---|---|---|---|",
        *(
            f"| {k} | {v:.1%} | >= 95 % | {'yes' if v >= 0.95 else 'no'} |"
            for k, v in share.items()
        ),
    ]
    OUT.parent.mkdir(parents=True, exist_ok=True)
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

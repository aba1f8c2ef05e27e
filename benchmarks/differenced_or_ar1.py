"""Differenced data or AR(1) noise: from what length the two are told apart (issue 26, §E2).

    python benchmarks/differenced_or_ar1.py [--runs 100]

Seeded records (seeds 20000 on) of white noise through ``np.diff`` and of AR(1) noise of
φ = -0.4 to -0.9 at 300 to 5,000 samples: how often ``auto``'s diagnostics name
AR(1) noise (``ar1_phi``), say either (``differenced_or_ar1``), say differenced, name an
oscillation, or none; R over the per-sample variance (2 for differenced unit white
noise, ``1 / (1 - φ²)`` for AR(1) of unit innovations) and how often R's ci95 covers it.
``--kinds`` runs some rows only (their first words: ``np.diff``, ``-0.7``). Writes
``benchmarks/results/differenced_or_ar1.md`` (or ``--out``).
"""

from __future__ import annotations

import argparse
import time
from pathlib import Path

import numpy as np
from scipy.signal import lfilter

import noisevar as nv
from noisevar.diagnostics.verdict_parts import found_oscillation

LENGTHS = (300, 500, 1000, 2000, 3000, 5000)
KINDS = (
    "np.diff of white noise",
    *(f"AR(1), phi {p}" for p in ("-0.4", "-0.5", "-0.6", "-0.7", "-0.8", "-0.9")),
)
CALLS = ("AR(1)", "either", "differenced", "oscillation", "none")


def record(kind: str, n: int, seed: int) -> tuple[np.ndarray, float]:
    """The record and its per-sample variance."""
    rng = np.random.default_rng(seed)
    if kind.startswith("np.diff"):
        return np.diff(rng.normal(size=n + 1)), 2.0
    phi = float(kind.split("phi ")[1])
    return lfilter([1.0], [1.0, -phi], rng.normal(size=n)), 1.0 / (1.0 - phi**2)


def call(d) -> str:
    """What the diagnostics say the record is."""
    if d.ar1_phi is not None:
        return "AR(1)"
    if d.differenced_or_ar1:
        return "either"
    if d.differenced:
        return "differenced"
    return "oscillation" if found_oscillation(d.whiteness) is not None else "none"


def _picked(args: argparse.Namespace) -> str:
    """The rows picked on the command line, as written there."""
    kinds = f" --kinds {' '.join(args.kinds)}" if args.kinds else ""
    lengths = (
        "" if tuple(args.lengths) == LENGTHS else f" --lengths {' '.join(map(str, args.lengths))}"
    )
    return kinds + lengths


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--runs", type=int, default=100)
    ap.add_argument("--kinds", nargs="*", default=None)
    ap.add_argument("--lengths", nargs="*", type=int, default=LENGTHS)
    ap.add_argument(
        "--out", default=str(Path(__file__).parent / "results" / "differenced_or_ar1.md")
    )
    args = ap.parse_args()
    kinds = [k for k in KINDS if args.kinds is None or any(w in k for w in args.kinds)]
    t0 = time.perf_counter()
    rows = []
    for kind in kinds:
        for n in args.lengths:
            counts = dict.fromkeys(CALLS, 0)
            ratio, cover = [], 0
            for s in range(args.runs):
                z, per_sample = record(kind, n, 20_000 + s)
                est = nv.estimate(z)
                counts[call(est.diagnostics)] += 1
                ratio.append(est.variance / per_sample)
                cover += est.ci95[0] <= per_sample <= est.ci95[1]
            lo, hi = np.percentile(ratio, [5, 95])
            cells = " | ".join(str(counts[c]) for c in CALLS)
            rows.append(
                f"| {kind} | {n} | {cells} | {np.mean(ratio):.3f} ({lo:.2f}-{hi:.2f}) | "
                f"{cover / args.runs:.0%} |"
            )
            print(rows[-1], flush=True)
    head = (
        "# Differenced data or AR(1) noise\n\n"
        f"`python benchmarks/differenced_or_ar1.py --runs {args.runs}{_picked(args)}`: "
        f"{args.runs} seeded "
        "records per row (seeds 20000 on); the calls of `auto`'s diagnostics and R over the "
        f"per-sample variance (mean, 5-95 %). {time.perf_counter() - t0:.0f} s.\n\n"
        "| record | samples | " + " | ".join(CALLS) + " | R / per-sample variance | ci95 covers |\n"
        "|---|---|" + "---|" * len(CALLS) + "---|---|\n"
    )
    Path(args.out).write_text(head + "\n".join(rows) + "\n")


if __name__ == "__main__":
    main()

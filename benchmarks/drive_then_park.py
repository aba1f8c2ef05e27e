"""A short record that drives, then parks: is the parked noise the answer, on every transform?

    python benchmarks/drive_then_park.py [--seeds 20] [--out drive_then_park]

Each record (``tests/diagnostics/park_records.drive_then_park``) drives over its first
half (a walk, or a smooth doubly integrated walk) and parks over its second, with white
noise of σ = 0.05 throughout: the truth is σ² = 0.0025, which the parked half alone
shows. Per family and length, over ``--seeds`` records:

- *one level at > 2x*: the answer reads one level (no R to use apart from R, and the
  regimes do not vary) while R is over twice σ²: the drive quoted as noise;
- *R to use covers σ²*: the R to use (``est.still`` when given, else R) has σ² in its ci95;
- *moved*: the R to use under reversal, 1-3 dropped leading samples, sign, x1000 and an
  offset of 1e4, outside the record's own R to use's ci95 (of 7 transforms a record).

Results: benchmarks/results/NAME.md.
"""

from __future__ import annotations

import argparse
import sys
import time
import warnings
from pathlib import Path

import numpy as np

import noisevar

ROOT = Path(__file__).resolve().parent.parent
sys.path.append(str(ROOT))  # after PYTHONPATH: the noisevar measured is the one it gives
from tests.diagnostics.park_records import SIGMA, drive_then_park  # noqa: E402

FAMILIES = {"smooth drive, steps 5": (5.0, True), "smooth drive, steps 2": (2.0, True),
            "walk, steps 2": (2.0, False)}  # fmt: skip
LENGTHS = (300, 400, 600, 1000)
TRANSFORMS = {
    "reversed": (lambda z: z[::-1], 1.0),
    "drop 1": (lambda z: z[1:], 1.0),
    "drop 2": (lambda z: z[2:], 1.0),
    "drop 3": (lambda z: z[3:], 1.0),
    "sign": (lambda z: -z, 1.0),
    "x1000": (lambda z: 1e3 * z, 1e-6),
    "offset 1e4": (lambda z: z + 1e4, 1.0),
}


def to_use(est) -> tuple[float, tuple[float, float]]:
    """The R to use and its ci95."""
    u = est if est.still is None else est.still
    return u.variance, u.ci95


def one_record(z: np.ndarray) -> tuple[bool, bool, int]:
    """(one level at over 2x σ², the R to use covers σ², transforms it moved under)."""
    est = noisevar.estimate(z)
    d = est.diagnostics
    one = est.still is None and not d.level_varies and est.variance > 2 * SIGMA**2
    v, (lo, hi) = to_use(est)
    moved = 0
    for f, back in TRANSFORMS.values():
        w = to_use(noisevar.estimate(f(z)))[0] * back
        moved += not lo <= w <= hi
    return one, lo <= SIGMA**2 <= hi, moved


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--seeds", type=int, default=20)
    ap.add_argument("--out", default="drive_then_park")
    args = ap.parse_args()
    warnings.simplefilter("ignore")
    t0 = time.time()
    rows = ["| family | samples | one level at > 2x | R to use covers σ² | moved (of 7 each) |",
            "|---|---|---|---|---|"]  # fmt: skip
    totals = np.zeros(3, dtype=int)
    for name, (step, smooth) in FAMILIES.items():
        for n in LENGTHS:
            res = np.array([one_record(drive_then_park(s, n, step, smooth))
                            for s in range(args.seeds)], dtype=int)  # fmt: skip
            one, cover, moved = res.sum(axis=0)
            totals += (one, cover, moved)
            rows.append(f"| {name} | {n} | {one} of {args.seeds} | {cover} of {args.seeds} | "
                        f"{moved} of {7 * args.seeds} |")  # fmt: skip
    k = len(FAMILIES) * len(LENGTHS) * args.seeds
    lines = [
        f"### Drive, then park (`python benchmarks/drive_then_park.py --seeds {args.seeds}`)",
        "",
        f"{k} seeded records, σ² = {SIGMA**2:g} (docstring); {time.time() - t0:.0f} s. "
        f"**One level at > 2x: {totals[0]} of {k}; R to use covers σ²: {totals[1]} of {k}; "
        f"moved: {totals[2]} of {7 * k}.**",
        "",
        *rows,
        "",
    ]
    out = ROOT / "benchmarks" / "results" / f"{args.out}.md"
    out.write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()

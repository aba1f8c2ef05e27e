"""A rest inside a moving record: does its R to use move with the block grids' phase?

    python benchmarks/still_phase.py [--records 30] [--seed 11] [--out still_phase]

Each record is white noise (σ = 0.1) under motion (a fast sine and noise of σ = 0.3)
everywhere but one rest (``tests/estimators/rest_records.rest_in_motion``), of
400-700 samples (blocks of 32). Two families of rests: 100-120 samples (each block grid
finds at least two blocks still on every phase) and 72-95 (the limit: a grid can find one
block only). A record fails when its R to use (``regimes="still"``) is missing on one of
reversal and 1-3 dropped leading samples and not on the record, or lies outside the
record's R to use's ci95 (issue 26 item 2). Results: benchmarks/results/NAME.md.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import numpy as np

import noisevar
from noisevar.estimators.regimes import why_no_still

ROOT = Path(__file__).resolve().parent.parent
sys.path.append(str(ROOT))  # after PYTHONPATH: the noisevar measured is the one it gives
from tests.estimators.rest_records import rest_in_motion  # noqa: E402

FAMILIES = {"rest 100-120 samples": (100, 121), "rest 72-95 samples (limit)": (72, 96)}


def to_use(est):
    """The R to use, None when there is none (said)."""
    return None if why_no_still(est) else (est if est.still is None else est.still)


def moved(z: np.ndarray) -> tuple[bool, bool]:
    """(the record has an R to use, it moves under a transform)."""
    base = to_use(noisevar.estimate(z))
    out = []
    for x in (z[::-1], z[1:], z[2:], z[3:]):
        out.append(to_use(noisevar.estimate(x)))
    if base is None:
        return False, any(u is not None for u in out)
    lo, hi = base.ci95
    return True, any(u is None or not lo <= u.variance <= hi for u in out)


def run(records: int, seed: int) -> dict[str, tuple[int, int]]:
    rng = np.random.default_rng(seed)
    res = {}
    for name, (a, b) in FAMILIES.items():
        found = bad = 0
        for i in range(records):
            n, length = int(rng.integers(400, 700)), int(rng.integers(a, b))
            at = int(rng.integers(100, n - length - 100))
            has, move = moved(rest_in_motion(i, n, at, length))
            found, bad = found + has, bad + move
        res[name] = (found, bad)
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=30)
    ap.add_argument("--seed", type=int, default=11)
    ap.add_argument("--out", default="still_phase")
    args = ap.parse_args()
    t0 = time.perf_counter()
    res = run(args.records, args.seed)
    wall = time.perf_counter() - t0
    cmd = f"python benchmarks/still_phase.py --records {args.records} --seed {args.seed}"
    lines = [
        "# A rest inside a moving record: the R to use under the block grids' phase",
        "",
        f"`{cmd}` ({wall:.0f} s; noisevar from `{Path(noisevar.__file__).parent}`).",
        "",
        "| records | with an R to use | R to use moved (missing or outside its ci95) under "
        "reversal or 1-3 dropped samples |",
        "|---|---|---|",
        *(f"| {k} | {f} of {args.records} | {b} of {args.records} |" for k, (f, b) in res.items()),
        "",
    ]
    out = ROOT / "benchmarks" / "results" / f"{args.out}.md"
    out.write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()

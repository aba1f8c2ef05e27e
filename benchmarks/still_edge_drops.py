"""A still stretch at the minimum length: does the R to use come and go as the grid moves?

    python benchmarks/still_edge_drops.py [--records 50] [--seed 23] [--out still_edge_drops]

Each record is white noise (σ = 0.1) under motion (a fast sine and noise of σ = 0.3)
everywhere but one rest of 64-90 samples (``tests/estimators/rest_records.rest_in_motion``)
inside a record of 400-700 samples (blocks of 32), so the block grids cut the rest into one,
two or three whole blocks as 0-3 leading samples are dropped. Two families: the samples as
drawn, and the same record written on a grid whose step is 2.5x the rest's σ (the rest's
noise under half a step's error variance, as a CGM's 1 mg/dL or a GPS altitude's 1 cm:
real_audit20's cgm5, real_audit4's GPS Alt). Each record is read as given, reversed and
with 1, 2, 3 leading samples dropped; a transform *comes and goes* when it has an R to use
(``regimes="still"``) and the record has none or the other way round, and *moves* when both
have one and the transform's lies outside the record's ci95 (issue 26 item 2).
Results: benchmarks/results/NAME.md.
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

#: the rest's lengths (samples): from the minimum a still R needs to under three blocks
LENGTHS = (64, 91)
#: the grid's step over the rest's σ in the grid family
STEP_OVER_SIGMA = 2.5
TRANSFORMS = {
    "reversed": lambda x: x[::-1],
    "drop 1": lambda x: x[1:],
    "drop 2": lambda x: x[2:],
    "drop 3": lambda x: x[3:],
}


def to_use(est):
    """The R to use, None when there is none (said)."""
    return None if why_no_still(est) else (est if est.still is None else est.still)


def on_grid(z: np.ndarray) -> np.ndarray:
    """``z`` written on a grid of :data:`STEP_OVER_SIGMA` times the rest's σ (0.1)."""
    step = STEP_OVER_SIGMA * 0.1
    return np.round(z / step) * step


FAMILIES = {"white noise": lambda z: z, f"on a grid of {STEP_OVER_SIGMA:g}σ": on_grid}


def record_of(seed: int) -> tuple[np.ndarray, int, int]:
    """Record ``seed``: its samples, the rest's start and length."""
    rng = np.random.default_rng([23, seed])
    n, length = int(rng.integers(400, 700)), int(rng.integers(*LENGTHS))
    at = int(rng.integers(100, n - length - 100))
    return rest_in_motion(seed, n, at, length), at, length


def read(z: np.ndarray) -> dict[str, tuple[bool, bool, bool]]:
    """Per transform: (comes and goes, moves outside the record's ci95, the regimes moved:
    one of the two reads the record as one level or its R to use is R itself, so PELT's
    split or the floor, not the still stretches, decided); ``"record"``: (has an R to use,
    False, False)."""
    est = noisevar.estimate(z)
    base = to_use(est)
    out = {"record": (base is not None, False, False)}
    for name, f in TRANSFORMS.items():
        again = noisevar.estimate(f(z))
        u = to_use(again)
        regimes = any(
            not e.diagnostics.level_varies or (e.still is None and to_use(e) is not None)
            for e in (est, again)
        )
        if base is None or u is None:
            out[name] = ((base is None) != (u is None), False, regimes)
        else:
            out[name] = (False, not base.ci95[0] <= u.variance <= base.ci95[1], regimes)
    return out


def run(records: int, seed: int) -> dict[str, dict[str, int]]:
    """Counts per family: records with an R to use, records where it comes and goes or
    moves under any transform, transforms where it does (of 4 per record), and of those
    the transforms where the regimes moved (:func:`read`)."""
    res = {}
    for fam, write in FAMILIES.items():
        c = {"found": 0, "comes_goes": 0, "moves": 0, "events_cg": 0, "events_mv": 0, "regimes": 0}
        for i in range(records):
            z, _, _ = record_of(seed * 1000 + i)
            r = read(write(z))
            c["found"] += r["record"][0]
            cg = [r[k][0] for k in TRANSFORMS]
            mv = [r[k][1] for k in TRANSFORMS]
            c["comes_goes"] += any(cg)
            c["moves"] += any(mv)
            c["events_cg"] += sum(cg)
            c["events_mv"] += sum(mv)
            c["regimes"] += sum((r[k][0] or r[k][1]) and r[k][2] for k in TRANSFORMS)
        res[fam] = c
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--records", type=int, default=50)
    ap.add_argument("--seed", type=int, default=23)
    ap.add_argument("--out", default="still_edge_drops")
    args = ap.parse_args()
    t0 = time.perf_counter()
    res = run(args.records, args.seed)
    wall = time.perf_counter() - t0
    cmd = f"python benchmarks/still_edge_drops.py --records {args.records} --seed {args.seed}"
    n = args.records
    lines = [
        "# A still stretch at the minimum length: the R to use as the block grid moves",
        "",
        f"`{cmd}` ({wall:.0f} s; noisevar from `{Path(noisevar.__file__).parent}`).",
        "",
        f"Rests of {LENGTHS[0]}-{LENGTHS[1] - 1} samples inside motion; each record as given, "
        "reversed and with 1-3 leading samples dropped (4 transforms a record).",
        "",
        "| family | records with an R to use | R to use comes and goes (records; transforms) "
        "| moves outside the record's ci95 (records; transforms) | of those transforms, the "
        "regimes moved (one level on one side, or R itself the R to use) |",
        "|---|---|---|---|---|",
        *(
            f"| {k} | {c['found']} of {n} | {c['comes_goes']} of {n}; {c['events_cg']} of "
            f"{4 * n} | {c['moves']} of {n}; {c['events_mv']} of {4 * n} | "
            f"{c['regimes']} of {c['events_cg'] + c['events_mv']} |"
            for k, c in res.items()
        ),
        "",
    ]
    out = ROOT / "benchmarks" / "results" / f"{args.out}.md"
    out.write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()

"""A short burst in a smooth record: do its level and R to use move with the grids' phase?

    python benchmarks/short_bursts.py [--seeds 6] [--out short_bursts]

Each record is the seeded smooth record of
``tests/diagnostics/test_short_burst_on_both_grids.py`` (4000 samples, a period of 90
samples, white noise of σ 0.1, blocks of 32): 14 samples from 2000-2028 (every 4) get
noise of σ 3 on top, a burst shorter than half a block. A record moves when, reversed or
with 1-3 leading samples dropped, whether its level varies changes or its R to use is
missing or outside the record's R to use's ci95 (issue 26 class 4).
Results: benchmarks/results/NAME.md.
"""

from __future__ import annotations

import argparse
import sys
import time
from pathlib import Path

import noisevar

ROOT = Path(__file__).resolve().parent.parent
sys.path.append(str(ROOT))  # after PYTHONPATH: the noisevar measured is the one it gives
from tests.diagnostics.test_short_burst_on_both_grids import burst_record, use_of  # noqa: E402

TRANSFORMS = {
    "reversed": lambda z: z[::-1],
    **{f"drop {d}": (lambda z, d=d: z[d:]) for d in (1, 2, 3)},
}


def moves(seed: int, at: int) -> list[str]:
    """The transforms under which the record's level or R to use moves."""
    z = burst_record(seed, at)
    est = noisevar.estimate(z)
    base = use_of(est)
    out = []
    for name, f in TRANSFORMS.items():
        other = noisevar.estimate(f(z))
        use = use_of(other)
        same = other.diagnostics.level_varies == est.diagnostics.level_varies
        if not same or use is None or not base.ci95[0] <= use.variance <= base.ci95[1]:
            out.append(name)
    return out


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--seeds", type=int, default=6)
    ap.add_argument("--out", default="short_bursts")
    args = ap.parse_args()
    t0 = time.perf_counter()
    rows = [(s, at, moves(s, at)) for s in range(args.seeds) for at in range(2000, 2032, 4)]
    bad = [r for r in rows if r[2]]
    lines = [
        "# A short burst in a smooth record: level and R to use under the grids' phase",
        "",
        f"`python benchmarks/short_bursts.py --seeds {args.seeds}` "
        f"({time.perf_counter() - t0:.0f} s; noisevar from `{Path(noisevar.__file__).parent}`).",
        "",
        f"**Moved under reversal or 1-3 dropped samples: {len(bad)} of {len(rows)} records.**",
        "",
        "| seed | burst at | moved under |",
        "|---|---|---|",
        *(f"| {s} | {at} | {', '.join(m)} |" for s, at, m in bad),
    ]
    text = "\n".join(lines) + "\n"
    (ROOT / "benchmarks" / "results" / f"{args.out}.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()

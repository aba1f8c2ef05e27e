"""Which quantity moves the verdict's lead when 1-3 leading samples are dropped (issue 26).

    python benchmarks/verdict_lead_flip.py

Three real channels flip their first clause between "the noise is coloured" and "the noise
level changes along the record" (real_audit11 watch_ride v_north, real_audit18 Scorpio
DNEAR and Totem GR); watch_ride heart_rate, which holds, is the control. For each drop the
table gives what ``verdict._not_white`` compares: R, the still level and its 95 % interval
(``diag.quiet``), R over it against ``STILL_RATIO``, whether its interval top is under R,
the level profile's quiet share against ``MOSTLY_MOTION``, and the lag-1 autocorrelation of
the whole record and of its still stretches, and the share of the still stretches' departure
from white noise that the whole record's autocorrelation explains (``shared_colour``: at
``SHARED_EXPLAINS`` or more they are as coloured, ``colour_in_still``, and the lead names the
level change and the colour together, whatever the ratio; session 28). Writes
``benchmarks/results/verdict_lead_flip.md``.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np

import noisevar as nv
from noisevar.diagnostics.regimes import STILL_RATIO
from noisevar.diagnostics.verdict_parts import MOSTLY_MOTION, SHARED_EXPLAINS, shared_colour

sys.path.insert(0, str(Path(__file__).resolve().parent))
import real_audit11  # noqa: E402
import real_audit18  # noqa: E402
from real_audit import clause, finding  # noqa: E402

OUT = Path(__file__).resolve().parent / "results" / "verdict_lead_flip.md"
HEAD = ("| channel | drop | R | still R (ci95) | R / still | ci top < R | quiet share | "
        "lag-1 whole | lag-1 still | shared | first clause |")  # fmt: skip


def cases() -> list[tuple[str, np.ndarray]]:
    """(name, samples) of the flipping channels and the control."""
    watch, _t = real_audit11.channels_of("watch_ride")
    return [("watch_ride v_north", watch["v_north"]),
            ("scorpio DNEAR", real_audit18.channels_of("scorpio")["DNEAR"]),
            ("totem GR", real_audit18.channels_of("totem")["GR"]),
            ("watch_ride heart_rate (holds)", watch["heart_rate"])]  # fmt: skip


def row(name: str, z: np.ndarray, d: int) -> str:
    """One drop's table row."""
    e = nv.estimate(z[d:])
    g = e.diagnostics
    q, s = g.quiet, g.still_whiteness
    still = f"{q.variance:.4g} ({q.lo:.4g}-{q.hi:.4g})" if q and q.hi else "-"
    top = "yes" if q and q.hi and q.hi < e.variance else "no"
    ratio = f"{e.variance / q.variance:.2f}" if q else "-"
    lag = f"{s.lag1:+.3f}" if s is not None else "-"
    shared = shared_colour(g)
    share = "-" if shared is None else f"{shared:.3f}"
    return (f"| {name} | {d} | {e.variance:.4g} | {still} | {ratio} | {top} | "
            f"{g.level_profile.quiet_share:.3f} | {g.whiteness.lag1:+.3f} | {lag} | {share} | "
            f"{clause(e.verdict)} |")  # fmt: skip


def main() -> None:
    lines = [f"# The verdict's lead under 1-3 dropped samples (STILL_RATIO {STILL_RATIO}, "
             f"MOSTLY_MOTION {MOSTLY_MOTION}, SHARED_EXPLAINS {SHARED_EXPLAINS})", "", HEAD,
             "|" + " --- |" * 11]  # fmt: skip
    held = 0
    for name, z in cases():
        lines += [row(name, z, d) for d in range(4)]
        held += len({finding(nv.estimate(z[d:]).verdict) for d in range(4)}) == 1
    lines += ["", f"**{held} of {len(cases())} channels keep one finding over drops 0-3** "
              "(``real_audit.finding``: the lead up to its first ':' or ',')."]  # fmt: skip
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

"""Why R moves with 1-3 leading samples dropped on two real records (issue 26, class 4).

    python benchmarks/jump_drops.py      # writes benchmarks/results/jump_drops.md

A measurement, not a check: it prints what decides R under each drop.

1. real_audit12's floating lidar, 50 m speed (the coloured estimate, ``span=5``): the jump
   detector's lone step at samples 160-169 (glitches of 20.3 and 18.5) is confirmed by the
   window medians' third difference at sample 167 against its threshold, the larger of both
   grids'. The binding one is the grid from the record's end, whose last block holds samples
   48-303 *and the rest of the record, 0-47*: the level of that block (and the whole-window
   raise, read off every level) moved with the record's first samples' edge residuals (fixed:
   the rest takes the last level but does not make it, _levels.kept_levels).
2. real_audit18's Totem #9, ATC1: the record starts inside a fast oscillation; sample 0 is
   judged a glitch at the edge (``_edges.edge_glitches``) with 0 or 1 dropped, and its
   deleted residual (a cubic over 11 samples that cannot follow the oscillation) adds most
   of R's sum of squares; with 2-3 dropped the edge run is 3 samples, no glitch, nothing added
   (not fixed: a noise test on the glitch's fit refused PX4 airspeed's real start-up value).
3. A seeded synthetic: white noise (sigma 0.01) under a fast damped oscillation at the start.
"""

from __future__ import annotations

import sys
import time
from pathlib import Path

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))
import real_audit12  # noqa: E402
import real_audit18  # noqa: E402

from noisevar.estimators.auto import AUTO_COLOURED_SPAN, _levels, _trim, auto_estimate, core  # noqa: E402  # noqa: E402
from noisevar.numeric import steps  # noqa: E402

OUT = Path(__file__).parent / "results" / "jump_drops.md"
DROPS = range(6)
#: the lidar's confirmed sample (record index) and the back grid's block that holds it
LIDAR_AT = 167


def _lidar_rows(z: np.ndarray) -> list[str]:
    """R, the D3med level at :data:`LIDAR_AT` over its two thresholds, and the back level."""
    seen: dict = {}
    confirmed, whole = steps._confirmed, _levels.Above._raised_whole

    def probe(x, idx, above, scale, w):
        at = np.flatnonzero(idx + seen["d"] == LIDAR_AT)
        if at.size and above.whole:
            k = idx[at]
            d3 = steps._steps_numba.median_third_differences(
                np.ascontiguousarray(x), steps._ints(k), x.size - w, steps._NET
            )
            level = d3**2 * scale / (steps.STEP_CONFIRM**2 * 20.0 * steps._median_variance(w))
            g = above.g
            jf = np.array([k[0], k[0] - 1])
            tf = float(np.max(_levels.bracketing(jf, above.fwd, g.block)))
            jb = g.back_index(np.array([k[0], k[0] - 1]))
            tb = float(np.max(_levels.bracketing(np.maximum(jb, 0), above.bwd, g.block)))
            seen["conf"] = (float(level[0]), float(tf), tb)
        return confirmed(x, idx, above, scale, w)

    def raise_whole(self, x, expected):
        out = whole(self, x, expected)
        seen["raise"] = (float(self.bwd[-1]), float(out.fwd[0] / self.fwd[0]))
        return out

    steps._confirmed, _levels.Above._raised_whole = probe, raise_whole
    rows = []
    try:
        for d in DROPS:
            seen.clear()
            seen["d"] = d
            r = auto_estimate(z[d:], span=AUTO_COLOURED_SPAN)
            lv, tf, tb = seen.get("conf", (np.nan,) * 3)
            back, f = seen.get("raise", (np.nan, np.nan))
            rows.append(
                f"| {d} | {r.variance:.4g} | {lv:.3f} | {tf:.3f} | {tb:.3f} "
                f"| {lv / max(tf, tb):.3f} | {back:.4f} | {f:.4f} |"
            )
    finally:
        steps._confirmed, _levels.Above._raised_whole = confirmed, whole
    return rows


def _edge_rows(z: np.ndarray, label: str) -> list[str]:
    """R, core, the outlying samples among the first 5 and what the edge glitch adds."""
    seen: dict = {}
    edge = core.edge_glitches

    def probe(x, outl, spans, detect, order, ends, *levels):
        out = edge(x, outl, spans, detect, order, ends, *levels)
        seen["e"] = (outl[outl < 5].tolist(), out[1])
        return out

    core.edge_glitches = probe
    rows = []
    try:
        for d in DROPS:
            r = auto_estimate(z[d:], span=AUTO_COLOURED_SPAN)
            at, add = seen["e"]
            n = z.size - d
            rows.append(
                f"| {label} | {d} | {r.variance:.4g} | {r.core_variance:.4g} | {at} | {add:.4g} "
                f"| {add / (r.variance * n):.0%} |"
            )
    finally:
        core.edge_glitches = edge
    return rows


def synthetic(seed: int = 1, n: int = 4000, period: float = 12.0, ph: float = 1.5) -> np.ndarray:
    """White noise (sigma 0.01) under a damped oscillation at the start (amplitude 3.5)."""
    k = np.arange(n)
    rng = np.random.default_rng(seed)
    start = 3.5 * np.cos(2 * np.pi * k / period + ph) * np.exp(-((k / 25.0) ** 2))
    return start + rng.normal(0.0, 0.01, n)


def main() -> None:
    t0 = time.time()
    lidar = real_audit12.channels_of("floating_lidar")["Spd_50m"]
    atc1 = real_audit18.channels_of("totem")["ATC1"]
    assert _trim is not None  # noqa: S101 - imported for the probes' modules
    lines = [
        "# jump_drops: what decides R under 0-5 leading samples dropped (issue 26, class 4)",
        "",
        "`python benchmarks/jump_drops.py`; a measurement (see the module docstring).",
        "",
        "## 1. floating lidar Spd_50m, auto span 5 (the coloured estimate)",
        "",
        f"D3med level at sample {LIDAR_AT} against its thresholds (fwd grid, back grid); the "
        "step is confirmed (samples 158-171 left out) when the ratio to the larger is > 1. "
        "back level: the back grid's last block's level before the whole-window raise "
        "(samples 0-303); raise: the whole-window factor.",
        "",
        "| drop | R | D3med level | fwd thr | back thr | ratio | back level | raise |",
        "|---|---|---|---|---|---|---|---|",
        *_lidar_rows(lidar),
        "",
        "## 2. edge glitches (auto span 5): Totem ATC1 and a synthetic fast start",
        "",
        "| record | drop | R | core | outlying among first 5 | edge add | of R's sum |",
        "|---|---|---|---|---|---|---|",
        *_edge_rows(atc1, "Totem ATC1"),
        *_edge_rows(synthetic(), "synthetic (sigma² 1e-4)"),
        "",
        f"wall {time.time() - t0:.1f} s",
    ]
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

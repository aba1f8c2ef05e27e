"""Lone glitches: one outlying sample is noise in R, never a regime of its own (issue 26).

A glitch of many σ spreads through the diagnostics' residual filter over its whole span,
so the block it falls in gets a raised median as well as a raised mean square: one sample
read as a stretch of motion, whether it did depended on its size and on where the block
grid put it (at sample 1500, 80σ: "the noise level changes"; 20σ, or at the record's
edge: not). The level profile therefore reads each block within reach of a lone glitch
with the glitch bridged (:func:`bridge_blocks`): its level without it. R, the tails and
the kurtosis keep it: it is noise (docs/algorithms.md §E1 *Lone glitches*).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics.plan import DIAG_SPAN, DiagPlan
from noisevar.diagnostics.sums import DiagSums, diag_part

#: At most this many outlying samples within one :data:`DIAG_SPAN` of each other make one
#: lone glitch; more are a burst (motion, a tap) or the noise's tails, left as they are.
LONE_MAX = 2


@dataclass(frozen=True)
class Glitch:
    """One lone outlying sample.

    Attributes
    ----------
    index : int
        Its sample.
    sigmas : float
        How far it lies from its neighbours' line, over the noise's standard deviation
        (the quiet level's, on the diagnostics' residual): unit-free.
    """

    index: int
    sigmas: float

    def to_dict(self) -> dict[str, float | int]:
        return {"index": self.index, "sigmas": self.sigmas}


def lone(glitches: NDArray) -> NDArray:
    """The outlying samples that are lone glitches: clusters of at most :data:`LONE_MAX`.

    A cluster is a run of outlying samples each within :data:`DIAG_SPAN` of the next.
    """
    g = np.unique(np.asarray(glitches, dtype=int))
    if g.size == 0:
        return g
    cut = np.flatnonzero(np.diff(g) > DIAG_SPAN) + 1
    runs = np.split(g, cut)
    return np.concatenate([r for r in runs if r.size <= LONE_MAX] or [g[:0]])


def bridged(x: NDArray, at: NDArray) -> NDArray:
    """``x`` (a copy) with the samples ``at`` set to the line through their neighbours.

    Beyond the last kept sample on either side, the nearest kept one (as ``np.interp``).
    """
    x = np.array(x, dtype=float)
    if at.size and at.size < x.size:
        ok = np.ones(x.size, dtype=bool)
        ok[at] = False
        x[at] = np.interp(at, np.flatnonzero(ok), x[ok])
    return x


def deviations(glitches: NDArray, read: Callable[[int, int], NDArray], n: int) -> NDArray:
    """Each glitch's distance from the line through its neighbours (record units)."""
    out = np.empty(glitches.size)
    for i, g in enumerate(glitches):
        a, b = max(0, int(g) - DIAG_SPAN), min(n, int(g) + DIAG_SPAN + 1)
        x = np.asarray(read(a, b), dtype=float)
        near = glitches[(glitches >= a) & (glitches < b)] - a
        out[i] = abs(x[g - a] - bridged(x, near)[g - a])
    return out


def _touched(plan: DiagPlan, glitches: NDArray) -> set[int]:
    """Profile blocks with a residual whose window holds one of ``glitches``."""
    h, out = plan.h, set()
    for s, (a, b) in zip(plan.slot0, plan.segments, strict=True):
        if s is None:
            continue
        for g in glitches[(glitches >= a) & (glitches < b)]:
            k0, k1 = max(int(g) - h, a + h), min(int(g) + h + 1, b - h)
            if k0 < k1:
                first, last = s + k0 - (a + h), s + k1 - 1 - (a + h)
                size, count = plan.profile.size, plan.profile.count
                out.update(range(min(first // size, count - 1), min(last // size, count - 1) + 1))
    return out


def bridge_blocks(sums: DiagSums, glitches: NDArray, read: Callable[[int, int], NDArray]) -> None:
    """The profile blocks within reach of ``glitches``, summed again with them bridged.

    Parameters
    ----------
    sums : DiagSums
        Complete sums; their profile entries are replaced in place (the shape grid's,
        the kurtosis' and the whiteness windows' are left as they are).
    glitches : ndarray of int
        Lone glitches (record indices, sorted).
    read : callable
        ``read(a, b)``: samples ``a .. b`` of the record, on the scale the sums were made.

    Notes
    -----
    Each glitch is set to the line through its neighbours and the block's residuals are
    made again (:func:`~noisevar.diagnostics.sums.diag_part`): its count, mean square,
    median and tails are then the block's level without the glitch. A block that lost
    residuals around a level jump is left as it is (its kept mask is not re-read).
    """
    plan = sums.plan
    grid = plan.profile
    for blk in sorted(_touched(plan, glitches)):
        lo_slot, hi_slot = blk * grid.size, grid.end(blk)
        old = sums.profile.get(blk)
        if old is None or old[0] != hi_slot - lo_slot:
            continue
        parts = []
        for i, (s, (a, b)) in enumerate(zip(plan.slot0, plan.segments, strict=True)):
            m = b - a - 2 * plan.h
            if s is None or s + m <= lo_slot or s >= hi_slot:
                continue
            k0 = max(lo_slot, s) - s + a + plan.h
            k1 = min(hi_slot, s + m) - s + a + plan.h
            wa, wb = max(a, k0 - DIAG_SPAN), min(b, k1 + DIAG_SPAN)
            near = glitches[(glitches >= wa) & (glitches < wb)] - wa
            x = bridged(read(wa, wb), near)
            parts.append(diag_part(x, wa, (k0, k1), i, plan, profile_only=True).profile[blk])
        piece = parts[0]
        for p in parts[1:]:
            piece.merge(p)
        sums.reblock(blk, piece)

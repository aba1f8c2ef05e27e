"""A short burst read on the block grid that splits it in two (docs/algorithms.md §E1
*Regimes*): where it sits, not where the record's grids happen to fall, decides whether it
is a regime of motion."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING

import numpy as np
from numpy.lib.stride_tricks import sliding_window_view
from numpy.typing import NDArray

from noisevar.diagnostics import profile_of
from noisevar.diagnostics.plan import DIAG_SPAN, DiagPlan, make_plan
from noisevar.diagnostics.regimes import Regime
from noisevar.diagnostics.segments import Segmentation
from noisevar.diagnostics.sums import _residual_part

if TYPE_CHECKING:
    from noisevar.diagnostics.results import NoiseDiagnostics

#: ``read(diag, a, b)``: a short regime of motion ``a .. b`` read on the grid that splits it.
Split = Callable[["NoiseDiagnostics", int, int], "tuple[int, tuple[Regime, ...]] | None"]

#: Window positions a block is read at when the burst's centre is searched (one a sample
#: up to this block size; beyond it, this many a block).
CENTRE_STEPS = 64


def burst_centre(z: NDArray, a: int, b: int, block: int) -> int | None:
    """The sample at the middle of the one-block windows within ``a .. b`` whose median
    squared residual is largest: where a short burst sits, whatever the block grid.

    Parameters
    ----------
    z : ndarray
        The record.
    a, b : int
        Sample range to search (a regime of motion and a block either side).
    block : int
        The profile's block size.

    Returns
    -------
    int or None
        The middle of the best windows' span (None: the range holds no whole window).

    Notes
    -----
    The residual is the diagnostics' own (the profile's). A median moves in steps, so
    neighbouring windows tie; the middle of the first and last best windows is the same
    sample read forwards or reversed.
    """
    h = DIAG_SPAN // 2
    lo, hi = max(a, h), min(b, z.size - h)
    if hi - lo < block:
        return None
    sq = _residual_part(z, 0, lo, hi, None)[0] ** 2
    step = max(1, block // CENTRE_STEPS)
    med = np.median(sliding_window_view(sq, block)[::step], axis=1)
    top = np.flatnonzero(med == med.max()) * step
    return lo + (int(top[0]) + int(top[-1]) + block) // 2


def on_split_grid(
    z: NDArray,
    seg: Segmentation,
    exclude: NDArray | None,
    glitches: NDArray,
    lsb: float | None,
    a: int,
    b: int,
) -> tuple[int, tuple[Regime, ...]] | None:
    """The record's regimes read on the block grid with a block edge at the burst in
    ``a .. b`` (:func:`burst_centre`), and that sample.

    Parameters
    ----------
    z : ndarray
        The record.
    seg : Segmentation
        Its uniform segments.
    exclude : ndarray of bool or None
        Samples left out around level jumps.
    glitches : ndarray of int
        Lone glitches' indices, bridged.
    lsb : float or None
        The record's grid step.
    a, b : int
        A short regime of motion, found on some grid.

    Returns
    -------
    (int, tuple of Regime) or None
        The burst's centre and the regimes, in the record's sample indices (None: no
        centre, or a record too short to shift).

    Notes
    -----
    The grid is the record's own (its block size), laid ``k`` samples later: the profile
    of ``z[k:]``, its indices moved back by ``k``.
    """
    plan = make_plan(z.size, seg.segments, np.zeros(0))
    block = plan.profile.size
    c = burst_centre(z, max(0, a - block), min(z.size, b + block), block)
    if c is None:
        return None
    k = _slot_of(plan, c) % block
    cut = [(max(p - k, 0), q - k) for p, q in seg.segments if q - k > max(p - k, 0)]
    if not cut:
        return None
    gl = glitches[glitches >= k] - k
    x = None if exclude is None else exclude[k:]
    prof = profile_of(z[k:], Segmentation(tuple(cut), ()), x, gl, lsb, block)
    return c, tuple(replace(r, start=r.start + k, stop=r.stop + k) for r in prof.regimes)


def _slot_of(plan: DiagPlan, c: int) -> int:
    """The residual slot of sample ``c`` (that of its segment's last slot before it, when
    ``c`` is not in a diagnosed segment's residuals)."""
    slot = 0
    for s, (p, q) in zip(plan.slot0, plan.segments, strict=True):
        if s is not None and p <= c:
            slot = s + min(c, q - plan.h - 1) - p - plan.h
    return max(slot, 0)


def split_reader(record: object) -> Split | None:
    """:func:`on_split_grid` of a record in memory (its ``z``, ``seg`` and the ``jumps``
    its diagnostics left out), as ``read(diag, a, b)``; None for a record read in chunks."""
    z, seg = getattr(record, "z", None), getattr(record, "seg", None)
    if z is None or seg is None:
        return None

    def read(diag: NoiseDiagnostics, a: int, b: int) -> tuple[int, tuple[Regime, ...]] | None:
        lone = np.array([g.index for g in diag.glitches], dtype=int)
        return on_split_grid(z, seg, getattr(record, "jumps", None), lone, diag.lsb, a, b)

    return read

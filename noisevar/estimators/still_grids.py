"""A still stretch's extent on the two block grids: the record's, laid from its start, and
the reversed record's, laid from its end (docs/algorithms.md §E1 *The still set*).

:func:`~noisevar.estimators.still_quiet.still_estimate` reads the still R on the stretches
still on both grids; these say where else they may end: at the record's ends on the grid
laid from that end, grown to either grid's, shrunk by a block, and how far the still R's
interval must widen to hold those readings.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np

from noisevar.diagnostics.profile import LevelProfile, on_either_grid
from noisevar.estimators.results import VarianceEstimate, chi2_interval
from noisevar.estimators.still_set import STILL_MIN


def at_the_ends(
    ranges: list[tuple[int, int]], prof: LevelProfile, back: LevelProfile, n: int
) -> list[tuple[int, int]]:
    """The still stretches on both block grids, those at the record's ends read on the
    grid laid from that end.

    Parameters
    ----------
    ranges : list of (int, int)
        The stretches still on both grids (:func:`~noisevar.diagnostics.profile.on_both_grids`).
    prof, back : LevelProfile
        The record's profile and the reversed record's (its own sample indices).
    n : int
        Samples in the record.

    Returns
    -------
    list of (int, int)
        ``ranges``, a piece that starts at the record's first block replaced by the
        record's own still stretch that holds it, one that ends at its last block by the
        reversed record's.

    Notes
    -----
    docs/algorithms.md §E1 (*The still set*). The record's grid is laid from its start,
    the reversed record's from its end: a still stretch at the start is cut into whole
    blocks by the first, while the second's phase there moves with the record's length
    (its block at the start takes the rest, 32 to 63 samples). Both find it still, and
    the stretch still on both was 64 samples or 63 (too short for R's method) as leading
    samples were dropped (sktime's BasicMotions: a 100-sample Standing start). Read on
    the grid aligned with its end, it is the same stretch whatever is dropped at the
    other end; reversal swaps the grids and the ends together. A stretch inside the
    record stays on both grids (a rest a block long, quiet on one grid and straddling
    two blocks of the other, is no still stretch).
    """
    if not ranges or not prof.start.size or not back.start.size:
        return ranges
    first, last = int(prof.start[0]), n - int(back.start[0])
    own = prof.still_stretches
    rev = [(n - b, n - a) for a, b in back.still_stretches]
    out = []
    for c, d in ranges:
        if c == first:
            c, d = next(((a, b) for a, b in own if a <= c and d <= b), (c, d))
        if d == last:
            c, d = next(((a, b) for a, b in rev if a <= c and d <= b), (c, d))
        out.append((c, d))
    return out


def grown_to_either(
    ranges: list[tuple[int, int]], prof: LevelProfile, back: LevelProfile, n: int
) -> list[tuple[int, int]]:
    """The stretches still on either block grid that hold a stretch still on both.

    Parameters
    ----------
    ranges : list of (int, int)
        The stretches still on both grids (:func:`~noisevar.diagnostics.profile.on_both_grids`).
    prof, back : LevelProfile
        The record's profile and the reversed record's (its own sample indices).
    n : int
        Samples in the record.

    Returns
    -------
    list of (int, int)
        Each run of the two grids' still stretches' union that holds a piece of
        ``ranges``, in order (those that hold none left out). A grid whose blocks are all
        quiet adds nothing: it finds the record one level, no stretch of it apart.

    Notes
    -----
    docs/algorithms.md §E1 (*A still stretch inside the record*). A rest about two blocks
    long is cut into whole blocks by each grid: both find it still, and their
    intersection is 64 samples when the grids' phases agree and 61-63 when dropping a
    leading sample moves the record's own grid (sktime's BasicMotions: acc_z, gyr_z's R to
    use came and went). Each sample of the union is in a still block of one grid, and
    both grids find the rest still, so it is one still stretch whatever the phase; the
    reversed grid, laid from the record's end, does not move when leading samples are
    dropped, and reversal swaps the grids. The intersection is still read first (the
    union adds at most a block at each end that the other grid found with motion in part).
    """
    apart = [p.still_stretches if not p.quiet.all() else [] for p in (prof, back)]
    either = on_either_grid(*apart, n)
    return [(a, b) for a, b in either if any(a <= c and d <= b for c, d in ranges)]


def long_on_every_phase(
    ranges: list[tuple[int, int]], prof: LevelProfile, back: LevelProfile, n: int
) -> list[tuple[int, int]]:
    """The stretches still on both block grids when one of them stays at least
    :data:`STILL_MIN` samples on every phase of the grids, else none.

    Parameters
    ----------
    ranges : list of (int, int)
        The stretches still on both grids (:func:`~noisevar.diagnostics.profile.on_both_grids`).
    prof, back : LevelProfile
        The record's profile and the reversed record's (its own sample indices).
    n : int
        Samples in the record.

    Returns
    -------
    list of (int, int)
        ``ranges`` when one of them lies in a still stretch of each grid with a block to
        spare (at least :data:`STILL_MIN` samples and one profile block), or when a block
        alone holds :data:`STILL_MIN` samples; else none: the still R is then read by the
        fallbacks (the still regimes, the end's own grid, the grids' union, the rest to the
        sample) on every phase.

    Notes
    -----
    docs/algorithms.md §E1 (*A still stretch at the minimum length*). A grid finds one
    whole block more or less of a rest as its phase moves (the record's with dropped
    leading samples, the two swapped by a reversal), so a still stretch of exactly two
    blocks of 32 on one phase is one block, under 64, on the next, where the still R was
    read by the fallbacks or not at all: real_audit20's cgm5 read a 64-sample stretch,
    0.487, and none with 1-3 samples dropped. A stretch each grid finds with a block to
    spare stays 64 samples on every phase (cgm5 Subject 4: 96 on both grids, read 89-92
    samples on both at every phase, its still R 0.29-0.33).
    """
    block = int(prof.stop[0] - prof.start[0]) if prof.start.size else STILL_MIN
    if block >= STILL_MIN:  # one block is long enough: the minimum is not counted in blocks
        return ranges
    spare = STILL_MIN + block
    own = [(a, b) for a, b in prof.still_stretches if b - a >= spare]
    rev = [(n - b, n - a) for a, b in back.still_stretches if b - a >= spare]
    kept = any(
        any(a <= c and d <= b for a, b in own) and any(a <= c and d <= b for a, b in rev)
        for c, d in ranges
    )
    return ranges if kept else []


def shrunk(ranges: list[tuple[int, int]], prof: LevelProfile) -> list[tuple[int, int]]:
    """``ranges`` each less one profile block at an end inside the profile (pieces of at
    least :data:`STILL_MIN` samples): where they are still, whichever grid ends them."""
    if not prof.start.size:
        return []
    edge, first, last = int(prof.stop[0] - prof.start[0]), prof.start[0], prof.stop[-1]
    cut = [(a + edge if a > first else a, b - edge if b < last else b) for a, b in ranges]
    return [(a, b) for a, b in cut if b - a >= STILL_MIN]


def may_leave(
    still: VarianceEstimate,
    prof: LevelProfile,
    ranges: list[tuple[int, int]],
    other: list[tuple[int, int]],
) -> bool:
    """Whether R's method on ``other`` may read outside ``still``'s interval: the profile's
    mean squares over the blocks inside ``other`` and inside ``ranges`` put it there, or
    either holds no whole block (the stretches are short: measuring them costs little).

    A screen on the blocks' sums the diagnostics made already, so that a long still set,
    whose ends weigh little, is not read twice more (the still stretches' phase is about
    a sixth of ``auto``'s time on 1e6 samples with motion)."""
    ms = [block_mean_square(prof, r) for r in (ranges, other)]
    if not (ms[0] > 0.0 and ms[1] > 0.0):
        return True
    lo, hi = still.ci95
    return not lo <= still.variance * ms[1] / ms[0] <= hi


def block_mean_square(prof: LevelProfile, ranges: list[tuple[int, int]]) -> float:
    """The mean square of the profile blocks wholly inside ``ranges`` (0 when none is)."""
    inside = np.zeros(prof.start.size, dtype=bool)
    for a, b in ranges:
        inside |= (prof.start >= a) & (prof.stop <= b)
    count = (prof.stop - prof.start if prof.count is None else prof.count)[inside]
    total = float(np.sum(count))
    return float(np.sum(count * prof.variance[inside])) / total if total > 0 else 0.0


def over_either_grid(still: VarianceEstimate, either: VarianceEstimate | None) -> VarianceEstimate:
    """The still R with its dof cut until its interval holds another reading too.

    Parameters
    ----------
    still : VarianceEstimate
        R's method on the stretches still on both block grids (the record's and its
        reversal's).
    either : VarianceEstimate or None
        The same method on the stretches still on either grid (their union), or on the
        stretches less a block at their inner ends; None when it could not be measured.

    Returns
    -------
    VarianceEstimate
        ``still`` itself when ``either`` is None or inside its 95 % interval; else
        ``still`` with the fewest dof cut that put ``either``'s value on the edge of its
        χ² interval (its variance unchanged), with a note.

    Notes
    -----
    docs/algorithms.md §E1 (*The still set*). A still stretch's ends are known to a
    profile block: the two grids a reversal swaps can end it a block apart, and dropping
    a few leading samples moves the record's own grid's phase, so the stretch R is read
    on moves by a block (a humidity record's night: still R 0.0066 on 76 samples, 0.024
    on 139 with one sample dropped). The readings on the stretches grown to either grid's
    and shrunk by a block at their inner ends are the still level as far as the grids can
    tell: the value stays the both-grid one (nothing of the motion beside it),
    and its interval is that of fewer dof, which the method's own widening
    (``honest_interval``) keeps, so that it holds the other too. Reversal swaps the grids
    and leaves both readings as they are.
    """
    if either is None or not either.variance > 0.0 or not still.dof > 0.0:
        return still
    v, w = still.variance, either.variance
    lo, hi = still.ci95
    if lo <= w <= hi:
        return still
    inside = (
        (lambda d: chi2_interval(v, d)[1] >= w)
        if w > v
        else (lambda d: chi2_interval(v, d)[0] <= w)
    )
    a, b = 0.1, float(still.dof)  # a χ² interval on 0.1 dof spans about 30 decades
    if not inside(a):
        return still
    for _ in range(40):  # bisection in log dof
        mid = float(np.sqrt(a * b))
        a, b = (mid, b) if inside(mid) else (a, mid)
    dof = a
    note = (
        f"the still stretches' ends are known to a profile block: grown to either block "
        f"grid's or shrunk by a block they read {w:.4g}, so the interval is that of "
        f"{dof:.3g} dof "
        "(docs/algorithms.md §E1 The still set)"
    )
    return replace(still, dof=dof, ci95=chi2_interval(v, dof), notes=[*still.notes, note])

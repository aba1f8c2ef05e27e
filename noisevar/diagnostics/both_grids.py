"""A record's regimes read on both block grids: the record's, laid from its start, and its
reversal's, laid from its end (docs/algorithms.md §E1 *Regimes*)."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING

from noisevar.diagnostics.profile import MOTION_RUN, LevelProfile, with_back_grid
from noisevar.diagnostics.regimes import STILL_RATIO, Regime
from noisevar.diagnostics.split_grid import Split, split_reader

if TYPE_CHECKING:
    from noisevar.diagnostics.results import NoiseDiagnostics


def regimes_on_both_grids(diag: NoiseDiagnostics, record: object) -> NoiseDiagnostics:
    """``diag`` read on both block grids: the record's and its reversal's.

    Parameters
    ----------
    diag : NoiseDiagnostics
        The record's diagnostics (its profile on the grid from the record's start).
    record : object
        Its ``back_profile(diag)``: the same profile of the record reversed (its blocks
        end where the record's start); none: ``diag`` is returned. A record in memory
        also reads a short burst on the grid that splits it
        (:func:`~noisevar.diagnostics.split_grid.split_reader`).

    Returns
    -------
    NoiseDiagnostics
        Its profile's regimes those of ``back(diag)`` (in the record's sample indices)
        when the record's own grid finds one still level and the reversed grid regimes
        that are not still (:func:`_back_regimes`: a split hinted on the record's grid, or
        all in its last block), or its one level when the record's own grid finds only
        regimes of motion under :data:`MOTION_RUN` blocks that the reversed grid does not
        (:func:`_short_motion_read_twice`); where the level then varies, its profile with the
        reversed grid's quiet blocks (:func:`~noisevar.diagnostics.profile.with_back_grid`),
        so that the quiet share and whether any stretch is quiet read both grids; so too
        where one level has a run of left-out blocks over
        :data:`~noisevar.diagnostics.regimes.STILL_RATIO` times the quiet level
        (:meth:`LevelProfile.left_out_ratio`, then the smaller of both).

    Notes
    -----
    docs/algorithms.md §E1 *Regimes*. ``back`` is called only in those cases, where the
    record's last block is left out of its quiet set, where its grid hints a change
    it does not make (:attr:`LevelProfile.near_split`), or where its only regimes of
    motion are short: a record whose still stretches
    are apart (``still_set.has_still_apart``) has them measured on both grids anyway (the
    same profile, made once).
    """
    back = getattr(record, "back_profile", None)
    if back is None or not diag.level_profile.quiet.size:
        return diag
    split = split_reader(record)
    made: list[LevelProfile] = []

    def once(d: NoiseDiagnostics) -> LevelProfile:
        if not made:
            made.append(back(d))
        return made[0]

    diag = _back_regimes(diag, once, split)
    prof = diag.level_profile
    if not diag.level_varies and not prof.unmeasured and prof.left_out_ratio() <= STILL_RATIO:
        return diag
    prof = with_back_grid(diag.level_profile, once(diag), diag.n)
    return replace(diag, level_profile=prof)


def _back_regimes(
    diag: NoiseDiagnostics, back: Callable[[NoiseDiagnostics], LevelProfile], split: Split | None
) -> NoiseDiagnostics:
    """``diag`` with the reversed grid's regimes when only they find the level varies.

    Notes
    -----
    Regimes are found on block medians: a burst shorter than half a block is seen by the
    grid that puts it in one block, not by the record's own grid when its last block,
    which takes the rest of the record (up to twice a block), joins it to quiet samples.
    A GPS track ending in 30 wild fixes was one level forwards and two regimes reversed,
    and its R to use flipped between R and the still R 66x below it (issue 26). So the
    level varies when the reversed grid finds a regime that is not still inside the
    record's last block (``back`` is called when that block is left out of the quiet set:
    a burst there raises its mean square). Elsewhere the two grids differ by a phase
    only: one huge spike's reach (Student-t noise) fits one block of either by chance,
    but a change that PELT makes at its penalty on one grid's phase and not on the other
    is hinted on the grid that does not make it (:attr:`LevelProfile.near_split`). A rest
    of 72-95 samples in motion was one level or three regimes, and its R to use R or the
    still R 9x below it, as 1-3 leading samples were dropped or the record reversed (7 of
    100 records, ``benchmarks/still_phase.py``); with the reversed grid's regimes there,
    which dropping leading samples does not move and reversal swaps with the record's,
    the split is made on both grids or on neither.
    """
    prof = diag.level_profile
    if any(not r.still for r in prof.regimes):
        return _short_motion_read_twice(diag, back, split)
    # a record in memory with a block left out reads a short burst there on the grid that
    # splits it (_split_reads): whether either grid hints it moves with their phases
    if prof.quiet[-1] and not prof.near_split and (split is None or prof.quiet.all()):
        return diag
    rev = back(diag)
    if all(r.still for r in rev.regimes):
        return diag
    n = diag.n
    mirrored = tuple(replace(r, start=n - r.stop, stop=n - r.start) for r in reversed(rev.regimes))
    # without a hint on the record's grid, only where it dilutes a burst that the reversed
    # one does not: its last block, which takes the rest of the record
    last = int(prof.start[-1])
    at_end = not prof.quiet[-1] and all(r.still or r.start >= last for r in mirrored)
    found = None if at_end or not _all_short(rev) else _split_reads(diag, mirrored, split)
    if found is not None:
        return replace(diag, level_profile=replace(prof, regimes=mirrored)) if found[0] else diag
    if not (at_end or (prof.near_split and _runs_of_motion(rev))):
        return diag
    return replace(diag, level_profile=replace(prof, regimes=mirrored))


def _short_motion_read_twice(
    diag: NoiseDiagnostics, back: Callable[[NoiseDiagnostics], LevelProfile], split: Split | None
) -> NoiseDiagnostics:
    """``diag`` with the reversed grid's one level when the record's grid finds motion
    only in regimes shorter than :data:`MOTION_RUN` blocks and the reversed grid none.

    Notes
    -----
    The mirror of :func:`_back_regimes`, which takes the reversed grid's regimes of
    motion onto a record's one level only when each spans :data:`MOTION_RUN` blocks, or
    lies in the record's last block (which takes the rest of the record). Read on the
    record reversed, that rule keeps a short regime of motion found on its own grid only
    there: elsewhere a burst shorter than half a block, its residuals spread by the
    smoother's span, lifts the median of the one block that holds it whole and of
    neither block that shares it (UCR InternalBleeding16's 12-sample anomaly: one block
    at 82x reversed, two at 2.8x and 3.1x forwards), so it was a regime reversed and not
    forwards, and the R to use moved x0.134. A short regime is kept when the reversed
    grid finds it too.
    """
    prof = diag.level_profile
    if any(k >= MOTION_RUN for k in _motion_blocks(prof)):
        return diag
    rev = back(diag)
    n = diag.n
    # the reversed grid's last block takes the rest of the record: a burst there, diluted
    # on that grid, is the record's own grid's to find (as _back_regimes' ``at_end``)
    tail = n - int(rev.start[-1])
    if not rev.quiet[-1] and all(r.still or r.stop <= tail for r in prof.regimes):
        return diag
    mirrored = tuple(replace(r, start=n - r.stop, stop=n - r.start) for r in reversed(rev.regimes))
    found = _split_reads(diag, prof.regimes, split) if _all_short(rev, True) else None
    if found is not None:
        one = [m for m in (mirrored, found[1]) if all(r.still for r in m)]
        if found[0] or not one:
            return diag
        return replace(diag, level_profile=replace(prof, regimes=one[0]))
    if not all(r.still for r in rev.regimes):
        return diag
    return replace(diag, level_profile=replace(prof, regimes=mirrored))


def _split_reads(
    diag: NoiseDiagnostics, regimes: tuple[Regime, ...], split: Split | None
) -> tuple[bool, tuple[Regime, ...]] | None:
    """Whether each short regime of motion in ``regimes`` is one on the block grid that
    splits it (:func:`~noisevar.diagnostics.split_grid.on_split_grid`), and that grid's
    regimes (the last read); None where a read is missing or the reads disagree.

    Notes
    -----
    The record's grid and its reversal's fall where the record's ends put them: dropping
    leading samples moves one and not the other, so a rule on the two grids, whichever it
    is, keeps or drops a burst shorter than a block at some phases only (seeded 14-sample
    bursts: 5 of 32 records moved with 1-3 dropped). The grid with a block edge at the
    burst's middle (the middle of the one-block windows that read it highest) is placed
    by the burst itself: no drop and no reversal moves it. It splits the burst about its
    middle, as a grid reads it weakest: a burst is motion where a grid that does not hold
    it whole finds it too, which the rule on both grids asked of two grids.
    """
    if split is None:
        return None
    motion = [r for r in regimes if not r.still]
    reads = [x for x in (split(diag, r.start, r.stop) for r in motion) if x is not None]
    # a read with no still regime has no level to set a burst against (a short record
    # whose blocks around jumps are left out): the rule on both grids decides
    if not reads or len(reads) < len(motion) or not all(_any_still(g) for _, g in reads):
        return None
    found = {any(not g.still and g.start <= c <= g.stop for g in got) for c, got in reads}
    return None if len(found) > 1 else (found.pop(), reads[-1][1])


def _any_still(regimes: tuple[Regime, ...]) -> bool:
    """Some regime of ``regimes`` is still."""
    return any(r.still for r in regimes)


def _all_short(prof: LevelProfile, none: bool = False) -> bool:
    """Every regime of ``prof`` that is not still spans under :data:`MOTION_RUN` blocks
    (and there is one, unless ``none``)."""
    blocks = _motion_blocks(prof)
    return all(k < MOTION_RUN for k in blocks) and (none or bool(blocks))


def _runs_of_motion(prof: LevelProfile) -> bool:
    """Every regime of ``prof`` that is not still spans :data:`MOTION_RUN` blocks or more:
    a stretch of motion, not one huge spike's reach (Student-t(3) noise: one block at
    13x, on one grid's phase)."""
    return all(k >= MOTION_RUN for k in _motion_blocks(prof))


def _motion_blocks(prof: LevelProfile) -> list[int]:
    """The number of blocks of ``prof`` in each of its regimes that is not still."""
    return [
        int(((prof.start >= r.start) & (prof.stop <= r.stop)).sum())
        for r in prof.regimes
        if not r.still
    ]

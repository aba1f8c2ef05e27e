"""The quiet level: the still regimes pooled, measured on the same residual as R (issue 26).

The level profile finds which blocks are quiet on the diagnostics' own residual (a fixed
span); a smooth signal leaks through it where R's method, which picks its spans from the
record, lets none through (a seasonal series: 14 against 0.04). So the level quoted as
the quiet level is measured with R's own method: on the still stretches (the estimate's
``.still``), or R itself when the whole record is quiet, or absent with a reason
(docs/algorithms.md §E1 *The quiet level*).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics import NoiseDiagnostics
from noisevar.diagnostics.held_share import held_share
from noisevar.diagnostics.profile import LevelProfile, on_both_grids, on_either_grid
from noisevar.diagnostics.quantisation import half_a_step, joined_step, second_difference_step
from noisevar.diagnostics.regimes import HELD, STILL, QuietLevel
from noisevar.errors import NoisevarError
from noisevar.estimators.results import VarianceEstimate
from noisevar.estimators.still_extent import to_the_sample
from noisevar.estimators.still_grids import (
    at_the_ends,
    grown_to_either,
    long_on_every_phase,
    may_leave,
    over_either_grid,
    shrunk,
)
from noisevar.estimators.still_set import (
    SAME,
    STILL_MIN,
    has_still_apart,
    no_quieter_level,
    one_level_reversed,
)

if TYPE_CHECKING:
    from noisevar.estimators.pipeline import Record


def on_still_stretches(
    record: Record | Any, params: dict, diag: NoiseDiagnostics, both: bool = True
) -> VarianceEstimate | None:
    """R's method on the still regimes' quiet stretches (:func:`still_estimate`'s estimate)."""
    return still_estimate(record, params, diag, both)[1]


def still_estimate(
    record: Record | Any, params: dict, diag: NoiseDiagnostics, both: bool = True
) -> tuple[list[tuple[int, int]], VarianceEstimate | None]:
    """R's method on the still regimes' quiet stretches, still on both block grids.

    Parameters
    ----------
    record : Record
        The record (``estimate_in`` and, when it has it, ``still_ranges``).
    params : dict
        R's method's parameters (``"method"`` is left out).
    diag : NoiseDiagnostics
        The record's diagnostics (its quiet blocks).
    both : bool
        Keep only what the reversed record's block grid finds still too (the record's
        ``still_ranges``: one more profile pass); False: the record's own grid.

    Returns
    -------
    ranges : list of (int, int)
        The sample ranges measured (before the samples around jumps are cut out).
    VarianceEstimate or None
        None when the record cannot be cut, the stretches are too short for the method, or
        their residual is all float rounding (held values, plus a trend: issue 26).
    """
    estimate_in = getattr(record, "estimate_in", None)
    if estimate_in is None:
        return [], None
    ranges = pieces = diag.level_profile.still_stretches
    back = back_of(record, diag) if both else None
    grids = getattr(record, "still_ranges", None) if both else None
    if ranges and back is not None:  # the fallbacks below start from the pieces on both grids
        pieces = on_both_grids(ranges, back(diag).still_stretches, diag.n)
        ranges = long_on_every_phase(pieces, diag.level_profile, back(diag), diag.n)
    elif ranges and grids is not None:
        ranges = pieces = grids(diag)
    kept = {k: v for k, v in params.items() if k != "method"}
    est = _measured(estimate_in, kept, ranges)
    if est is not None and back is not None and ranges:  # the extent known to a block
        prof = diag.level_profile
        either = on_either_grid(prof.still_stretches, back(diag).still_stretches, diag.n)
        for other in (either, shrunk(ranges, prof)):
            if other and other != ranges and may_leave(est, prof, ranges, other):
                est = over_either_grid(est, _measured(estimate_in, kept, other))
    if est is None and both:  # the quiet blocks in pieces: the still regimes themselves
        ranges = still_regime_ranges(diag, None if back is None else back(diag))
        est = _measured(estimate_in, kept, ranges)
    if est is None and back is not None and pieces:  # the record's ends on their own grids
        ends = at_the_ends(pieces, diag.level_profile, back(diag), diag.n)
        est = _measured(estimate_in, kept, ends) if ends != pieces else None
        ranges = ends if est is not None else ranges
    if est is None and back is not None and pieces:  # whole on either grid, still on both
        grown = grown_to_either(pieces, diag.level_profile, back(diag), diag.n)
        est = _measured(estimate_in, kept, grown) if grown != pieces else None
        est = None if est is None or _held_values(record, est, grown) else est
        ranges = grown if est is not None else ranges
    if est is None and back is not None and pieces:  # a short rest: its ends to the sample
        rest = to_the_sample(pieces, diag.level_profile, back(diag), _reader(record), diag.n)
        est = _measured(estimate_in, kept, rest)
        est = None if est is None or _held_values(record, est, rest) else est
        ranges = rest if est is not None else ranges
    if est is None:
        return ranges, None
    est.notes.append(f"the still regimes only: {len(ranges)} stretches, {est.n_total} samples")
    est.stretches = tuple((int(a), int(b)) for a, b in ranges)  # the fits' stretches too
    return ranges, est


def back_of(
    record: Record | Any, diag: NoiseDiagnostics
) -> Callable[[NoiseDiagnostics], LevelProfile] | None:
    """``back(diag)``: the reversed record's level profile, the one the diagnostics were
    read with when they hold it (``level_profile.back_grid``: no second profile, nor its
    PELT), else the record's ``back_profile``; None when the record has neither."""
    grid = diag.level_profile.back_grid
    if grid is not None and grid.profile is not None:
        made = grid.profile
        return lambda _diag: made
    return getattr(record, "back_profile", None)


def held_digits(
    record: Record | Any,
    diag: NoiseDiagnostics,
    still: VarianceEstimate | None,
    ranges: list[tuple[int, int]],
) -> QuietLevel | None:
    """Why a still R is held values, not noise (None when it may be noise): on a grid,
    :func:`held_on_grid`; off any grid, under the stored digits (below).

    Parameters
    ----------
    record : Record
        The record (its samples ``z`` in memory, or its ``reader()``), in the units of
        ``still``.
    diag : NoiseDiagnostics
        The record's diagnostics (its ``lsb``: the grid, :func:`held_on_grid`'s rule).
    still : VarianceEstimate or None
        R's method on the still stretches ``ranges``.
    ranges : list of (int, int)
        The still stretches it was measured on.

    Returns
    -------
    QuietLevel or None
        On a grid, :func:`held_on_grid`'s. Else absent (``source`` :data:`HELD`), with the
        reason, when the still stretches' second differences sit on a grid (the stored
        digits' last step ``δ``) and ``still`` is under half a step's error variance
        (:func:`~noisevar.diagnostics.quantisation.half_a_step`): the stretches hold their
        values and move only by the last stored digit, so what R's residual reads there is
        that digit's rounding, not the sensor's noise.

    Notes
    -----
    docs/algorithms.md §E3 (*Held values*): the same rule as a grid's (noise under half a
    step is no level of its own), where the grid is the stored digits of a stretch
    (MIDC's direct normal at night: the logger's floor, -0.433491, drifting by 1e-6,
    read 1.1e-13). A floor at δ²/12 would change nothing there (the level is about it),
    so there is no still R, said.
    """
    if still is not None and diag.lsb is not None:
        return held_on_grid(record, diag, still, ranges)
    if still is None or diag.lsb is not None or not _held_values(record, still, ranges):
        return None
    step = _digit_step(record, ranges)
    reason = (
        f"the still stretches hold their values, moving only by the last stored digit "
        f"({step:.3g}): they read {still.variance:.3g}, under the error of noise of half "
        "that step, so the sensor's noise is under what the record's digits hold "
        "(docs/algorithms.md §E3 Held values)"
    )
    return QuietLevel(None, None, None, diag.level_profile.quiet_share, HELD, reason)


def held_on_grid(
    record: Record | Any,
    diag: NoiseDiagnostics,
    still: VarianceEstimate,
    ranges: list[tuple[int, int]],
) -> QuietLevel | None:
    """Why a still R on a grid is held values, not noise (None when it may be noise).

    Parameters
    ----------
    record, diag, still, ranges
        As :func:`held_digits`; ``diag.lsb`` is the grid step.

    Returns
    -------
    QuietLevel or None
        Absent (``source`` :data:`HELD`), with the reason, when most of the stretches'
        second differences are 0 and far more of them than white noise of the still R's
        level gives on the grid they move on (their smallest move, at least ``lsb``), even
        at the low end of its 95 % interval
        (:class:`~noisevar.diagnostics.held_share.HeldShare`'s ``beyond_noise``).

    Notes
    -----
    docs/algorithms.md §E3 (*Held values*). A sensor at rest varies; a run of one value is
    padding, a stale sensor or a logger's hold, and the still R then rests on the few
    samples around it (the Permian gamma ray's log end: 60 of 65 samples one value, R to
    use 0.0045 against a redundant sensor's 3.8). Noise under half a step holds many values
    too, and as many as its level on the grid predicts: it keeps its still R.
    """
    read = _reader(record)
    if read is None or not ranges:
        return None
    held = held_share([read(a, b) for a, b in ranges], still.ci95[0], diag.lsb)
    if not held.beyond_noise:
        return None
    reason = (
        f"the still stretches are held values, {held.share:.0%} of their second differences "
        f"0 where noise of their level ({still.variance:.3g}) on a grid of their smallest "
        f"move ({held.step:.3g}) holds at most {held.noise:.1%}: padding, a stale sensor or a "
        "logger's hold, not the sensor at rest (docs/algorithms.md §E3 Held values)"
    )
    return QuietLevel(None, None, None, diag.level_profile.quiet_share, HELD, reason)


def _digit_step(record: Record | Any, ranges: list[tuple[int, int]]) -> float | None:
    """The step the stretches' second differences sit on (their last stored digit), None
    when they sit on none or the record cannot be read."""
    read = _reader(record)
    if read is None or not ranges:
        return None
    return joined_step([second_difference_step(read(a, b)) for a, b in ranges])


def _held_values(
    record: Record | Any, still: VarianceEstimate, ranges: list[tuple[int, int]]
) -> bool:
    """Whether ``still``, read on ``ranges``, is under half a step's error variance of the
    step their second differences sit on: held values, not noise (:func:`held_digits`).

    The still stretches grown to either grid (:func:`grown_to_either`) are not read where
    this holds, on a grid or not: a held stretch's few flips of the last digit move its
    reading with the grid's phase (MIDC UAT's accumulated energy at night: 2.8e-11, then
    7.2e-12 with a sample dropped, with the stored digit 1e-5)."""
    step = _digit_step(record, ranges)
    return bool(step is not None and step > 0 and still.variance < half_a_step(step))


def above_record(
    diag: NoiseDiagnostics, still: VarianceEstimate | None, record_r: VarianceEstimate
) -> QuietLevel | None:
    """Why a still R is no quiet level (:func:`~noisevar.estimators.still_set.not_quieter`
    against the first R; ``still_set.kept_still`` asks again on R as quoted): absent, for
    that reason (:func:`~noisevar.estimators.still_set.no_quieter_level`); None when it may be.
    """
    return None if still is None else no_quieter_level(diag, still, record_r.variance)


def _measured(
    estimate_in: Callable[[dict, list[tuple[int, int]]], VarianceEstimate],
    params: dict,
    ranges: list[tuple[int, int]],
) -> VarianceEstimate | None:
    """R's method on ``ranges`` (less the samples around jumps, pieces of at least
    :data:`STILL_MIN`); None when there is none, or its residual is all float rounding
    (held values, plus a trend: issue 26)."""
    if not ranges:
        return None
    try:
        est = estimate_in(params, ranges)
    except NoisevarError:
        return None
    return est if est.variance > 0.0 else None


def still_regime_ranges(
    diag: NoiseDiagnostics, back: LevelProfile | None = None
) -> list[tuple[int, int]]:
    """The still regimes' sample ranges, less one profile block at either end.

    Parameters
    ----------
    diag : NoiseDiagnostics
        The record's diagnostics (its regimes).
    back : LevelProfile, optional
        The reversed record's profile: what its still regimes hold is added (the two block
        grids that a reversal swaps; the union is the same stretches either way), when
        its level varies too (reversed, a record can be one regime, still by default and
        over its motion as well: a 75-sample rest in motion read 6x its noise).

    Returns
    -------
    list of (int, int)
        In order. Empty when the record's level does not vary (one regime).

    Notes
    -----
    docs/algorithms.md §E1 (*The still set*). The quiet set drops a still regime's blocks
    one by one (a tap, a flip of a held value on a grid, a logger's drift step), so a long
    still night can leave only pieces under :data:`STILL_MIN`; the regime itself, found on
    block medians that such blocks do not move, is the sensor still. Its edge blocks can
    hold part of the motion beside it (as ``still_levels.other_still_levels``); the samples
    around level jumps are cut out where R's method runs (``estimate_in``).
    """
    if not diag.level_varies:
        return []
    ranges = _trimmed(diag.level_profile)
    if back is None or all(r.still for r in back.regimes):  # one level reversed: no regime
        return ranges
    return on_either_grid(ranges, _trimmed(back), diag.n)


def regime_stretches(
    diag: NoiseDiagnostics, ranges: list[tuple[int, int]] | None = None
) -> list[tuple[int, int]]:
    """The still regimes' stretches, for a fit on one of them.

    Each still regime less one block at either end (:func:`still_regime_ranges`), or
    ``ranges`` (those a still R was measured on: ``VarianceEstimate.stretches``, which
    hold the reversed grid's too), cut at the blocks that lost residuals around a level
    jump (as ``LevelProfile.still_stretches``); pieces of at least :data:`STILL_MIN`
    samples, in order.
    """
    prof = diag.level_profile
    whole = np.zeros(diag.n, dtype=bool)
    for a, b in still_regime_ranges(diag) if ranges is None else ranges:
        whole[a:b] = True
    if prof.count is not None:
        for a, b, c in zip(prof.start, prof.stop, prof.count, strict=True):
            if c < b - a:
                whole[a:b] = False
    edges = np.flatnonzero(np.diff(np.r_[0, whole.view(np.int8), 0]))
    pieces = zip(edges[::2], edges[1::2], strict=True)
    return [(int(a), int(b)) for a, b in pieces if b - a >= STILL_MIN]


def _trimmed(prof: LevelProfile) -> list[tuple[int, int]]:
    """The still regimes of ``prof``, each less one block at either end."""
    edge = int(prof.stop[0] - prof.start[0]) if prof.start.size else 0
    spans = [(r.start + edge, r.stop - edge) for r in prof.regimes if r.still]
    return [(a, b) for a, b in spans if b - a >= STILL_MIN]


def quiet_apart(
    record: Record | Any,
    params: dict,
    diag: NoiseDiagnostics,
    variance: float,
    conclude: Callable[[VarianceEstimate], VarianceEstimate],
    core: float | None = None,
) -> QuietLevel | None:
    """The quiet level measured by a pass of R's method of its own, when it needs one.

    Parameters
    ----------
    record : Record
        The record (as :func:`on_still_stretches`).
    params : dict
        R's method's parameters.
    diag : NoiseDiagnostics
        The record's diagnostics.
    variance : float
        The record's R.
    conclude : callable
        ``conclude(est)``: the estimate with its interval widened as R's is.
    core : float, optional
        The record's core variance (R without its outlying samples), compared with the
        quiet blocks' level: R is the quiet level only when it is not above their interval.

    Returns
    -------
    QuietLevel or None
        Source ``"same"`` (R, :func:`quiet_level`) when nothing is quiet on the record's
        grid and the reversed grid finds one level
        (:func:`~noisevar.estimators.still_set.one_level_reversed`). Else
        None unless the record is of one level, its still stretches are not apart
        (:func:`~noisevar.estimators.still_set.has_still_apart`: no ``.still``), and the
        blocks left out of the quiet set change its level beyond its interval
        (:attr:`~noisevar.diagnostics.LevelProfile.one_quiet_level` False): the quiet
        blocks' level on R's residual is then neither R nor ``.still``. Absent, with the
        reason, when the quiet stretches are too short for the method.
    """
    prof = diag.level_profile
    if one_level_reversed(diag, variance):  # nothing quiet apart on either grid: R's level
        return QuietLevel(None, None, None, prof.quiet_share, SAME, _nothing_apart())
    level = variance if core is None else core
    if not prof.quiet.any() or _r_is_quiet(prof, level) or has_still_apart(diag, variance):
        return None
    # one grid: a record of one level has no motion beside its quiet stretches for the
    # other grid to cut off, and the reversed profile would cost a pass of its own
    est = on_still_stretches(record, params, diag, both=False)
    share = diag.level_profile.quiet_share
    if est is None:
        return QuietLevel(None, None, None, share, reason=_too_short(share))
    est = conclude(est)
    return QuietLevel(est.variance, *est.ci95, share, "quiet stretches")


def quiet_level(
    diag: NoiseDiagnostics,
    result: VarianceEstimate,
    still: VarianceEstimate | None,
    gap: str | None,
) -> QuietLevel:
    """The quiet level on the same residual as R, or why there is none.

    Parameters
    ----------
    diag : NoiseDiagnostics
        The record's diagnostics (``diag.quiet``: :func:`quiet_apart`'s, when it was).
    result : VarianceEstimate
        The record's R, concluded (its interval widened).
    still : VarianceEstimate or None
        R's method on the still stretches (the estimate's ``.still``).
    gap : str or None
        Why there is no still R to use
        (:func:`~noisevar.estimators.still_set.still_gap`).

    Returns
    -------
    QuietLevel
        ``.still`` when there is one; R itself, source ``"same"``, when the still stretches
        read R's level (``still_set.same_level``) or nothing is apart on either grid; else
        the level measured apart (:func:`quiet_apart`);
        else R itself when the record is one quiet level (every block quiet, or those left
        out change nothing the quiet level's interval can tell); else absent, with the
        reason (no quiet block, or still stretches too short for R's method).

    Notes
    -----
    docs/algorithms.md §E1 *The quiet level*. Every level is R's own method, so the
    quiet level and R are on one residual: a one-level record's quiet level is R, within
    their intervals by construction.
    """
    prof = diag.level_profile
    share = prof.quiet_share
    if still is not None:
        if not share and still.stretches:  # no quiet block: the still regimes measured
            share = sum(b - a for a, b in still.stretches) / max(diag.n, 1)
        return QuietLevel(still.variance, *still.ci95, share, STILL)
    if diag.quiet is not None and diag.quiet.source == SAME:  # R's level: R is the R to use
        return replace(diag.quiet, variance=result.variance, lo=result.ci95[0], hi=result.ci95[1])
    if diag.quiet is not None:
        return diag.quiet
    if prof.one_quiet_level:  # and R agrees with it, or quiet_apart measured it apart
        return QuietLevel(result.variance, *result.ci95, share, "record")
    if not prof.any_quiet:
        reason = "no stretch of the record is quiet (its level varies throughout)"
    elif gap:
        reason = gap.removeprefix("regimes='still': ")
    else:
        reason = _too_short(share)
    return QuietLevel(None, None, None, share, reason=reason)


def _r_is_quiet(prof: Any, level: float) -> bool:
    """R itself is the quiet level: the record is one quiet level (the blocks left out of
    the quiet set change nothing its interval can tell) and R's core (``level``) is not
    above that interval. Not when R holds what the profile's blocks do not see (the
    samples around level jumps: a still IMU tapped at its start, R's core 93x its still
    level): the quiet level is then measured apart. (A level below the interval is a
    signal leaking into the profile's residual and not into R's: R is the quiet level.)"""
    return bool(prof.one_quiet_level and level <= prof.quiet_interval[1])


def _reader(record: Record | Any) -> Callable[[int, int], NDArray] | None:
    """``read(a, b)``: samples ``a .. b`` of a record in its estimates' units (any segment
    of one in memory; a chunked record's reader; None when it has neither)."""
    z = getattr(record, "z", None)
    if z is not None:
        return lambda a, b: z[a:b]
    reader = getattr(record, "reader", None)
    return None if reader is None else reader()


def _nothing_apart() -> str:
    return (
        "the record's block grid finds no quiet block and the reversed record's finds one "
        "level with nothing apart, so R is the quiet level"
    )


def _too_short(share: float) -> str:
    return (
        f"the quiet stretches ({share:.0%} of the record) are in pieces shorter than the "
        f"{STILL_MIN} samples R's method needs (away from jumps)"
    )


def rounding_floor(still: VarianceEstimate, lsb: float | None) -> VarianceEstimate:
    """The still R on a grid of step ``lsb``: at least its rounding error lsb²/12.

    Parameters
    ----------
    still : VarianceEstimate
        R's method on the still stretches (the estimate's ``.still``).
    lsb : float or None
        The record's grid step (``diagnostics.lsb``), None when it is not on a grid.

    Returns
    -------
    VarianceEstimate
        ``still`` itself when it is at least lsb²/12 (or there is no grid); else lsb²/12,
        its core raised to it, the top of its interval σ²'s top plus lsb²/12 (the bottom
        stays the measurement's: off the grid, under a trend, the same stretches read
        it), with a note.

    Notes
    -----
    docs/algorithms.md §E3 (*Held values*). A sensor at rest whose noise is well under the
    grid step writes held values that flip by a step now and then: R's residual sees the
    flips, not the rounding error, which is a constant offset per stretch (uniform over
    the step from stretch to stretch). The error a filter sees there is σ² + lsb²/12 with σ
    under the step, so no still R under lsb²/12 is a noise level; the floor is the rounding
    error, the product's convention for data on a grid (the whole record's R has it
    already, §E3).
    """
    if lsb is None or not lsb > 0.0:
        return still
    q = lsb * lsb / 12.0
    if still.variance >= q:
        return still
    lo, hi = still.ci95
    note = (
        f"the still stretches read {still.variance:.4g}, under the rounding error "
        f"lsb²/12 = {q:.4g} of the grid step {lsb:.4g}: held values (the noise under the "
        "step), so the still R is that rounding error (docs/algorithms.md §E3)"
    )
    return replace(
        still,
        variance=q,
        ci95=(lo, hi + q),
        core_variance=None if still.core_variance is None else max(still.core_variance, q),
        notes=[*still.notes, note],
    )

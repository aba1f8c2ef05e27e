"""Trimming for ``auto``: outliers and jumps flagged, their neighbourhoods left out (§F5.3, §F5.4).

:func:`trimmed_blocks` turns every span's squared residuals into per-block sums with
the flagged samples' neighbourhoods zeroed, and keeps what a shorter span can recover.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import maximum_filter1d

from noisevar._distributions import norm_cdf, norm_pdf
from noisevar.errors import NoisevarError
from noisevar.estimators.auto._edges import bridge_edges, detection_squares, lone_glitches
from noisevar.estimators.auto._levels import (
    Above,
    Grids,
    above_medians,
    half_levels,
    kept_levels,
    rounding_floors,
)
from noisevar.estimators.auto._levels import above_local as _above_local
from noisevar.estimators.auto._levels import bracketing as _bracketing
from noisevar.numeric.blocks import (
    block_counts,
    block_square_sums,
    block_sums,
    chosen_above_sums,
    dilate,
    flagged_per_block,
)
from noisevar.numeric.steps import STEP_MAX_FRACTION, lone_steps, step_flags
from noisevar.numeric.sweeps import near_any, window_counts

#: Trimmed samples are widened by half of this span (or of the longest span below it).
AUTO_MASK_SPAN = 41
AUTO_BLOCK = 256
#: The core (``core_variance``) leaves out squares beyond this many local standard deviations
#: (or ``trim``, if lower): a contaminant below ``trim`` is not an outlier but is no bulk.
AUTO_CORE_TRIM = 3.5
#: The fast-signal rule's window, in blocks, centred on each flag (§F5.3).
WINDOW_BLOCKS = 2
#: Runs of at most this many outlying samples are glitches to the step detector (§F5.3).
GLITCH_MAX = 2


def auto_block(n: int) -> int:
    """Samples per block of ``auto`` on a record of ``n`` samples (a short record: one block)."""
    return AUTO_BLOCK if n >= 2 * AUTO_BLOCK else min(max(n // 2, 16), n)


def _truncated_second_moment(kappa: float) -> float:
    """``E[Z² ; |Z| < κ] / P(|Z| < κ)`` for a standard normal ``Z``."""
    p = 2.0 * norm_cdf(kappa) - 1.0
    return float((p - 2.0 * kappa * norm_pdf(kappa)) / p)


def core_trimmed(
    sq: NDArray,
    b: _Blocks,
    choice: NDArray,
    sums: tuple[NDArray, NDArray],
    kappa: float,
) -> tuple[NDArray, NDArray]:
    """The core's block sums and counts with the squares beyond ``κ_c`` left out (§F5.4).

    ``sq`` holds every span's squares with the flagged neighbourhoods zeroed, ``choice``
    each block's span and ``sums`` its chosen sums and counts (recovered samples in).
    Each kept square of the chosen span above ``κ_c²`` times the bracketing level
    (:func:`_above_local`; the level ``sum / (count τ(κ))`` without the sample) leaves the
    core, and so does a recovered one: a contaminant below the outlier threshold ``κ`` is
    no outlier, yet no bulk either (F5.7b).
    """
    chosen_sum, counts = sums
    if not np.isfinite(kappa):
        return chosen_sum, counts
    c = min(kappa, AUTO_CORE_TRIM)
    block, nb = b.block, b.nb
    with np.errstate(invalid="ignore", divide="ignore"):
        # e² > c² (S - e²) / ((N - 1) τ): the level without the sample itself (which would
        # raise its own threshold: +0.15 % on Gaussian noise at c = 3.5)
        local = c**2 * chosen_sum / ((counts - 1.0) * _truncated_second_moment(kappa) + c**2)
    local = np.where(np.isfinite(local), local, np.inf)  # an all-trimmed block: nothing
    # the squares above the bracketing level (compiled: one pass, no gathered copy)
    out = None if block % 2 else chosen_above_sums(sq, choice, local, half_levels(local), block)
    out_sum, out_n = out if out is not None else _above_sums(sq, choice, local, block)
    if b.recover is not None:
        near, usable, values = b.recover
        rows = np.minimum(near // block, nb - 1)
        v = values[np.minimum(choice[rows], usable), np.arange(near.size)]
        far = v > _bracketing(near, local, block)
        out_sum += np.bincount(rows[far], weights=v[far], minlength=nb)
        out_n += np.bincount(rows[far], minlength=nb)
    return np.maximum(chosen_sum - out_sum, 0.0), counts - out_n


def _above_sums(
    sq: NDArray, choice: NDArray, local: NDArray, block: int
) -> tuple[NDArray, NDArray]:
    """:func:`~noisevar.numeric.blocks.chosen_above_sums` in NumPy (any block)."""
    nb, n = local.size, sq.shape[1]
    x = np.empty(n)
    x[: nb * block].reshape(nb, block)[:] = sq[:, : nb * block].reshape(-1, nb, block)[
        choice, np.arange(nb)
    ]
    x[nb * block :] = sq[choice[-1], nb * block :]
    idx = np.flatnonzero(_above_local(x, local, block))
    rows = np.minimum(idx // block, nb - 1)
    out_sum = np.bincount(rows, weights=x[idx], minlength=nb).astype(float)  # int if empty
    return out_sum, np.bincount(rows, minlength=nb).astype(float)


def _outlier_mask(
    sq: NDArray,
    kappa: float,
    block: int,
    widen: int,
    steps: Callable[[Callable[[NDArray], NDArray], float, NDArray], tuple] | None,
    step_limit: float,
    after: int = 0,
    z: NDArray | None = None,
) -> tuple[NDArray | None, NDArray | None, NDArray | None]:
    """Squared residuals that are outliers, and samples next to jumps (the caller widens both).

    Pass 1 takes a robust local scale from block medians of ``e²`` (of every
    sample: a subsample's phase would move with the samples dropped before it);
    pass 2 refines it with the mean of each block's kept squares, so that a
    noise level changing along the record is followed (a noise step is not
    mistaken for outliers). Residuals beyond ``κ`` local standard
    deviations are flagged, and so are samples next to a jump found by
    ``steps(above, κ²)`` (:func:`step_mask`). Pass 1 leaves ``widen``
    neighbours on each side of what it flags out of the scale (a jump spreads
    over the whole span of the residual sequence); the returned mask is not
    widened, so that the caller can widen it by each span's half. Each is
    None when nothing is flagged (the common case, which then costs no
    masking). Jumps are kept while the detector flags at most ``step_limit``
    samples (more: a fast signal); the third value is what it flagged (None: nothing).
    Every level is read on two grids, from the window's start and from the record's end,
    ``after`` samples past the window (:mod:`~noisevar.estimators.auto._levels`): a sample
    is above only when above on both, so that the reversed record sees the same levels.
    No level is below the rounding of the samples ``z`` (the window's; :func:`rounding_floors`).
    """
    g = Grids.make(sq.size, block, after)
    scale = kappa**2 / 0.4549364231195724  # the median of χ²₁ is 0.4549
    floors = None if z is None else rounding_floors(z, g)
    first = above_medians(sq, g, scale, floors)  # the block medians' flags
    idx = None
    if first.any():
        if widen > 0:  # leave the whole neighbourhood of a jump out of the scale
            first = dilate(first, widen)
        idx = np.flatnonzero(first)
    # κ² times the local variance of each block on both grids (held at its centre)
    k = kappa**2 / _truncated_second_moment(kappa)
    fwd, bwd = kept_levels(sq, idx, g, k, floors)
    above = Above(fwd, bwd, g, None if floors is None else (k * floors[0], k * floors[1]))
    outlier = above(sq)
    jumps, found = None, None
    if steps is not None:
        found, lone, plain = steps(above, kappa**2, outlier)
        if step_limit >= 0 and found.any():
            jumps = _believed(found, block, lone, plain)
    return (outlier if outlier.any() else None), jumps, found


def _believed(
    found: NDArray, block: int, lone: NDArray | None = None, plain: NDArray | None = None
) -> NDArray | None:
    """The jump samples ``found`` that are jumps, not a fast signal (§F5.3).

    Lone steps ``lone`` (:func:`~noisevar.numeric.steps.lone_steps`: one jump's response
    between two quiet straight sides; None: none) are jumps: a step is one event, whatever
    its size and however many others share the record. Of the other flags, one with more than
    :data:`STEP_MAX_FRACTION` of the ``WINDOW_BLOCKS * block`` samples centred on it
    flagged (at the record's edges the window is moved inward, not cut short: a cluster of
    jumps near an edge is not judged on fewer samples; lone steps not counted) sees a
    fast signal, not a jump: its flag is dropped, and so is any flag within half that
    window of it (the fast stretch's edge, lone or not).
    The window is centred on the sample, not on a block grid anchored at the record's
    start, so that reversing the record moves no decision but through ``found`` itself.
    ``plain`` (a short record whose levels the detector raised to its statistic's own:
    :class:`~noisevar.numeric.steps.StepFlags`): the flags at the levels before, which
    are counted instead (at the raised levels a fast signal flags under the fraction).
    """
    rest = found if lone is None else found & ~lone
    idx = np.flatnonzero(rest)
    if not idx.size:
        return found
    half = WINDOW_BLOCKS * block // 2
    # the window of 2 half + 1 samples (the record, if shorter) lies inside the record: at
    # an edge it is moved inward, not cut short, so that every flag is judged on as many
    # samples (the mirror image at the other edge: symmetric in time)
    size = min(2 * half + 1, found.size)
    lo = np.clip(idx - half, 0, found.size - size)
    hi = lo + size - 1
    counted = idx if plain is None else np.flatnonzero(plain if lone is None else plain & ~lone)
    fast = window_counts(counted, lo, hi) > STEP_MAX_FRACTION * size
    if not fast.any():
        return found
    # a flag within half the window of a fast one is the same fast stretch (its edge)
    at = idx[fast]
    idx = np.flatnonzero(found)
    near = near_any(idx, at, half)
    out = found.copy()
    out[idx[near]] = False
    return out if out.any() else None


def _near_flagged(
    flagged: NDArray, idx: NDArray, spans: tuple[int, ...], half: int, sq: NDArray
) -> tuple[NDArray, NDArray, NDArray] | None:
    """Samples of the common mask ``idx`` that a shorter span can still use.

    The common mask widens flagged samples by ``half``; the residual of a
    span ``s`` at sample ``k`` reaches ``s // 2`` samples either way, so a
    sample more than ``s // 2`` from every flagged one has a clean residual
    for that span. Returns the indices of such samples, the longest usable
    span index of each, and their squared residuals for the spans up to it
    (before the caller zeroes the masked ones), or None.
    """
    usable = np.full(idx.size, -1)
    for j, s in enumerate(spans):
        if s // 2 >= half:
            break
        usable[~dilate(flagged, s // 2)[idx]] = j
    keep = usable >= 0
    if not keep.any():
        return None
    near = idx[keep]
    return near, usable[keep], sq[: int(usable.max()) + 1, near].copy()


@dataclass
class _Blocks:
    """Per-block sums of every span's squared residuals, after trimming (§F5.4)."""

    block: int
    nb: int
    kept_count: NDArray  # (nb,) samples kept per block
    block_sum: NDArray  # (n_spans, nb)
    fourth: NDArray  # (nb,) sums of the shortest span's e⁴
    total_fourth: NDArray  # (nb,) the same off the jumps alone (outliers kept: §E1 tails)
    clean_for: NDArray  # (n_spans, nb) span j's residuals untouched by a flagged sample
    recover: tuple[NDArray, NDArray, NDArray] | None  # see _near_flagged
    total_count: NDArray  # (nb,) samples off the jumps (outliers kept: they are noise)
    total_sum: NDArray  # (n_spans, nb) their sums
    outliers: NDArray  # samples that are outliers (one per spike)
    clean_total: NDArray  # (n_spans, nb) as clean_for, for the jumps alone
    recover_total: tuple[NDArray, NDArray, NDArray] | None  # as recover, near the jumps
    jumps: NDArray  # samples left out around jumps (widened; all False when none)
    found: NDArray  # indices of the samples the jump detector flagged (before its limit)
    near_jumps: NDArray  # outlying samples in a jump's neighbourhood (one per spike; left out)


def _flag(
    z: NDArray,
    sq0: NDArray,
    trim: float,
    block: int,
    half: int,
    step_limit: float | None,
    after: int = 0,
    start: bool = True,
    detect: tuple[int, int] | None = None,
) -> tuple:
    """Outliers, jumps (None when none) and what the jump detector flagged, from the shortest span.

    ``step_limit``: at most this many jump samples are believed (default: a fifth of ``z``);
    ``after``: samples of the record after ``z`` (a chunk's window; see :func:`_outlier_mask`);
    ``start``: ``z`` starts where the record does; ``detect``: the span and order of
    ``sq0`` (a longer run of outlying samples may then be one glitch: _edges.lone_glitches).
    """
    if not np.isfinite(trim):
        return None, None, None
    limit = STEP_MAX_FRACTION * z.size if step_limit is None else step_limit
    ends = (start, after == 0)
    return _outlier_mask(
        sq0, trim, block, half, lambda v, sc, out: _steps(z, out, v, sc, ends, detect), limit,
        after, z,
    )  # fmt: skip


def _steps(
    z: NDArray,
    outliers: NDArray,
    above: Callable[[NDArray], NDArray],
    scale: float,
    ends: tuple[bool, bool] = (True, True),
    detect: tuple[int, int] | None = None,
) -> tuple[NDArray, NDArray, NDArray | None]:
    """The step detector's flags on ``z`` with its glitches bridged, its lone steps (at the
    levels it confirmed them at) and :class:`~noisevar.numeric.steps.StepFlags`' ``plain``.

    ``ends``: whether ``z`` starts (ends) where the record does (a glitch there, _edges);
    ``detect``: see :func:`_flag`.
    """
    lone = None if detect is None else (above, detect)
    bridged = _bridged(z, outliers, ends, lone)
    flags = step_flags(bridged, above, scale)
    found = flags.found
    return found, lone_steps(bridged, found, flags.levels, scale), flags.plain


def _bridged(
    z: NDArray,
    outliers: NDArray,
    ends: tuple[bool, bool] = (True, True),
    lone: tuple[Above, tuple[int, int]] | None = None,
) -> NDArray:
    """``z`` with its isolated outlying samples replaced by the line between their neighbours.

    A glitch is one or two samples: bridged, the step detector sees nothing there (on a
    fast signal its window medians alone can be moved by the signal's curvature, §F5.3).
    A jump persists on both sides of the samples it makes outlying, and a tap of motion
    rings over several: runs of more than :data:`GLITCH_MAX` outlying samples are left
    as they are, for the detector to judge.
    """
    o = np.flatnonzero(outliers)
    if not o.size:
        return z
    cut = np.r_[False, np.diff(o) > 1]
    run = np.cumsum(cut)  # the run of each outlying sample
    a, b = o[np.r_[True, cut[1:]]], o[np.r_[cut[1:], True]] + 1
    # a run at the record's edge: one glitch, spread by the one-sided rows over more
    # samples than inside; the fit without it finds it (_edges.bridge_edges)
    edge = np.zeros(a.size, dtype=bool)
    edge[0] |= bool(ends[0] and a[0] == 0)
    edge[-1] |= bool(ends[1] and b[-1] == z.size)
    short = ((b - a) <= GLITCH_MAX) & ~edge
    glitch = o[short[run]]
    if glitch.size == z.size:
        return z
    out = z.copy()
    if edge.any():
        out = bridge_edges(out, list(zip(a[edge], b[edge], strict=True)))
    if lone is not None:  # a longer run inside: one glitch when its sample explains it
        runs = list(zip(a[~short & ~edge], b[~short & ~edge], strict=True))
        for j, value in lone_glitches(z, runs, lone[0].at, lone[1]):
            out[j] = value
    if not glitch.size:
        return out
    # each glitch lies between the samples just outside its run, which are no glitch: the
    # line through those two (np.interp over them alone picks the same pair, so the same
    # numbers as over every sample that is no glitch)
    sides = np.unique(np.r_[a[short] - 1, b[short]])
    sides = sides[(sides >= 0) & (sides < z.size)]
    out[glitch] = np.interp(glitch, sides, out[sides])
    return out


def _zero(sq: NDArray, flags: NDArray | None, half: int, block: int, nb: int) -> NDArray:
    """Zero the squares within ``half`` of ``flags`` in place; the samples left out per block."""
    if flags is None:
        return np.zeros(nb)
    idx = np.flatnonzero(dilate(flags, half) if half > 0 else flags)
    if idx.size == sq.shape[1]:
        raise NoisevarError("every residual was trimmed as an outlier: the signal is not usable")
    sq[:, idx] = 0.0
    return flagged_per_block(idx, block, nb)


def _recoverable(
    flags: NDArray | None, spans: tuple[int, ...], half: int, sq: NDArray
) -> tuple[NDArray, NDArray, NDArray] | None:
    """:func:`_near_flagged` for the mask of ``flags`` widened by ``half`` (None: no flags)."""
    if flags is None:
        return None
    idx = np.flatnonzero(dilate(flags, half) if half > 0 else flags)
    return _near_flagged(flags, idx, spans, half, sq)


def _trimmed_blocks(
    z: NDArray,
    sq: NDArray,
    spans: tuple[int, ...],
    trim: float,
    step_limit: float | None = None,
    after: int = 0,
    start: bool = True,
    order: int | None = None,
) -> _Blocks:
    """Flag jumps and outliers, zero their neighbourhoods in ``sq`` and sum the blocks.

    Block sums are taken twice: with only the jumps left out (the total variance:
    outliers are noise) and with outliers left out too (the core, §F5.4). ``start``:
    ``z`` starts where the record does (see :func:`_flag`).
    """
    m = z.size
    block = auto_block(m)
    nb = max(1, m // block)
    # flagged samples are widened by half the longest span up to AUTO_MASK_SPAN; a
    # longer span is used only in blocks that its wider neighbourhood leaves alone
    half = max(s for s in spans if s <= max(AUTO_MASK_SPAN, spans[0])) // 2
    det = detection_squares(z, sq[0], spans[0], (start, after == 0))  # a glitch at an edge
    detect = None if order is None else (spans[0], order)
    outliers, jumps, found = _flag(z, det, trim, block, half, step_limit, after, start, detect)
    flagged = jumps if outliers is None else outliers if jumps is None else outliers | jumps
    # before any zeroing: the values near jumps (for the total) and near every flag
    sq0_copy = sq[0] if outliers is None else sq[0].copy()
    recover_total = _recoverable(jumps, spans, half, sq)
    recover = recover_total if outliers is None else _recoverable(flagged, spans, half, sq)
    total_count = block_counts(block, nb, m) - _zero(sq, jumps, half, block, nb)
    total_sum = np.stack([block_sums(q, block, nb) for q in sq])
    total_fourth = block_square_sums(sq[0], block, nb)
    clean_total = _clean_for(jumps, spans, half, block, nb)
    # without outliers the flagged samples are the jumps': the same sums, not taken again
    kept_count, block_sum, fourth, clean_for = total_count, total_sum, total_fourth, clean_total
    out_at = near = np.zeros(0, dtype=int)
    if outliers is not None:
        kept_count = block_counts(block, nb, m) - _zero(sq, flagged, half, block, nb)
        block_sum = np.stack([block_sums(q, block, nb) for q in sq])
        fourth = block_square_sums(sq[0], block, nb)
        clean_for = _clean_for(flagged, spans, half, block, nb)
        # residuals next to a jump are the jump's, not outliers
        alone = outliers if jumps is None else outliers & ~dilate(jumps, half)
        # one outlying sample spreads over its neighbours' residuals: count the peaks
        out_at = _local_peaks(sq0_copy, np.flatnonzero(alone), spans[0])
        if jumps is not None:  # for the diagnostics (estimators.glitches)
            near = _local_peaks(sq0_copy, np.flatnonzero(outliers & ~alone), spans[0])
    return _Blocks(
        block, nb, kept_count, block_sum, fourth, total_fourth, clean_for,
        recover, total_count, total_sum, out_at, clean_total,
        recover_total, np.zeros(m, dtype=bool) if jumps is None else dilate(jumps, half),
        np.zeros(0, dtype=int) if found is None else np.flatnonzero(found), near,
    )  # fmt: skip


def _local_peaks(x: NDArray, idx: NDArray, size: int) -> NDArray:
    """The ``idx`` where ``x`` is the largest of the ``size`` samples centred there (to 1e-9).

    ``maximum_filter1d(x, size)[idx] == x[idx]``, reading only the windows around ``idx``
    (the filter's reflected edges hold no value outside the clipped window).
    """
    if idx.size * size > x.size:  # many: one pass of the filter is cheaper
        top = maximum_filter1d(x, size)[idx]
    else:
        reach = np.arange(-(size // 2), size // 2 + 1)
        top = x[np.clip(idx[:, None] + reach, 0, x.size - 1)].max(axis=1, initial=-np.inf)
    # equal to rounding counts as the largest: at an edge a short span's rows read one
    # glitch as the same square on several samples (span 5: three; _edges moves it to its own)
    return idx[x[idx] >= top * (1.0 - 1e-9)]


def _clean_for(
    flags: NDArray | None, spans: tuple[int, ...], half: int, block: int, nb: int
) -> NDArray:
    """Per span and block: no flagged sample within the span's reach beyond the mask's."""
    clean = np.ones((len(spans), nb), dtype=bool)
    if flags is None:
        return clean
    per_block = flagged_per_block(np.flatnonzero(dilate(flags, half)), block, nb)
    for j, s in enumerate(spans):
        if s // 2 > half:
            wide = flagged_per_block(np.flatnonzero(dilate(flags, s // 2)), block, nb)
            clean[j] = wide == per_block
    return clean

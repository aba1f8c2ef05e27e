"""Level jumps: a step detector blind to parabolas, confirmed by window medians.

``auto`` leaves the samples around a jump out as signal (docs/algorithms.md §F5.3).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache
from typing import NamedTuple

import numpy as np
from numpy.typing import NDArray

from noisevar._distributions import chi2_ppf
from noisevar.numeric.fir import centred_rows

try:  # the compiled slope medians (numba); np.median below is the reference
    from noisevar.numeric import _steps_numba
except ImportError:  # pragma: no cover - numba not installed
    _steps_numba = None  # type: ignore[assignment]

#: The compiled slope medians of :func:`detrended_windows` and the compiled confirmation
#: (:func:`_confirmed`) while true (and numba is installed); false selects the NumPy
#: references (the same numbers, tested).
COMPILED: bool = _steps_numba is not None

STEP_WINDOW = 6
STEP_THRESHOLD = 6.0
#: A candidate jump is confirmed where the third difference of window *medians* stands this
#: many standard deviations out: a persistent level change moves medians, an isolated spike
#: (heavy-tailed noise, a glitch) does not.
STEP_CONFIRM = 4.0
#: Above this fraction of flagged samples the step detector is ignored: what it sees is a
#: fast signal (a sinusoid of a few tens of samples per period), not jumps. Lone steps
#: (:func:`lone_steps`) are single jumps whatever the fraction.
STEP_MAX_FRACTION = 0.2
#: A lone step's sides are straight lines within the noise unless their residual exceeds
#: this upper quantile of its chi-squared law (:func:`lone_steps`).
STEP_SIDES_ALPHA = 1e-3


def step_mask(
    z: NDArray, above: Callable[[NDArray], NDArray], scale: float = 1.0, w: int = STEP_WINDOW
) -> NDArray:
    """Samples next to a jump, found by a step detector blind to parabolas
    (:func:`step_flags`' first value)."""
    return step_flags(z, above, scale, w).found


class StepFlags(NamedTuple):
    """What the step detector flagged, and at which levels (:func:`step_flags`)."""

    found: NDArray
    #: The levels the flags were confirmed at (raised to the statistic's own, or ``above``).
    levels: Callable[[NDArray], NDArray]
    #: Where the levels were raised over the whole window (a short record): the flags at the
    #: levels before the raise, which judge a fast signal (None: not raised so).
    plain: NDArray | None = None


def step_flags(
    z: NDArray, above: Callable[[NDArray], NDArray], scale: float = 1.0, w: int = STEP_WINDOW
) -> StepFlags:
    """Samples next to a jump, found by a step detector blind to parabolas.

    With ``M[i] = mean(z[i:i+w])``, ``D3[k] = M[k+w] - 3 M[k] + 3 M[k-w] -
    M[k-2w]`` is the third difference of four adjacent window means: zero on
    any parabola (a ramp, a turn), while a jump ``J`` gives ``|D3|`` up to
    ``2 J`` against a noise standard deviation ``σ sqrt(20 / w)``. At
    ``w = 6`` a jump of 6 σ stands 6.6 standard deviations out, where the
    cubic residual shows it only at about 2.5 (a local cubic absorbs most of
    a jump). A fast signal (a sinusoid of 30 samples per period, say) also
    trips it; the caller then ignores it (:data:`STEP_MAX_FRACTION`).

    ``above(x)`` tells where ``x`` exceeds ``scale`` times the local noise
    variance; ``found`` holds the samples where ``|D3|``
    exceeds :data:`STEP_THRESHOLD` standard deviations, each with its left neighbour
    (``D3[k]`` is centred between samples ``k - 1`` and ``k``), at ``above``'s levels
    raised to the statistic's own where that stands above white noise's
    (:func:`_own_levels`; ``levels``, and ``plain`` when raised over the whole window:
    then only lone steps are jumps whatever the fraction, and the others are judged a
    fast signal by ``plain``'s fraction, docs/algorithms.md §F5.3). (The scale is folded
    into the window means, so the test costs no pass of its own: two work
    arrays, the third differences written in place.)
    """
    n = z.size
    if n < 4 * w:
        return StepFlags(np.zeros(n, dtype=bool), above)
    # mm[i] = mean(z[i:i+w]), pre-scaled so that D3² compares with threshold_var directly
    gain = np.sqrt(scale / (STEP_THRESHOLD**2 * 20.0 / w)) / w
    mm = np.convolve(z, np.full(w, gain), mode="valid")  # n - w + 1
    work = np.empty(n)
    d1 = work[: n - 2 * w + 1]
    np.subtract(mm[w:], mm[:-w], out=d1)  # third difference at lag w, as three first ones
    d2 = mm[: n - 3 * w + 1]
    np.subtract(d1[w:], d1[:-w], out=d2)
    d3 = work[2 * w : n - 2 * w + 1]  # D3 at k = 2w .. n - 2w, aligned with the samples
    np.subtract(d2[w:], d2[:-w], out=d3)
    np.multiply(d3, d3, out=d3)
    work[: 2 * w] = 0.0  # D3 is not defined there: no jump can be seen
    work[n - 2 * w + 1 :] = 0.0
    candidates = _above_both_sides(work, above)
    if not candidates.any():
        return StepFlags(candidates, above)
    idx = np.flatnonzero(candidates)
    own = _own_levels(work, candidates, above)
    plain = None
    if getattr(own, "whole", False):  # raised over a short record: the flags before, too
        first = np.zeros_like(candidates)
        first[idx] = True
        plain = _paired(_confirm_steps(z, first, above, scale, w))
    if not candidates.any():
        return StepFlags(candidates, own, plain)
    return StepFlags(_paired(_confirm_steps(z, candidates, own, scale, w)), own, plain)


def _paired(out: NDArray) -> NDArray:
    """``D3`` at ``k`` is centred on the boundary between samples ``k - 1`` and ``k``: both
    are flagged, so that the reversed record flags the same samples (symmetric in time)."""
    out[:-1] = out[:-1] | out[1:]
    return out


def _own_levels(
    work: NDArray, candidates: NDArray, above: Callable[[NDArray], NDArray]
) -> Callable[[NDArray], NDArray]:
    """``above`` with its levels raised to ``D3``'s own where the noise is not white, and
    ``candidates`` (in place) those still above.

    The levels are the residual's, and ``D3`` of white noise at that level has a known
    variance; low-passed noise (a sensor's own filter) gives ``D3`` far more (window means
    wander), so at the white threshold it flagged a fifth of every record as jumps, then a
    fast signal (:data:`STEP_MAX_FRACTION`) whose true steps stayed in R (x1e4, issue 26).
    ``above.raised(work, idx, expected)`` raises each level where the block's own median of
    ``work`` stands well above ``expected`` times it (``None``: a plain callable, kept).
    """
    raised = getattr(above, "raised", None)
    if raised is None:
        return above
    idx = np.flatnonzero(candidates)
    own = raised(work, idx, STEP_THRESHOLD**-2)
    if own is not above:
        candidates[idx] = _above_both_sides_at(work[idx], idx, own, work.size)
    return own


def _above_both_sides(x: NDArray, above: Callable[[NDArray], NDArray]) -> NDArray:
    """``above(x)`` at ``k`` and at ``k - 1`` alike: ``x[k]`` is centred between the two.

    The local level may change between two samples; testing against both keeps the
    decision the same on the reversed record (where the boundary's sample is ``k - 1``).
    """
    sides = getattr(above, "sides", None)
    hit = None if sides is None else sides(x)  # compiled: the same flags in one pass
    if hit is not None:
        return hit
    floor = getattr(above, "floor", None)
    if floor is not None and getattr(above, "at", None) is not None:
        # no sample at or below the lowest level is above: compare only the others
        idx = np.flatnonzero(x > floor)
        idx = idx[above.at(x[idx], idx)]  # type: ignore[attr-defined]
        hit = np.zeros(x.size, dtype=bool)
    else:
        hit = above(x)
        idx = np.flatnonzero(hit)
    if idx.size:
        idx = idx[idx > 0]
        left = above_at(above, x[idx], idx - 1, x.size)
        hit[:] = False
        hit[idx[left]] = True
    return hit


def above_on_two_grids(
    x: NDArray, floor: float, halves: tuple[NDArray, NDArray], first: float, half: int, q: int
) -> NDArray | None:
    """``x[k]`` above the levels of both samples ``k`` and ``k - 1`` on two grids (None: no numba).

    Parameters
    ----------
    x : ndarray, shape (n,)
    floor : float
        No value at or below it is above (a screen).
    halves : (ndarray, ndarray)
        The level of each half block of ``half`` samples from the window's start (the last
        for the rest), and the same on the reversed window after its first ``q`` samples.
    first : float
        The level of the samples past the reversed grid's start.

    Returns
    -------
    ndarray of bool or None
        False at ``k = 0``.
    """
    if not COMPILED or _steps_numba is None:
        return None
    fwd, bwd = halves
    return _steps_numba.above_both_sides(
        np.ascontiguousarray(x, dtype=float), floor, fwd, bwd, first, half, q
    )


def above_on_two_grids_at(
    values: NDArray, idx: NDArray, halves: tuple[NDArray, NDArray], first: float, half: int, m: int
) -> NDArray | None:
    """:func:`above_on_two_grids` of samples that are ``values`` at ``idx``, read there only.

    ``m``: the samples of the reversed grid (the window's less its first ``q``); None: no numba.
    """
    if not COMPILED or _steps_numba is None:
        return None
    fwd, bwd = halves
    return _steps_numba.above_both_sides_at(
        np.ascontiguousarray(values, dtype=float), _ints(idx), fwd, bwd, first, half, m
    )


def above_at(above: Callable[[NDArray], NDArray], values: NDArray, idx: NDArray, n: int) -> NDArray:
    """``above(x)[idx]`` for the ``n`` samples ``x`` that are ``values`` at ``idx``, 0 elsewhere.

    ``above`` compares each sample with its own local level (0 is never above a level
    of squares), so only ``idx`` are compared: through ``above.at(values, idx)`` when it
    has one (no array the window's size), else on a probe that is 0 elsewhere.
    """
    at = getattr(above, "at", None)
    if at is not None:
        return at(values, idx)
    probe = np.zeros(n)
    probe[idx] = values
    return above(probe)[idx]


def _above_both_sides_at(
    values: NDArray, idx: NDArray, above: Callable[[NDArray], NDArray], n: int
) -> NDArray:
    """:func:`_above_both_sides` at the sorted ``idx`` of ``n`` samples 0 but ``values`` there."""
    sides_at = getattr(above, "sides_at", None)
    hit = None if sides_at is None else sides_at(values, idx)  # compiled: the same flags
    if hit is not None:
        return hit
    hit = above_at(above, values, idx, n) & (idx > 0)
    hit[hit] = above_at(above, values[hit], idx[hit] - 1, n)
    return hit


@lru_cache(maxsize=8)
def _median_variance(w: int) -> float:
    """Variance of the median of ``w`` standard normal samples (seeded Monte Carlo, 2e5 draws)."""
    x = np.random.default_rng(0).standard_normal((200_000, w))
    return float(np.var(np.median(x, axis=1)))


#: A sorting network of six values (12 comparators; it sorts every 0-1 input, so every input).
SORT6 = (
    (0, 5), (1, 3), (2, 4), (1, 2), (3, 4), (0, 3), (2, 5), (0, 1), (2, 3), (4, 5), (1, 2), (3, 4),
)  # fmt: skip


#: The values :data:`SORT6` sorts.
SORT6_VALUES = sorted({i for pair in SORT6 for i in pair})
_NET = np.array(SORT6, dtype=np.int64)  # for the compiled kernel


def _window_medians(z: NDArray, starts: NDArray, w: int) -> NDArray:
    """The median of each window ``z[s : s + w]``, ``s`` in ``starts``."""
    return _row_medians(z[starts[:, None] + np.arange(w)])


def _row_medians(x: NDArray) -> NDArray:
    """The median along the last axis of ``x``.

    Six values (:data:`STEP_WINDOW`) go through :data:`SORT6` column by column: the
    same numbers as ``np.median`` (the mean of the middle two, ``(a + b) / 2``), seven
    times faster than its partition of many short rows.
    """
    if x.shape[-1] != len(SORT6_VALUES):
        return np.median(x, axis=-1)
    c = [x[..., i] for i in range(x.shape[-1])]
    for i, j in SORT6:
        lo = np.minimum(c[i], c[j])
        c[j] = np.maximum(c[i], c[j])
        c[i] = lo
    return (c[2] + c[3]) / 2


def detrended_windows(z: NDArray, at: NDArray, idx: NDArray, w: int) -> NDArray:
    """The windows ``z[s : s + w]`` of each row of starts ``at``, less the row's local line.

    ``at`` holds the starts ``k + w, k, k - w, k - 2w``. The line's slope is the median
    of the ``2 w`` slopes from each sample of a window to the sample one window before
    it on the same side of the candidate ``k`` (window ``k + w`` to ``k``, ``k - w`` to
    ``k - 2w``), so a jump at ``k`` tilts none of them; the line is a function of the
    sample less ``idx``. An added line adds its slope to every pair's, so to their
    median, and the four medians then move by one constant, which the third difference
    cancels; a spike is one pair of ``2 w``, and a median of a window that a steep line
    crosses, which took the middle samples' noise alone (so a tap moved it like a mean),
    is taken off the line.
    """
    j = at[..., None] + np.arange(w)  # (m, 4, w) sample indices
    x = z[j]
    # pairs on one side of the candidate each (windows 0-1 after it, 2-3 before it): a
    # jump at the candidate tilts no pair's slope
    if COMPILED and _steps_numba is not None and at.size:
        slope = _steps_numba.pair_slope_medians(np.ascontiguousarray(z), _ints(at), w)
    else:
        gap = np.maximum(at[:, 0::2] - at[:, 1::2], 1)[..., None]  # a window apart, (m, 2, 1)
        slope = np.median(((x[:, 0::2] - x[:, 1::2]) / gap).reshape(x.shape[0], -1), axis=1)
    return x - slope[:, None, None] * (j - idx[:, None, None])


def _ints(x: NDArray) -> NDArray:
    return np.ascontiguousarray(x, dtype=np.int64)


def _confirm_steps(
    z: NDArray, candidates: NDArray, above: Callable[[NDArray], NDArray], scale: float, w: int
) -> NDArray:
    """Keep the runs of candidate samples where window medians confirm a level change.

    ``D3med[k]`` is :func:`step_mask`'s third difference with window medians in place
    of means; a run of candidates (samples closer than ``w``) stays when ``D3med``
    exceeds :data:`STEP_CONFIRM` of its standard deviations at one of its samples.
    Each candidate's test is its own: the middle one of each run is tested first, and
    the others only in the runs it did not confirm (a long run of motion is settled by
    one median test, not thousands).
    """
    idx = np.flatnonzero(candidates)
    first = np.flatnonzero(np.r_[True, np.diff(idx) > w])  # each run's first candidate
    last = np.r_[first[1:], idx.size] - 1
    run = np.repeat(np.arange(first.size), last - first + 1)  # run of each candidate
    mid = (first + last) // 2
    keep_run = _confirmed(z, idx[mid], above, scale, w)
    rest = np.flatnonzero(~keep_run[run])
    rest = rest[rest != mid[run[rest]]]
    if rest.size:
        keep_run[run[rest[_confirmed(z, idx[rest], above, scale, w)]]] = True
    out = np.zeros_like(candidates)
    out[idx[keep_run[run]]] = True
    return out


def _confirmed(
    z: NDArray, idx: NDArray, above: Callable[[NDArray], NDArray], scale: float, w: int
) -> NDArray:
    """Whether ``D3med`` confirms a level change at each of the sorted samples ``idx``."""
    last = z.size - w  # the last window's start
    if COMPILED and _steps_numba is not None and w == len(SORT6_VALUES) and idx.size:
        # the same numbers, one candidate at a time without work arrays (5x faster)
        d3 = _steps_numba.median_third_differences(np.ascontiguousarray(z), _ints(idx), last, _NET)
    else:
        at = np.clip(idx[:, None] + np.array([w, 0, -w, -2 * w]), 0, last)
        # each candidate's four windows, off their local line (an added trend moves nothing)
        med = _row_medians(detrended_windows(z, at, idx, w))
        # D3med = m(k+w) - 3 m(k) + 3 m(k-w) - m(k-2w), sd = σ sqrt(20 var(median)), added
        # in pairs as OpenBLAS's product with (1, -3, 3, -1) did (on any BLAS, the kernel's)
        d3 = (med[:, 0] * 1.0 + med[:, 2] * 3.0) + (med[:, 1] * -3.0 + med[:, 3] * -1.0)
    level = d3**2 * scale / (STEP_CONFIRM**2 * 20.0 * _median_variance(w))
    return _above_both_sides_at(level, idx, above, z.size)


def lone_steps(
    z: NDArray,
    found: NDArray,
    above: Callable[[NDArray], NDArray],
    scale: float = 1.0,
    w: int = STEP_WINDOW,
) -> NDArray:
    """The flagged samples of :func:`step_mask` that one jump between two quiet sides explains.

    A run of flags (gaps of at most ``w`` merged: ``|D3|`` dips through zero inside one
    jump's response) is a *lone step* when

    - it is no longer than ``4 w`` samples: ``D3`` of a single step is non-zero on
      ``4 w - 1`` samples (with the boundary pair flagged, ``4 w``) whatever its size, so a
      large jump flags up to ``4 w`` samples and a small one two (a step is one event,
      not as many as the samples it flags);
    - no other flag lies within ``2 w`` samples (``D3``'s reach) of either end;
    - its two sides, the ``2 w - 1`` samples before and after it, are each a straight line
      within the noise: their pooled residual mean square about a line per side stays
      below the :data:`STEP_SIDES_ALPHA` quantile of ``σ² χ²_ν / ν`` (``ν = 2 (2 w - 3)``),
      ``σ²`` the local noise level (``above``, at both ends of the run). A jump is a
      level change between two sides whose own noise is known.

    A fast signal (a sinusoid of a few tens of samples per period) keeps ``|D3|`` high
    over many windows: its runs are longer than one step's response or close to each
    other, and the signal bends within ``2 w`` samples of them; those flags are left to
    the fraction rule (:data:`STEP_MAX_FRACTION`). Lengths, gaps and line fits read the
    same on the reversed record, so it has the same lone steps.
    """
    out = np.zeros_like(found)
    idx = np.flatnonzero(found)
    m = 2 * w - 1
    if not idx.size or z.size < 4 * w:
        return out
    cut = np.flatnonzero(np.diff(idx) > w)
    start, end = idx[np.r_[0, cut + 1]], idx[np.r_[cut, idx.size - 1]]
    gap = start[1:] - end[:-1] - 1
    quiet = np.r_[True, gap >= 2 * w] & np.r_[gap >= 2 * w, True]
    # no flag within 2w is known only where D3 could have flagged there (k from 2w to
    # n - 2w, with its boundary pair): a run nearer an edge may have a neighbour unseen
    seen = (start >= 4 * w - 1) & (end + 4 * w <= z.size)
    ok = quiet & (end - start + 1 <= 4 * w) & seen
    if not ok.any():
        return out
    a, b = start[ok], end[ok]
    resid = _line_residuals(m)
    own = np.arange(m)  # each residual read from its own sample (a held side: exactly 0)
    rss = np.sum(centred_rows(resid, z[a[:, None] - m + own], own) ** 2, axis=1)
    rss += np.sum(centred_rows(resid, z[b[:, None] + 1 + own], own) ** 2, axis=1)
    dof = 2 * (m - 2)
    level = rss / dof * scale / (_sides_quantile(dof) / dof)
    ok[ok] = ~(above_at(above, level, a, z.size) & above_at(above, level, b, z.size))
    length = end[ok] - start[ok] + 1  # the runs' samples, flagged or in a gap of the run
    first = np.cumsum(length) - length
    at = np.repeat(start[ok] - first, length) + np.arange(int(length.sum()))
    out[at] = found[at]
    return out


@lru_cache(maxsize=8)
def _line_residuals(m: int) -> NDArray:
    """The residual maker of a line fitted over ``m`` samples (read-only: it is shared)."""
    t = np.arange(m, dtype=float)
    x = np.c_[np.ones(m), t - t.mean()]
    resid = np.eye(m) - x @ np.linalg.pinv(x)
    resid.flags.writeable = False
    return resid


@lru_cache(maxsize=8)
def _sides_quantile(dof: int) -> float:
    """The ``1 - STEP_SIDES_ALPHA`` quantile of ``χ²`` with ``dof`` degrees of freedom."""
    return float(chi2_ppf(1.0 - STEP_SIDES_ALPHA, dof))

"""Level jumps: a step detector blind to parabolas, confirmed by window medians.

``auto`` leaves the samples around a jump out as signal (docs/algorithms.md §F5.3).
"""

from __future__ import annotations

from collections.abc import Callable
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

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


def step_mask(
    z: NDArray, above: Callable[[NDArray], NDArray], scale: float = 1.0, w: int = STEP_WINDOW
) -> NDArray:
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
    variance; returns the samples where ``|D3|``
    exceeds :data:`STEP_THRESHOLD` standard deviations, each with its left neighbour
    (``D3[k]`` is centred between samples ``k - 1`` and ``k``). (The scale is folded
    into the window means, so the test costs no pass of its own: two work
    arrays, the third differences written in place.)
    """
    n = z.size
    if n < 4 * w:
        return np.zeros(n, dtype=bool)
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
        return candidates
    out = _confirm_steps(z, candidates, above, scale, w)
    # D3 at k is centred on the boundary between samples k - 1 and k: both are flagged, so
    # that the reversed record flags the same samples (symmetric in time, issue 26)
    out[:-1] = out[:-1] | out[1:]
    return out


def _above_both_sides(x: NDArray, above: Callable[[NDArray], NDArray]) -> NDArray:
    """``above(x)`` at ``k`` and at ``k - 1`` alike: ``x[k]`` is centred between the two.

    The local level may change between two samples; testing against both keeps the
    decision the same on the reversed record (where the boundary's sample is ``k - 1``).
    """
    hit = above(x)
    idx = np.flatnonzero(hit)
    if idx.size:
        idx = idx[idx > 0]
        probe = np.zeros_like(x)
        probe[idx - 1] = x[idx]
        left = np.zeros_like(hit)
        left[idx] = above(probe)[idx - 1]
        hit &= left
    return hit


@lru_cache(maxsize=8)
def _median_variance(w: int) -> float:
    """Variance of the median of ``w`` standard normal samples (seeded Monte Carlo, 2e5 draws)."""
    x = np.random.default_rng(0).standard_normal((200_000, w))
    return float(np.var(np.median(x, axis=1)))


def _confirm_steps(
    z: NDArray, candidates: NDArray, above: Callable[[NDArray], NDArray], scale: float, w: int
) -> NDArray:
    """Keep the runs of candidate samples where window medians confirm a level change.

    ``D3med[k]`` is :func:`step_mask`'s third difference with window medians in place
    of means; a run of candidates (samples closer than ``w``) stays when ``D3med``
    exceeds :data:`STEP_CONFIRM` of its standard deviations at one of its samples.
    """
    idx = np.flatnonzero(candidates)
    windows = np.lib.stride_tricks.sliding_window_view(z, w)
    at = np.clip(idx[:, None] + np.array([w, 0, -w, -2 * w]), 0, windows.shape[0] - 1)
    med = np.median(windows[at.ravel()], axis=1).reshape(at.shape)
    # D3med = m(k+w) - 3 m(k) + 3 m(k-w) - m(k-2w), sd = σ sqrt(20 var(median))
    d3 = med @ np.array([1.0, -3.0, 3.0, -1.0])
    probe = np.zeros(z.size)
    probe[idx] = d3**2 * scale / (STEP_CONFIRM**2 * 20.0 * _median_variance(w))
    confirmed = _above_both_sides(probe, above)[idx]
    run = np.cumsum(np.r_[True, np.diff(idx) > w])  # run label of each candidate
    keep_run = np.zeros(run[-1] + 1, dtype=bool)
    keep_run[run[confirmed]] = True
    out = np.zeros_like(candidates)
    out[idx[keep_run[run]]] = True
    return out


def lone_steps(found: NDArray, w: int = STEP_WINDOW) -> NDArray:
    """The flagged samples of :func:`step_mask` that one jump with quiet sides explains.

    A run of flags (gaps of at most ``w`` merged: ``|D3|`` dips through zero inside one
    jump's response) is *lone* when it is no longer than ``4 w`` samples and no other flag
    lies within ``2 w`` samples of either end. A step is one event: ``D3`` of a single
    step is non-zero on ``4 w - 1`` samples (with the boundary pair flagged, ``4 w``),
    whatever its size, so a large jump flags up to ``4 w`` samples and a small one two;
    counting samples weighs a jump by its size, not by being one. ``2 w`` is ``D3``'s reach
    to either side: with no flag there, the window means that measured the level on each
    side hold no other event, so the levels either side are known from quiet samples. A
    fast signal (a sinusoid of a few tens of samples per period) keeps ``|D3|`` high over
    many windows: its flags form runs longer than one step's response, or runs closer than
    ``2 w`` to each other; those are left to the fraction rule
    (:data:`STEP_MAX_FRACTION`). The rule reads only run lengths and gaps, so the reversed
    record has the same lone steps.
    """
    out = np.zeros_like(found)
    idx = np.flatnonzero(found)
    if not idx.size:
        return out
    cut = np.flatnonzero(np.diff(idx) > w)
    start, end = idx[np.r_[0, cut + 1]], idx[np.r_[cut, idx.size - 1]]
    gap = start[1:] - end[:-1] - 1
    quiet = np.r_[True, gap >= 2 * w] & np.r_[gap >= 2 * w, True]
    lone = quiet & (end - start + 1 <= 4 * w)
    mark = np.zeros(found.size + 1, dtype=np.int64)
    np.add.at(mark, start[lone], 1)
    np.add.at(mark, end[lone] + 1, -1)
    return found & (np.cumsum(mark[:-1]) > 0)

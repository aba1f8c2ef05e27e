"""Compiled (numba) kernel behind :func:`noisevar.numeric.steps.detrended_windows`.

The median of each candidate's ``2 w`` pair slopes, each row insertion-sorted as its
slopes are computed (``np.median`` partitions many short rows, 3x slower); the same
divisions and the same middle values, so the same numbers. ``nogil``: the chunks of a
record run in parallel threads.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def pair_slope_medians(z, at, w):  # pragma: no cover - compiled
    """Median over each row of ``(z[at0 + i] - z[at1 + i]) / max(at0 - at1, 1)``, both pairs.

    ``at`` has rows of four window starts; the pairs are windows 0-1 and 2-3.
    """
    m = at.shape[0]
    out = np.empty(m)
    buf = np.empty(2 * w)
    for r in range(m):
        for p in range(2):
            a0 = at[r, 2 * p]
            a1 = at[r, 2 * p + 1]
            gap = np.float64(max(a0 - a1, 1))
            for i in range(w):  # insertion sort as the slopes come (a dozen values)
                v = (z[a0 + i] - z[a1 + i]) / gap
                k = p * w + i
                while k > 0 and buf[k - 1] > v:
                    buf[k] = buf[k - 1]
                    k -= 1
                buf[k] = v
        out[r] = (buf[w - 1] + buf[w]) / 2.0
    return out


@njit(cache=True, nogil=True, inline="always")
def _sort6(v, o, net):  # pragma: no cover - compiled
    """Sort ``v[o : o + 6]`` in place through the network ``net`` (min and max, no branches)."""
    for c in range(net.shape[0]):
        i, j = net[c, 0], net[c, 1]
        a, b = v[o + i], v[o + j]
        v[o + i] = min(a, b)
        v[o + j] = max(a, b)


@njit(cache=True, nogil=True, inline="always")
def _kth_of_two(v, k):  # pragma: no cover - compiled
    """The ``k``-th smallest (from 1) of ``v[0:6]`` and ``v[6:12]``, each sorted.

    ``min over i of max(a_i, b_(k - i))`` (``a_0 = b_0 = -inf``): the split of the ``k``
    smallest between the two gives it, and every other split a value at least as large.
    """
    best = np.inf
    for i in range(max(0, k - 6), min(k, 6) + 1):
        a = v[i - 1] if i > 0 else -np.inf
        b = v[6 + k - i - 1] if k - i > 0 else -np.inf
        best = min(best, max(a, b))
    return best


@njit(cache=True, nogil=True)
def median_third_differences(z, idx, last, net):  # pragma: no cover - compiled
    """``D3med`` at each candidate ``idx`` for windows of six: detrended window medians.

    Per candidate ``k``: window starts ``k + 6, k, k - 6, k - 12`` clipped to ``0 .. last``;
    the slope is the median of the twelve pair slopes (:func:`pair_slope_medians`: each
    pair's six sorted by ``net``, ``steps.SORT6`` as an array, then the sixth and seventh
    of both); each window
    ``z[s + i] - slope * (s + i - k)`` sorted, its median the mean of the middle two; then
    ``(m0 + 3 m2) + (-3 m1 - m3)`` (the reference's order). The same operations and order
    statistics as ``detrended_windows`` and its row medians, without their work arrays.
    """
    w = 6
    m = idx.shape[0]
    out = np.empty(m)
    at = np.empty(4, dtype=np.int64)
    v = np.empty(2 * w)
    med = np.empty(4)
    for r in range(m):
        k = idx[r]
        for q in range(4):
            at[q] = min(max(k + (1 - q) * w, 0), last)
        for p in range(2):  # the slope: median of both pairs' slopes
            a0, a1 = at[2 * p], at[2 * p + 1]
            gap = np.float64(max(a0 - a1, 1))
            for i in range(w):
                v[p * w + i] = (z[a0 + i] - z[a1 + i]) / gap
            _sort6(v, p * w, net)
        slope = (_kth_of_two(v, w) + _kth_of_two(v, w + 1)) / 2.0
        for q in range(4):
            s = at[q]
            for i in range(w):
                v[i] = z[s + i] - slope * np.float64(s + i - k)
            _sort6(v, 0, net)
            med[q] = (v[2] + v[3]) / 2.0
        out[r] = (med[0] * 1.0 + med[2] * 3.0) + (med[1] * -3.0 + med[3] * -1.0)
    return out


@njit(cache=True, nogil=True, inline="always")
def _above_at(v, i, fwd, bwd, bwd0, half, m):  # pragma: no cover - compiled
    """``v`` above the level of sample ``i`` on both grids (each a level per half block)."""
    if not v > fwd[min(i // half, fwd.shape[0] - 1)]:
        return False
    j = m - 1 - i
    return v > (bwd[min(j // half, bwd.shape[0] - 1)] if j >= 0 else bwd0)


@njit(cache=True, nogil=True)
def above_both_sides(x, floor, fwd, bwd, bwd0, half, q):  # pragma: no cover - compiled
    """``x[k]`` above the levels of samples ``k`` and ``k - 1`` (``k >= 1``), on both grids.

    ``fwd``: the level of each half block from the window's start (samples ``i // half``,
    the last one for the rest); ``bwd`` the same on the reversed window less its first
    ``q`` samples (``bwd0`` before it); only ``x[k] > floor`` can be above. Comparisons
    with the levels looked up as the NumPy path looks them up: the same flags.
    """
    n = x.shape[0]
    m = n - q
    hit = np.zeros(n, dtype=np.bool_)
    for k in range(1, n):
        v = x[k]
        if v > floor and _above_at(v, k, fwd, bwd, bwd0, half, m):
            hit[k] = _above_at(v, k - 1, fwd, bwd, bwd0, half, m)
    return hit


@njit(cache=True, nogil=True)
def above_both_sides_at(values, idx, fwd, bwd, bwd0, half, m):  # pragma: no cover - compiled
    """:func:`above_both_sides` of samples that are ``values`` at the ``idx`` (0 elsewhere).

    ``m``: the samples the reversed grid reads (the window's less its first ``q``).
    """
    hit = np.zeros(idx.shape[0], dtype=np.bool_)
    for r in range(idx.shape[0]):
        k = idx[r]
        v = values[r]
        if k > 0 and _above_at(v, k, fwd, bwd, bwd0, half, m):
            hit[r] = _above_at(v, k - 1, fwd, bwd, bwd0, half, m)
    return hit

"""Compiled (numba) kernels behind :mod:`noisevar.numeric.fir`: symmetric filters, lagged products.

``auto`` filters the whole record with four centred Savitzky-Golay residual
sequences (spans 11, 21, 41 and 81). ``np.convolve`` spends one dot product of
``span`` taps per output sample; these sequences are symmetric, so the kernel adds
each pair ``(z[t - k] - z[t]) + (z[t + k] - z[t])`` first (half the multiplications;
the differences to the centre sample make an offset cancel exactly) and runs over
tiles of the output that stay in the first level cache, with the innermost loop along
the tile, which the compiler vectorises; four taps per pass over the tile (one store of
the running sum instead of four: 15 % faster, the same additions in the same order).
Same filter, same result to rounding (tested against ``np.convolve``).

``cache=True``: compiled once per machine into ``__pycache__``; ``nogil``: chunks of a
streamed record are filtered in parallel threads.
"""

from __future__ import annotations

import numpy as np
from numba import njit

_TILE = 1024


@njit(cache=True, nogil=True)
def symmetric_fir_squares(z, half, out, limit=-np.inf):  # pragma: no cover - compiled
    """``out[t] = (sum_k d_k z[t + k])²``: :func:`symmetric_fir`, squared."""
    return symmetric_fir(z, half, out, True, limit)


@njit(cache=True, nogil=True)
def symmetric_fir(z, half, out, square, limit=-np.inf):  # pragma: no cover - compiled
    """``out[t] = sum_k d_k (z[t + k] - z[t])`` (squared if ``square``) at centred ``t``.

    ``d`` is symmetric and sums to zero (a residual sequence), so this is ``sum_k d_k
    z[t + k]``, read from the differences to the centre sample: an offset cancels
    exactly and a held (constant) stretch gives exactly 0, whatever its value.

    Parameters
    ----------
    z : ndarray, float64, shape (n,)
    half : ndarray, float64, shape (h + 1,)
        ``d[h], d[h + 1], ..., d[2h]`` of a symmetric sequence of ``2h + 1`` taps.
    out : ndarray, float64, shape (n - 2h,)
        Written in place: the filter output at ``t = h .. n - h - 1``.
    square : bool
        Write the squared output.
    limit : float
        Count the outputs (squares if ``square``, else magnitudes) at or below it.

    Returns
    -------
    int
        That count (a screen the caller reads instead of a pass over ``out``).
    """
    n = z.shape[0]
    h = half.shape[0] - 1
    acc = np.empty(_TILE)
    low = 0
    for start in range(h, n - h, _TILE):
        stop = min(start + _TILE, n - h)
        m = stop - start
        # slices, so that the loops index from 0 and the compiler vectorises them
        a = acc[:m]
        mid = z[start:stop]
        for i in range(m):
            a[i] = 0.0  # the centre tap's difference
        k = 1
        while k + 3 <= h:  # four taps per pass over the tile, added in the same order
            c1, c2, c3, c4 = half[k], half[k + 1], half[k + 2], half[k + 3]
            left = z[start - k - 3 : stop - k]  # left[i + 3 - u] = z[t - k - u]
            right = z[start + k : stop + k + 3]  # right[i + u] = z[t + k + u]
            for i in range(m):
                c = mid[i]
                a[i] = (
                    (
                        (a[i] + c1 * ((left[i + 3] - c) + (right[i] - c)))
                        + c2 * ((left[i + 2] - c) + (right[i + 1] - c))
                    )
                    + c3 * ((left[i + 1] - c) + (right[i + 2] - c))
                ) + c4 * ((left[i] - c) + (right[i + 3] - c))
            k += 4
        while k <= h:
            c = half[k]
            left = z[start - k : stop - k]
            right = z[start + k : stop + k]
            for i in range(m):
                a[i] += c * ((left[i] - mid[i]) + (right[i] - mid[i]))
            k += 1
        o = out[start - h : stop - h]
        if square:
            for i in range(m):
                v = a[i] * a[i]
                o[i] = v
                low += v <= limit
        else:
            for i in range(m):
                o[i] = a[i]
                low += abs(a[i]) <= limit
    return low


@njit(cache=True, nogil=True)
def lagged_products(x, lags, out):  # pragma: no cover - compiled
    """``out[k] = sum_i x[i] x[i + k]`` for ``k = 0..lags``, one pass over ``x``.

    The loop over the lags is innermost: independent sums, which the compiler
    vectorises, and each sample is read from memory once. Four samples per pass over
    the lags, added in sample order (each lag's sum is the same sequence of additions
    as one sample at a time, with a quarter of the running sums' loads and stores:
    2x faster).
    """
    n = x.shape[0]
    acc = np.zeros(lags + 1)
    i = 0
    while i + 4 <= n - lags:
        x0, x1, x2, x3 = x[i], x[i + 1], x[i + 2], x[i + 3]
        for k in range(lags + 1):
            a = acc[k] + x0 * x[i + k]
            a += x1 * x[i + 1 + k]
            a += x2 * x[i + 2 + k]
            acc[k] = a + x3 * x[i + 3 + k]
        i += 4
    while i < n - lags:
        xi = x[i]
        for k in range(lags + 1):
            acc[k] += xi * x[i + k]
        i += 1
    for i in range(max(n - lags, 0), n):
        for k in range(n - i):
            acc[k] += x[i] * x[i + k]
    for k in range(lags + 1):
        out[k] = acc[k]


_MANY_TILE = 1024


@njit(cache=True, nogil=True, inline="always")
def _four(a, c, k, p0, p1, p2, p3):  # pragma: no cover - compiled
    """Taps ``k .. k + 3`` of ``c`` added to ``a`` in order."""
    return (((a + c[k] * p0) + c[k + 1] * p1) + c[k + 2] * p2) + c[k + 3] * p3


@njit(cache=True, nogil=True, inline="always")
def _pairs(left, right, i, c):  # pragma: no cover - compiled
    """The four pairs of taps ``k .. k + 3`` at output ``i`` (``left``, ``right`` as in
    :func:`symmetric_fir`), each ``(z[t - k] - z[t]) + (z[t + k] - z[t])``."""
    return (
        (left[i + 3] - c) + (right[i] - c),
        (left[i + 2] - c) + (right[i + 1] - c),
        (left[i + 1] - c) + (right[i + 2] - c),
        (left[i] - c) + (right[i + 3] - c),
    )


@njit(cache=True, nogil=True)
def _grouped(acc, halves, g, k, left, right, mid, m):  # pragma: no cover - compiled
    """Taps ``k .. k + 3`` into the first ``g`` running sums (each pair formed once)."""
    a0, a1, a2, a3 = acc[0], acc[1], acc[2], acc[3]
    c0, c1, c2, c3 = halves[0], halves[1], halves[2], halves[3]
    # one loop per group size, written out: a loop over the g sums inside the sample loop
    # would keep them in memory, not registers (the duplication is the speed)
    if g == 4:
        for i in range(m):
            p0, p1, p2, p3 = _pairs(left, right, i, mid[i])
            a0[i] = _four(a0[i], c0, k, p0, p1, p2, p3)
            a1[i] = _four(a1[i], c1, k, p0, p1, p2, p3)
            a2[i] = _four(a2[i], c2, k, p0, p1, p2, p3)
            a3[i] = _four(a3[i], c3, k, p0, p1, p2, p3)
    elif g == 3:
        for i in range(m):
            p0, p1, p2, p3 = _pairs(left, right, i, mid[i])
            a0[i] = _four(a0[i], c0, k, p0, p1, p2, p3)
            a1[i] = _four(a1[i], c1, k, p0, p1, p2, p3)
            a2[i] = _four(a2[i], c2, k, p0, p1, p2, p3)
    elif g == 2:
        for i in range(m):
            p0, p1, p2, p3 = _pairs(left, right, i, mid[i])
            a0[i] = _four(a0[i], c0, k, p0, p1, p2, p3)
            a1[i] = _four(a1[i], c1, k, p0, p1, p2, p3)
    elif g == 1:
        for i in range(m):
            p0, p1, p2, p3 = _pairs(left, right, i, mid[i])
            a0[i] = _four(a0[i], c0, k, p0, p1, p2, p3)


@njit(cache=True, nogil=True)
def _squared_out(acc, out, rows, limits, low, start, m):  # pragma: no cover - compiled
    """The running sums squared into ``out[rows[s], start:start + m]``, screened."""
    for s in range(rows.shape[0]):
        a = acc[s]
        o = out[rows[s], start : start + m]
        n_low = 0
        for i in range(m):
            v = a[i] * a[i]
            o[i] = v
            n_low += v <= limits[s]
        low[s] += n_low


@njit(cache=True, nogil=True)
def symmetric_firs_squares(z, halves, hs, lo, hi, out, rows, limits, low):  # pragma: no cover
    """:func:`symmetric_fir_squares` of up to four sequences at once, at samples ``lo .. hi``.

    ``halves[s, :hs[s] + 1]`` is sequence ``s``'s second half (``hs`` non-increasing;
    ``halves`` has four rows, the unused ones zero); ``out[rows[s], t]`` its squared output
    at sample ``t`` (every sequence reaches ``t``); ``low[s]`` adds the count of those at or
    below ``limits[s]``. Each pair ``(z[t - k] - z[t]) + (z[t + k] - z[t])`` is formed once,
    in registers, for every sequence that takes taps ``k .. k + 3`` together; each sequence
    adds its taps in the order of :func:`symmetric_fir` (four at a time from ``k = 1``, then
    one by one), so the same additions and the same outputs.
    """
    ns = hs.shape[0]
    acc = np.zeros((4, _MANY_TILE))
    for start in range(lo, hi, _MANY_TILE):
        stop = min(start + _MANY_TILE, hi)
        m = stop - start
        mid = z[start:stop]
        acc[:, :m] = 0.0
        for k in range(1, hs[0] + 1, 4):
            g = 0  # the sequences that take taps k .. k + 3 together
            while g < ns and hs[g] >= k + 3:
                g += 1
            left = z[start - k - 3 : stop - k]  # left[i + 3 - u] = z[t - k - u]
            right = z[start + k : stop + k + 3]  # right[i + u] = z[t + k + u]
            _grouped(acc, halves, g, k, left, right, mid, m)
            for s in range(g, ns):  # the last taps of the shorter ones, one by one
                a = acc[s]
                for kk in range(k, hs[s] + 1):
                    cc = halves[s, kk]
                    lk = z[start - kk : stop - kk]
                    rk = z[start + kk : stop + kk]
                    for i in range(m):
                        a[i] += cc * ((lk[i] - mid[i]) + (rk[i] - mid[i]))
        _squared_out(acc, out, rows, limits, low, start, m)

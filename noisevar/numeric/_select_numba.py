"""Compiled (numba) kernel behind :func:`noisevar.numeric.blocks.row_medians`: medians of rows.

NumPy's ``partition`` along a row is an introselect whose comparisons the processor
cannot predict. Here each row is narrowed by bands instead (sample selection, as Floyd
and Rivest's): a sorted sample of the values proposes two bounds that bracket the
middle ranks; one pass counts the values below the lower bound and copies those between
the bounds (a comparison whose outcome is nearly always the same, and a copy without a
branch); the band, a fraction of the row, is narrowed again, and the last few values are
insertion-sorted. A band that misses the ranks (an unlucky sample) is widened and the pass
run again over the same values. Order statistics are values of the row whatever the
algorithm, and the even case adds the same two of them as NumPy's median, so the same
numbers. ``nogil``: the chunks of a record run in parallel threads.
"""

from __future__ import annotations

import numpy as np
from numba import njit

#: Values in each sample that proposes a band.
_SAMPLE = 64
#: Ranks of the sample either side of the middle ranks' place that the band first spans.
_REACH = 6
#: At most this many values left: insertion-sorted.
_SMALL = 64


@njit(cache=True, nogil=True)
def _sorted_sample(src, m, samp):  # pragma: no cover - compiled
    """``samp`` filled with values spread over ``src[:m]``, insertion-sorted; its size."""
    s = min(_SAMPLE, m // 4)
    for i in range(s):
        v = src[(i * m) // s]
        j = i
        while j > 0 and samp[j - 1] > v:
            samp[j] = samp[j - 1]
            j -= 1
        samp[j] = v
    return s


@njit(cache=True, nogil=True)
def _band(src, m, lo, hi, dst):  # pragma: no cover - compiled
    """How many of ``src[:m]`` are below ``lo``, and those in ``[lo, hi]`` copied to ``dst``."""
    below = 0
    kept = 0
    for i in range(m):
        v = src[i]
        below += v < lo
        dst[kept] = v
        kept += (v >= lo) & (v <= hi)
    return below, kept


@njit(cache=True, nogil=True)
def _sort_head(work, m):  # pragma: no cover - compiled
    """``work[:m]`` sorted in place: Shell's sort (insertion sort, the last gap 1).

    Short or nearly sorted heads are the common case; a long one (a band of ties) costs
    ``m^1.3``, and the kernel compiles in a fraction of the time NumPy's sort takes in numba.
    """
    gap = 1
    while gap < m // 3:
        gap = 3 * gap + 1  # Knuth's gaps
    while gap >= 1:
        for i in range(gap, m):
            v = work[i]
            j = i
            while j >= gap and work[j - gap] > v:
                work[j] = work[j - gap]
                j -= gap
            work[j] = v
        gap //= 3


@njit(cache=True, nogil=True)
def _two_ranks(row, ra, rb, bufs, samp):  # pragma: no cover - compiled
    """Order statistics ``ra <= rb`` of ``row`` (``rb - ra <= 1``); ``row`` is not changed."""
    m = row.shape[0]
    src = row  # read, never written: the first band goes to a buffer
    which = 0
    if m <= _SMALL:
        src = bufs[1]
        for i in range(m):
            src[i] = row[i]
    while m > _SMALL:
        s = _sorted_sample(src, m, samp)
        dst = bufs[which]
        reach = _REACH
        while True:
            i_lo = (ra * s) // m - reach
            i_hi = (rb * s) // m + reach
            lo = -np.inf if i_lo < 0 else samp[i_lo]
            hi = np.inf if i_hi >= s else samp[i_hi]
            below, kept = _band(src, m, lo, hi, dst)
            if below <= ra and rb < below + kept or (i_lo < 0 and i_hi >= s):
                break  # (the second: every value, which only a NaN leaves out)
            reach *= 4  # the sample missed the ranks: a wider band over the same values
        if lo == hi:  # every value of the band is this one
            return lo, lo
        ra -= below
        rb -= below
        stop = kept == m  # the band is every value: nothing left to narrow
        src = dst
        m = kept
        which = 1 - which
        if stop:
            break
    _sort_head(src, m)
    return src[ra], src[rb]


@njit(cache=True, nogil=True)
def row_medians(x, out):  # pragma: no cover - compiled
    """``out[r] = np.median(x[r])`` for each row of ``x`` (no NaN, at least one column).

    Odd rows: the middle value; even rows: ``(a + b) / 2.0`` of the two middle ones.
    """
    n = x.shape[1]
    bufs = np.empty((2, n))
    samp = np.empty(_SAMPLE)
    k = n // 2
    for r in range(x.shape[0]):
        if n % 2:
            a, b = _two_ranks(x[r], k, k, bufs, samp)
            out[r] = b
        else:
            a, b = _two_ranks(x[r], k - 1, k, bufs, samp)
            out[r] = (a + b) / 2.0

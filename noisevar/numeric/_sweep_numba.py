"""Compiled (numba) kernels behind :mod:`noisevar.numeric.sweeps`: merges of sorted indices.

Each is one pass over sorted integer arrays with two moving pointers, where NumPy's
``searchsorted`` takes a binary search per element; integer results, so the same numbers
exactly. ``nogil``: the chunks of a record are estimated in parallel threads.
"""

from __future__ import annotations

import numpy as np
from numba import njit


@njit(cache=True, nogil=True)
def window_counts(idx, lo, hi):  # pragma: no cover - compiled
    """How many of the sorted ``idx`` lie in ``[lo[i], hi[i]]`` (``lo``, ``hi`` non-decreasing)."""
    n = idx.size
    out = np.empty(lo.size, dtype=np.int64)
    a = 0
    b = 0
    for i in range(lo.size):
        while a < n and idx[a] < lo[i]:
            a += 1
        while b < n and idx[b] <= hi[i]:
            b += 1
        out[i] = b - a
    return out


@njit(cache=True, nogil=True)
def near_any(idx, at, half):  # pragma: no cover - compiled
    """Whether some of the sorted ``at`` lies within ``half`` of each of the sorted ``idx``."""
    out = np.empty(idx.size, dtype=np.bool_)
    p = 0
    for i in range(idx.size):
        while p < at.size and at[p] < idx[i] - half:
            p += 1
        out[i] = p < at.size and at[p] <= idx[i] + half
    return out

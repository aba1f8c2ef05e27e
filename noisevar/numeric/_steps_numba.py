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

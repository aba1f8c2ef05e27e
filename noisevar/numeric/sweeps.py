"""Counts over sorted sample indices: how many lie in a window, whether one lies near.

``auto``'s jump detector judges each flag by the flags around it (docs/algorithms.md
§F5.3). The compiled kernels of :mod:`noisevar.numeric._sweep_numba` merge the sorted
arrays in one pass; the NumPy references (``searchsorted``) give the same integers
(tested) and run when numba is not installed.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

try:
    from noisevar.numeric import _sweep_numba
except ImportError:  # pragma: no cover - numba not installed
    _sweep_numba = None  # type: ignore[assignment]


def window_counts(idx: NDArray, lo: NDArray, hi: NDArray, compiled: bool = True) -> NDArray:
    """How many of the sorted ``idx`` lie in ``[lo[i], hi[i]]``, for each ``i``.

    Parameters
    ----------
    idx : ndarray of int, sorted
    lo, hi : ndarray of int, non-decreasing, the same size
    compiled : bool
        Use the compiled merge (False: the NumPy reference).

    Returns
    -------
    ndarray of int64
    """
    if compiled and _sweep_numba is not None:
        return _sweep_numba.window_counts(_ints(idx), _ints(lo), _ints(hi))
    return np.searchsorted(idx, hi, side="right") - np.searchsorted(idx, lo, side="left")


def near_any(idx: NDArray, at: NDArray, half: int, compiled: bool = True) -> NDArray:
    """Whether some of the sorted ``at`` (not empty) lies within ``half`` of each sorted ``idx``.

    Parameters
    ----------
    idx, at : ndarray of int, sorted
    half : int
    compiled : bool
        Use the compiled merge (False: the NumPy reference).

    Returns
    -------
    ndarray of bool
    """
    if compiled and _sweep_numba is not None:
        return _sweep_numba.near_any(_ints(idx), _ints(at), int(half))
    pos = np.searchsorted(at, idx)
    after = at[np.minimum(pos, at.size - 1)] - idx
    before = idx - at[np.maximum(pos - 1, 0)]
    return ((after >= 0) & (after <= half)) | ((before >= 0) & (before <= half))


def _ints(x: NDArray) -> NDArray:
    return np.ascontiguousarray(x, dtype=np.int64)

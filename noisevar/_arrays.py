"""Array helpers shared by the filters and the diagnostics."""

from __future__ import annotations

from numpy.typing import NDArray


def median_inplace(v: NDArray) -> float:
    """``np.median(v)`` (the same number) of a 1-D float array, partitioning ``v`` in place.

    No copy and no checks: ``v`` must be finite, non-empty and the caller's to reorder.
    """
    k = v.size // 2
    if v.size % 2:
        v.partition(k)
        return float(v[k])
    v.partition((k - 1, k))
    return float((v[k - 1] + v[k]) / 2.0)

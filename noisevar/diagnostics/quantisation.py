"""Samples on a grid: the quantisation step (docs/algorithms.md §E3)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: Samples used to propose a step; the whole record then confirms it.
LSB_PROBE = 4096
#: A sample is on the grid when within this fraction of a step of a grid point.
LSB_TOL = 1e-3


def find_lsb(z: NDArray) -> float | None:
    """The step of the grid the samples sit on, or None when they are not on one.

    Parameters
    ----------
    z : ndarray
        Samples.

    Returns
    -------
    float or None
        The smallest step ``Δ`` such that every ``(z - z₀) / Δ`` is an integer (to
        :data:`LSB_TOL`), proposed from the smallest gap between distinct values of a
        probe of the record.
    """
    probe = z[:: max(1, z.size // LSB_PROBE)]
    levels = np.unique(probe)
    if levels.size < 2:
        levels = np.unique(z)
        if levels.size < 2:
            return None
    steps = np.diff(levels)
    step = float(steps.min())
    spread = float(levels[-1] - levels[0])
    if step <= 0 or spread / step > 1e9:  # a grid finer than float64 resolves: continuous
        return None
    if not _on_grid(steps, step):
        return None
    return step if _on_grid(z - levels[0], step) else None


def _on_grid(x: NDArray, step: float) -> bool:
    """Every ``x / step`` within :data:`LSB_TOL` of an integer."""
    r = x / step
    return bool(np.max(np.abs(r - np.rint(r))) < LSB_TOL)

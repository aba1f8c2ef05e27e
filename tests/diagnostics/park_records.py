"""Seeded records that drive, then park (the benchmark's and the tests' one home)."""

from __future__ import annotations

import numpy as np

#: The parked noise's standard deviation.
SIGMA = 0.05


def drive_then_park(seed: int, n: int, step: float, smooth: bool) -> np.ndarray:
    """``n`` samples: a drive over the first half (a walk of steps ``step``, or with
    ``smooth`` a doubly integrated one of steps ``0.1 step``), then parked, with white
    noise of :data:`SIGMA` throughout."""
    rng = np.random.default_rng(seed)
    m = n // 2
    steps = step * rng.normal(size=m)
    drive = np.cumsum(np.cumsum(0.1 * steps)) if smooth else np.cumsum(steps)
    return np.r_[drive, np.full(n - m, drive[-1])] + SIGMA * rng.normal(size=n)

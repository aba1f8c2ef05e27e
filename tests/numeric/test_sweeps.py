"""The compiled merges of :mod:`noisevar.numeric.sweeps` give the NumPy references' integers."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.numeric import sweeps


@pytest.mark.parametrize("seed", range(20))
def test_compiled_window_counts_and_nearness_are_the_references(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(1, 5_000))
    flags = rng.random(n) < rng.choice([0.001, 0.05, 0.5, 0.99])
    flags[rng.integers(0, n)] = True
    idx = np.flatnonzero(flags)
    half = int(rng.integers(0, 300))
    size = min(2 * half + 1, n)
    lo = np.clip(idx - half, 0, n - size)
    hi = lo + size - 1
    counts = sweeps.window_counts(idx, lo, hi)
    assert counts.dtype == np.int64
    np.testing.assert_array_equal(counts, sweeps.window_counts(idx, lo, hi, compiled=False))
    at = idx[rng.random(idx.size) < 0.1] if idx.size > 10 else idx[:1]
    every = np.flatnonzero(flags | (rng.random(n) < 0.2))
    near = sweeps.near_any(every, at, half)
    np.testing.assert_array_equal(near, sweeps.near_any(every, at, half, compiled=False))
    # the definition itself: some flag of ``at`` within ``half``
    brute = np.abs(every[:, None] - at[None, :]).min(axis=1) <= half
    np.testing.assert_array_equal(near, brute)

"""The compiled slope medians of ``detrended_windows`` and the compiled confirmation give the
NumPy references' numbers, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.numeric import steps


@pytest.mark.parametrize("seed", range(12))
def test_compiled_detrended_windows_are_the_reference(monkeypatch, seed):
    rng = np.random.default_rng(seed)
    w = int(rng.choice([6, 6, 3, 8]))
    n = int(rng.integers(8 * w, 3_000))
    z = rng.normal(size=n) * 10.0 ** rng.uniform(-12, 9) + np.sin(np.arange(n) / 7.0)
    if seed % 3 == 0:  # a quantised record: ties among the slopes
        z = np.round(z / np.std(z) * 2.0)
    idx = np.sort(rng.choice(n, size=int(rng.integers(1, n // 4)), replace=False))
    at = np.clip(idx[:, None] + np.array([w, 0, -w, -2 * w]), 0, n - w)
    fast = steps.detrended_windows(z, at, idx, w)
    monkeypatch.setattr(steps, "COMPILED", False)
    slow = steps.detrended_windows(z, at, idx, w)
    assert fast.tobytes() == slow.tobytes()


@pytest.mark.parametrize("seed", range(8))
def test_compiled_confirmation_is_the_reference(monkeypatch, seed):
    """The confirmation's third differences of window medians (one kernel per candidate)."""
    rng = np.random.default_rng(100 + seed)
    w = steps.STEP_WINDOW
    n = int(rng.integers(8 * w, 20_000))
    z = rng.normal(size=n) * 10.0 ** rng.uniform(-12, 9) + np.sin(np.arange(n) / 7.0)
    if seed % 3 == 0:  # quantised: ties among the slopes and the window values
        z = np.round(z / np.std(z) * 2.0)
    if seed % 4 == 1:
        z[rng.integers(0, n) :] += 40.0 * np.std(z)  # a jump
    idx = np.sort(rng.choice(n, size=int(rng.integers(1, n // 3)), replace=False))
    seen = []

    def above(x: np.ndarray) -> np.ndarray:
        seen.append(x.copy())
        return x > np.median(x)

    fast = steps._confirmed(z, idx, above, 3.0, w)
    monkeypatch.setattr(steps, "COMPILED", False)
    slow = steps._confirmed(z, idx, above, 3.0, w)
    assert np.array_equal(fast, slow)
    assert seen[0].tobytes() == seen[len(seen) // 2].tobytes()  # the levels tested, bit for bit


@pytest.mark.parametrize(
    "m, block, after", [(5000, 256, 0), (5000, 256, 77), (1030, 16, 5), (700, 64, 0)]
)
def test_above_both_sides_compiled_equals_numpy(m, block, after, monkeypatch):
    """One compiled pass over the third differences: the flags of the NumPy path."""
    from noisevar.estimators.auto._levels import Above, Grids

    rng = np.random.default_rng(m + block + after)
    g = Grids.make(m, block, after)
    fwd = rng.uniform(0.5, 2.0, g.nb)
    bwd = rng.uniform(0.5, 2.0, g.nbb)
    fwd[rng.integers(0, g.nb)] = np.nan  # a block with no level: never exceeded
    x = rng.standard_normal(m) ** 2 * 1.5
    x[rng.integers(0, m, 50)] = 40.0
    above = Above(fwd, bwd, g)
    got = steps._above_both_sides(x, above)
    assert above.sides(x) is not None  # the compiled path ran
    monkeypatch.setattr(Above, "sides", lambda self, x: None)
    ref = steps._above_both_sides(x, above)
    assert ref.any() and np.array_equal(got, ref)


@pytest.mark.parametrize("m, block, after", [(5000, 256, 0), (5000, 256, 77), (1030, 16, 5)])
def test_above_both_sides_at_compiled_equals_numpy(m, block, after, monkeypatch):
    """The same flags at a few samples (the confirmation's), read there only."""
    from noisevar.estimators.auto._levels import Above, Grids

    rng = np.random.default_rng(m + after)
    g = Grids.make(m, block, after)
    fwd, bwd = rng.uniform(0.5, 2.0, g.nb), rng.uniform(0.5, 2.0, g.nbb)
    bwd[-1] = np.nan
    above = Above(fwd, bwd, g)
    idx = np.unique(np.r_[0, 1, m - 1, rng.integers(0, m, 300)])
    values = rng.uniform(0.0, 3.0, idx.size)
    got = steps._above_both_sides_at(values, idx, above, m)
    assert above.sides_at(values, idx) is not None
    monkeypatch.setattr(Above, "sides_at", lambda self, v, i: None)
    ref = steps._above_both_sides_at(values, idx, above, m)
    assert ref.any() and (~ref).any() and np.array_equal(got, ref)

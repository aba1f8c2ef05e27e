"""The compiled slope medians of ``detrended_windows`` give ``np.median``'s numbers, bit for bit."""

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

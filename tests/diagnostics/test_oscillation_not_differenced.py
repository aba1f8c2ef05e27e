"""An oscillation a few samples per period read as differenced data (real_audit19: Kepler's
KOI-2133, a red giant's oscillation in long cadence, split at its 253 gaps: correlations
+0.46, -0.18, -0.33, -0.07 at lags 1-4 read as a derivative filter's MA(4) noise, R x5.19).

Differenced noise is MA(q): q correlations fit the lags they are fitted on. An oscillation's
correlation runs on at every lag, and MA(q) noise leaves its fitted lags unexplained."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar as nv

N = 20_000


def _oscillation(seed: int, period: float, radius: float, gaps: bool) -> tuple:
    """White noise σ = 1 plus a randomly excited oscillation (AR(2) resonance) of std 2,
    with 100 gaps of 2-19 samples when ``gaps``."""
    rng = np.random.default_rng(seed)
    c = 2 * radius * np.cos(2 * np.pi / period)
    osc = lfilter([1.0], [1.0, -c, radius**2], rng.normal(size=N))
    z = 2.0 * osc / osc.std() + rng.normal(size=N)
    t = np.arange(N, dtype=float)
    keep = np.ones(N, bool)
    if gaps:
        for s in rng.choice(N - 50, 100, replace=False):
            keep[s : s + rng.integers(2, 20)] = False
    return z[keep], t[keep]


@pytest.mark.parametrize("period, radius", [(6.0, 0.75), (6.0, 0.85), (5.0, 0.75)])
@pytest.mark.parametrize("gaps", [False, True])
def test_an_oscillation_at_five_or_six_samples_is_not_differenced(period, radius, gaps):
    z, t = _oscillation(1, period, radius, gaps)
    est = nv.estimate(z, t=t)
    assert not est.diagnostics.short_correlated, est.verdict
    assert "differenced" not in est.verdict


def test_a_derivative_filters_ma_noise_still_fits_its_lags():
    from noisevar.diagnostics.ma_fit import ma_fits

    kernel = np.array([1.0, 1.0, 0.0, -1.0, -1.0]) / 6.0
    for seed in range(10):
        z = np.convolve(np.random.default_rng(seed).normal(size=N + 4), kernel, mode="valid")
        d = nv.estimate(z).diagnostics
        assert d.differenced and ma_fits(d.whiteness, d.noise_correlation)

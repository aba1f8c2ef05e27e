"""R of a record that vibrates is the noise without the vibration (issue 26; docs/algorithms.md
§E2 *Vibration*).

A sinusoid in white noise is named an oscillation, and the verdict says to notch or low-pass
it out before the filter; R read the noise plus the sinusoid through the residual filter's
gain at its frequency (at 0.476 of the rate, amplitude 1.5σ: R 5x σ²). R is now the noise
a filter sees once the vibration is notched out: the sinusoid fitted to R's residual is
taken out, and the interval is the block jackknife's.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv

SIGMA = 2.0


def _vibrating(seed: int, period: float, amplitude: float, n: int = 2000) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    tone = amplitude * SIGMA * np.sin(2 * np.pi * t / period + rng.uniform(0, 2 * np.pi))
    return rng.normal(0, SIGMA, n) + tone + 5 * SIGMA * np.sin(2 * np.pi * t / 2000)


@pytest.mark.parametrize(("period", "amplitude"), [(2.1, 1.5), (3.3, 3.0), (7.7, 0.5)])
def test_r_of_a_vibration_is_the_noise_without_it(period: float, amplitude: float) -> None:
    ests = [nv.estimate(_vibrating(50_000 + s, period, amplitude)) for s in range(12)]
    truth = SIGMA**2
    ratio = np.array([e.variance for e in ests]) / truth
    assert all("oscillation" in e.verdict for e in ests)
    assert abs(ratio.mean() - 1.0) < 0.04, ratio
    assert sum(e.ci95[0] <= truth <= e.ci95[1] for e in ests) >= 10
    assert any("taken out of R" in n for n in ests[0].notes)



@pytest.mark.parametrize("seed", [0, 3, 5])
def test_a_start_up_glitch_stays_in_the_interval(seed: int) -> None:
    """A vibration and one start-up glitch holding 40 % of R (PX4's vz, real_audit3): the
    jackknife's interval (1.60-1.97) left out the glitch's Poisson count R's own had, so R
    without that first sample (1.00) fell outside it."""
    rng = np.random.default_rng(seed)
    n = 2000
    t = np.arange(n)
    z = rng.normal(size=n) + 0.5 * np.sin(2 * np.pi * 0.128 * t + 1.0)
    z += np.cumsum(0.01 * rng.normal(size=n))
    z[0] += 40.0
    est = nv.estimate(z)
    assert any("was taken out of R" in note for note in est.notes)
    lo, hi = est.ci95
    assert lo <= nv.estimate(z[1:]).variance <= hi

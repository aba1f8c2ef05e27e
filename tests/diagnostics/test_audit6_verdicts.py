"""Failure classes of the sixth real-record audit (benchmarks/real_audit6.py: biosignals,
beat intervals, a satellite's X-ray sensor), seeded."""

import numpy as np
import pytest

import noisevar


def _slow_on_a_grid(sigma: float, seed: int = 0, n: int = 200_000) -> np.ndarray:
    """A slow signal (20 and 5 steps, periods 50,000 and 7,000 samples) plus white noise of
    ``sigma`` steps, rounded to whole steps: systole's EDA at 1 kHz on its 16-bit grid."""
    t = np.arange(n)
    slow = 20 * np.sin(2 * np.pi * t / 50_000) + 5 * np.sin(2 * np.pi * t / 7_000)
    return np.round(slow + sigma * np.random.default_rng(seed).normal(size=n))


@pytest.mark.parametrize("sigma", [0.02, 0.1])
def test_noise_under_half_a_step_is_the_rounding_not_colour(sigma: float) -> None:
    """systole's EDA (noise about 0.02 of its grid step) read "the noise is coloured: random
    walk at 1 sample, flicker walk at 4 samples ... model the coloured part", and at 0.02
    of a step the synthetic record read "mostly motion ...: the sensor noise measured in its
    still stretches (3% of it) is 0.006373", 13x under the rounding error lsb²/12 = 0.0833.
    Under half a step the residual is the rounding, which follows the signal: said first."""
    est = noisevar.estimate(_slow_on_a_grid(sigma))
    v = est.diagnostics.verdict
    assert v.startswith("noise under half a step on a grid of step 1:"), v
    assert "coloured part" not in v and "mostly motion" not in v
    assert "lsb²/12 = 0.08333" in v
    assert est.variance <= est.diagnostics.lsb**2 * (0.25 + 1 / 12)  # under half a step


def test_uniform_noise_is_not_called_gaussian() -> None:
    """nolds' quantum random numbers (16-bit, uniform) read "white Gaussian noise"; R is
    right, the word was not. Gaussian noise keeps it."""
    rng = np.random.default_rng(6)
    uniform = noisevar.estimate(rng.uniform(size=1000)).diagnostics.verdict
    assert uniform.startswith("white noise with tails lighter than Gaussian"), uniform
    gaussian = noisevar.estimate(rng.normal(size=1000)).diagnostics.verdict
    assert gaussian.startswith("white Gaussian noise")

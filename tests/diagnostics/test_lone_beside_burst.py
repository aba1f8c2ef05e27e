"""A lone outlying sample beside a burst is left out of the correlation findings (issue 26).

MIDC's accumulated irradiance opens with the day before's total, then resets: that one
increment held 99.99 % of the increments' sum of squares, their autocorrelation read 0
at every lag, and the record "behaves like a random walk"; less 1-3 samples it read "the
noise level changes ... mostly motion". Its cloud transients made the outlying samples too
many to leave out, the start-up value with them.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.diagnostics import lone_apart
from noisevar.diagnostics.quantisation import second_difference_step


def _accumulated(seed: int, n: int = 1440) -> np.ndarray:
    """A day's accumulated irradiance on a 1e-6 grid, clouds at noon, yesterday's total
    at sample 0."""
    rng = np.random.default_rng(seed)
    k = np.arange(n)
    irr = 0.015 * np.clip(np.sin(np.pi * (k - 380) / 650), 0, None)
    cloud = (k > 780) & (k < 860)
    irr[cloud] *= rng.uniform(0.1, 1.0, cloud.sum())
    irr += np.where(irr > 0, rng.normal(0, 2e-5, n), 0)
    x = np.round(np.cumsum(irr), 6)
    x[0] = 4.6
    return x


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_reset_at_sample_0_beside_clouds_is_no_random_walk(seed: int) -> None:
    x = _accumulated(seed)
    r = noisevar.estimate(x)
    assert r.diagnostics.identifiable, r.diagnostics.verdict
    first = r.diagnostics.verdict.split(":")[0]
    for drop in (1, 2, 3):
        assert noisevar.estimate(x[drop:]).diagnostics.verdict.split(":")[0] == first


def test_lone_apart_keeps_the_lone_ones_only() -> None:
    burst = np.arange(780, 860, 7)
    assert lone_apart(np.r_[0, burst], 1440).tolist() == [0]
    assert lone_apart(burst, 1440) is None or lone_apart(burst, 1440).size == 0
    assert lone_apart(np.r_[0, 300, 600, burst], 1440) is None  # 3 lone of 1440: too many


def test_an_offset_over_a_reset_is_no_grid() -> None:
    """Plus 1e4 standard deviations, float32's rounding at the moved values (0.013) left
    the reset's one second difference above it, read as a grid of step 4.8: "noise under
    half a step on a grid"."""
    x = _accumulated(0)
    step = second_difference_step(x + 1e4 * float(np.std(x)))
    assert step is None or step < 1e-5, step

"""Quantised records with held values: R does not move under an offset, a scale or a trend,
and float rounding is never a still level (issue 26, item 2; real_audit4's ship temperature).

A slow walk rounded to a grid of 1 with little noise holds each value for tens of samples,
with a few large spikes (the ship's temperature: 1-degree steps, spikes to 139-255 degC).
A held stretch's residual is 0 in exact arithmetic; in floats it was rounding that an
offset, a scale of 1.8 or a trend moved, against local levels of 0, so outlier and jump
flags flipped: on main +32 moved R x1.0119 and x1.8 x0.9859 (seed 6), a trend x0.915
(seed 7), and a trend gave a still R of 4e-28 (seed 10).
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar


def held_record(seed: int, n: int = 20_000) -> np.ndarray:
    """A slow walk on a grid of 1 with noise of 0.05 steps and 40 spikes of 115-231 steps."""
    rng = np.random.default_rng(seed)
    c = 23.5 + np.cumsum(rng.normal(0.0, 0.003, n))
    z = np.round(c + rng.normal(0.0, 0.05, n))
    at = rng.choice(n, 40, replace=False)
    z[at] += rng.choice([115.0, 128.0, 231.0], at.size)
    return z


@pytest.mark.parametrize("seed", [6, 7])
def test_an_offset_does_not_move_r_and_a_scale_moves_it_by_its_square(seed):
    z = held_record(seed)
    base = noisevar.estimate(z).variance
    for g, c in ((1.0, 32.0), (1.8, 0.0), (1.8, 32.0), (-1.0, 0.0), (1e3, 0.0)):
        again = noisevar.estimate(g * z + c).variance
        assert again / (g * g) == pytest.approx(base, rel=1e-12), (g, c)
    assert noisevar.estimate(z + 1e4 * np.std(z)).variance == pytest.approx(base, rel=1e-12)


@pytest.mark.parametrize("seed", [7, 10])
def test_a_trend_does_not_move_r_nor_the_held_still_level(seed):
    z = held_record(seed)
    base = noisevar.estimate(z)
    again = noisevar.estimate(z + np.linspace(0.0, 1e3 * np.std(z), z.size))
    assert again.variance == pytest.approx(base.variance, rel=1e-9)
    # held values: no still R, or the grid's rounding error lsb²/12 on both (the grid of the
    # second differences, which the trend keeps; docs/algorithms.md §E3 Held values)
    assert (base.still is None) == (again.still is None)
    if base.still is not None:
        assert base.still.variance == pytest.approx(1.0 / 12.0, rel=1e-9)
        assert again.still.variance == pytest.approx(base.still.variance, rel=1e-9)
    magnitude = 1e3 * np.std(z) + np.max(np.abs(z))
    for r in again.diagnostics.regimes:  # a held stretch plus a trend is flat, not still
        assert not (r.still and r.variance < (1e-12 * magnitude) ** 2)


def test_a_line_is_refused_as_constant_not_given_a_rounding_level():
    x = 17.0 + 0.37 * np.arange(5_000)
    with pytest.raises(noisevar.NoisevarError, match="not positive|constant"):
        noisevar.estimate(x)

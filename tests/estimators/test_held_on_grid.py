"""A still R on a grid is never under the grid's rounding error lsb²/12 (issue 26, class 2).

Seeded day/night records: a still night whose noise is under the grid step (held values that
flip by a step now and then), a large smooth day with clouds, all quantised to 0.1. The
still stretches' R read 0.50-0.78 x lsb²/12 on some of them before the floor
(docs/algorithms.md §E3 *Held values*).
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv

LSB = 0.1
FLOOR = LSB * LSB / 12


def day_night(seed: int, sigma: float, n: int = 1440) -> np.ndarray:
    """A day of 1-minute samples: night, a cloudy day from sample 400 to 1040, night."""
    rng = np.random.default_rng(seed)
    k = np.arange(n)
    sun = np.clip(np.sin(np.pi * (k - 400) / 640), 0, None)
    clouds = 1 + 0.3 * np.convolve(rng.standard_normal(n), np.ones(15) / 15, "same")
    c = 2.03 + 0.02 * np.sin(k / 90) + 800 * sun**1.5 * clouds
    return LSB * np.round((c + sigma * rng.standard_normal(n)) / LSB)


@pytest.mark.parametrize(("seed", "sigma"), [(2, 0.02), (6, 0.015)])
def test_held_night_still_r_is_not_under_the_rounding_error(seed, sigma):
    est = nv.estimate(day_night(seed, sigma))
    assert est.diagnostics.lsb == pytest.approx(LSB)
    assert est.still is not None
    assert est.still.variance >= FLOOR * (1 - 1e-9)
    assert est.still.ci95[0] <= est.still.variance <= est.still.ci95[1]
    assert any("rounding error" in n for n in est.still.notes)
    assert est.diagnostics.quiet.variance == est.still.variance  # the quoted level too


@pytest.mark.parametrize("how", ["scale", "sign", "offset"])
def test_floor_follows_the_grid(how):
    z = day_night(2, 0.02)
    a, b = {"scale": (1e3, 0.0), "sign": (-1.0, 0.0), "offset": (1.0, 50.0)}[how]
    est = nv.estimate(a * z + b)
    assert est.still is not None
    assert est.still.variance >= a * a * FLOOR * (1 - 1e-6)

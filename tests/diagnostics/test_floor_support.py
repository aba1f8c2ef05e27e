"""The regimes' floor does not hinge on one or two blocks (issue 26, class 4).

A held stretch in a noisy record (a calm wind written 0) leaves, on some phases of the
block grid, one block whose residual is a faint leak from the hold's edge: far under the
sensor's level. As the floor, it set the cap and left every other stretch out (SURFRAD
wind speed with 3 leading samples dropped: 1 block of 40 still against 33).
"""

from __future__ import annotations

import numpy as np
import pytest
from numpy.typing import NDArray

import noisevar
from noisevar.diagnostics.regimes import FLOOR_BLOCKS, find_regimes


def _held_in_noise(seed: int, n: int = 1440) -> np.ndarray:
    """Still noise on a 0.1 grid, motion at 1100-1350, a hold at 0 over 974-1046."""
    rng = np.random.default_rng(seed)
    z = 2.0 + 0.15 * rng.standard_normal(n)
    z[1100:1350] += 0.5 * rng.standard_normal(250)
    z[974:1046] = 0.0
    return np.round(z, 1)


def _still_blocks(z: np.ndarray) -> int:
    prof = noisevar.estimate(z).diagnostics.level_profile
    spans = [(r.start, r.stop) for r in prof.regimes if r.still]
    return int(sum(np.sum((prof.start >= a) & (prof.stop <= b)) for a, b in spans))


@pytest.mark.parametrize("seed", range(8))
def test_a_held_block_is_no_floor_whatever_the_grid_phase(seed: int) -> None:
    z = _held_in_noise(seed)
    counts = [_still_blocks(z[d:]) for d in range(4)]
    assert min(counts) >= 25, counts  # the still noise: most of the record's 40 blocks


def _regimes(level: NDArray, lsb: float | None = None) -> tuple:
    """Regimes of blocks of 32 samples at ``level`` (scattered 10 %, seeded)."""
    rng = np.random.default_rng(0)
    level = level * np.exp(0.1 * rng.standard_normal(level.size))
    start = 32 * np.arange(level.size)
    return find_regimes(start, start + 32, level, np.full(level.size, 11.8), lsb)


def test_a_short_hold_on_a_grid_is_no_floor() -> None:
    # on a 0.1 grid: 2 blocks of held values far under 20 of still noise, 8 of motion
    regimes = _regimes(np.r_[np.full(20, 0.02), [1e-5, 1e-5], np.full(8, 0.5)], lsb=0.1)
    low = min(regimes, key=lambda r: r.variance)
    assert (low.stop - low.start) // 32 < FLOOR_BLOCKS and not low.still and not low.near_still
    assert sum(r.stop - r.start for r in regimes if r.still) == 20 * 32


def test_two_blocks_between_flat_runs_set_no_floor() -> None:
    # a missing-value code held (flat) on either side of 2 blocks: all edge, whatever the phase
    level = np.r_[np.full(10, 2.2), np.zeros(5), [0.1, 0.1], np.zeros(5), np.full(10, 2.0)]
    regimes = _regimes(level)
    assert sum(r.stop - r.start for r in regimes if r.still) == 20 * 32

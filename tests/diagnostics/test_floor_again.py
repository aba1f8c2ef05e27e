"""A floor with no quiet block is sought again above it (issue 26).

The lowest regime, one block whose median is the record's lowest and whose mean square a
burst raises, has no quiet block: it was the floor, and with it left out as not still
the record had no still stretch at all on that grid's phase (traffic's Zurich taxi north
velocity, two samples dropped). The floor is sought again among the other regimes under
twice the left-out blocks' mean square; a record with no still stretch gains none.
"""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.diagnostics.profile import CHI2_1_MEDIAN, LevelProfile, profile_from_blocks

BURST = 11


def _profile(levels: list[float], seed: int) -> LevelProfile:
    """Blocks of 32 white residuals of the given variances, block ``BURST`` with a burst."""
    rng = np.random.default_rng(seed)
    e = np.sqrt(np.array(levels))[:, None] * rng.standard_normal((len(levels), 32))
    e[BURST, [8, 16, 24]] += [0.5, -0.5, 0.5]
    sq = e**2
    robust = np.median(sq, axis=1) / CHI2_1_MEDIAN
    start, count = np.arange(len(levels)) * 32, np.full(len(levels), 32.0)
    w = sq / robust[:, None]
    tails = (w.sum(axis=1), (w * w).sum(axis=1), np.ones(1))
    return profile_from_blocks(
        start, start + 32, count, sq.mean(axis=1), robust, 1.0, 1.0, tails=tails
    )


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_a_still_stretch_above_a_burst_floor_is_still(seed: int) -> None:
    prof = _profile([1.0] * 4 + [0.01] * 4 + [1.0] * 3 + [5e-4] + [9.0] * 4, seed)
    assert prof.still_stretches == [(128, 256)]
    assert [(r.start, r.stop) for r in prof.regimes if r.still] == [(128, 256)]
    # the same record with motion where it was still gains no still stretch
    moving = _profile([1.0] * 11 + [5e-4] + [9.0] * 4, seed)
    assert not any(r.still for r in moving.regimes)
    assert moving.still_stretches == []

"""A short still start's R to use does not hang on the block grid's phase (issue 26).

A still start of 100 samples then motion: the record's grid ends its still stretch a
block before the motion, the reversed grid a sample or so earlier with its phase, so the
stretch still on both grids was 64 samples or 63 (too short) as leading samples were
dropped; the still regime less its edge blocks that are not whole quiet blocks is the
same stretch on every grid (BasicMotions' smartwatch, docs/algorithms.md §E1).
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.estimators.regimes import why_no_still


def _still_start(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.arange(400)
    motion = 3.0 * np.sin(2 * np.pi * t / 17) + rng.standard_normal(400)
    return np.r_[0.1 * rng.standard_normal(100), motion]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_still_start_keeps_its_r_to_use_with_leading_samples_dropped(seed: int) -> None:
    z = _still_start(seed)
    first = noisevar.estimate(z)
    assert first.still is not None
    lo, hi = first.still.ci95
    for k in (1, 2, 3):
        again = noisevar.estimate(z[k:])
        assert again.still is not None, (k, why_no_still(again))
        assert lo <= again.still.variance <= hi

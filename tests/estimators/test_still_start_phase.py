"""A short still start's R to use does not hang on the block grid's phase (issue 26).

A still start of 100 samples then motion: the record's grid, laid from its start, ends
the still stretch a block before the motion; the reversed grid, whose block at the start
takes the rest of the record, a sample or so earlier with its phase, so the stretch still
on both grids was 64 samples or 63 (too short) as leading samples were dropped. Read on
the grid laid from the end it touches, it is the same stretch (BasicMotions' smartwatch,
docs/algorithms.md §E1 *A still stretch at a record's end*).
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

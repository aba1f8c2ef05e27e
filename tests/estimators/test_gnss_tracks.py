"""GPS elevation tracks and short logs give one answer under drops and reversal (issue 26).

Two gpxpy tracks (``benchmarks/real_audit3.py``) moved their R to use when nothing
changed; each class is reproduced here on seeded synthetic records:

- a burst at the record's end that one profile grid joins to quiet samples (its last block
  takes the rest) and the reversed grid puts in one block: one level forwards, two regimes
  reversed, and the R to use flipped between R and the still R 4x below it (the hike's
  elevation: 66x);
- a run of step flags near the record's edge, called a lone step when the flags that would
  make it part of a cluster lay where the step detector cannot look (the car's elevation:
  with 2 leading samples dropped the whole record was left out as jumps).
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.estimators.regimes import why_no_still
from noisevar.numeric.steps import STEP_WINDOW, lone_steps


def _use(est):
    """The R to use: the still R, R when the record is one still regime, None when none."""
    if est.still is not None:
        return est.still
    return None if why_no_still(est) else est


def _end_burst(seed: int) -> np.ndarray:
    """296 samples of white noise, 26 of them at 6x its level about 10-40 samples from the end."""
    rng = np.random.default_rng(seed)
    z = rng.normal(size=296)
    a = 256 + int(rng.integers(0, 12))
    z[a : a + 26] += rng.normal(0, 6, 26)
    return z


@pytest.mark.parametrize("seed", [4, 19])
def test_a_burst_at_the_end_is_a_regime_on_either_grid(seed):
    z = _end_burst(seed)
    est = noisevar.estimate(z)
    use = _use(est)
    assert est.diagnostics.level_varies and est.still is not None
    assert use.variance < est.variance / 2  # the burst carries R: the still R is apart
    for x in (z[::-1], z[1:], z[2:], z[3:]):
        again = noisevar.estimate(x)
        assert again.diagnostics.level_varies
        assert again.still is not None  # the same R to use: the still R, not R
        assert use.ci95[0] <= again.still.variance <= use.ci95[1]


def test_a_run_near_the_edge_is_not_a_lone_step():
    # no other flag within 2w of a lone step is known only where the detector could flag
    # (k from 2w to n - 2w with its boundary pair): 4w - 1 samples from either edge
    w = STEP_WINDOW
    rng = np.random.default_rng(7)
    z = 0.01 * np.arange(300) + rng.standard_normal(300)

    def above(x):
        return x > 1.0

    def lone_at(a, x=z):
        found = np.zeros(x.size, dtype=bool)
        found[a : a + 2] = True  # a small step's boundary pair
        return bool(lone_steps(x, found, above)[a : a + 2].all())

    assert not lone_at(2 * w) and not lone_at(4 * w - 2)  # a neighbour could hide before it
    assert lone_at(4 * w - 1) and lone_at(150)
    assert lone_at(300 - 4 * w - 1) and not lone_at(300 - 4 * w)  # the mirror image
    for a in (2 * w, 4 * w - 2, 4 * w - 1, 150):  # reversed: the same decisions
        assert lone_at(300 - 2 - a, z[::-1]) == lone_at(a)

"""A rest at the minimum length keeps its R to use as the block grid moves (issue 26 item 2,
drops23).

The stretches still on both block grids are whole blocks of the record's grid, whose phase
moves with dropped leading samples: a 70-sample rest was 64 samples still on both grids on
the record's phase, read there (0.0056), and under 64 with 1-3 samples dropped, where the
rest read to the sample had no piece of 64 either: the R to use came and went (real_audit20's
cgm5: 0.487 -> none). Unless a stretch lies in a still stretch of each grid with a block to
spare, the fallbacks now read the rest on every phase, and the rest to the sample settles on
its own level within the grids' quiet level's interval, which no phase moves (a 71-sample
rest read 64 samples on one phase and none of 64 with 2 dropped, the grids' quiet level
0.0118, then 0.0114)
(docs/algorithms.md §E1 *A still stretch at the minimum length*;
``python benchmarks/still_edge_drops.py``).
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.estimators.regimes import why_no_still
from tests.estimators.rest_records import rest_in_motion


def _to_use(est):
    """The R to use (``regimes="still"``), None when there is none."""
    return None if why_no_still(est) else (est if est.still is None else est.still)


#: (seed, n, rest start, rest length): records of ``benchmarks/still_edge_drops.py``
#: (``record_of(138)`` and ``record_of(23017)``) whose R to use came and went on main
RESTS = [(138, 678, 257, 70), (23017, 467, 290, 71)]


@pytest.mark.parametrize(
    ("seed", "n", "at", "length", "step"),  # as drawn, and the first on a grid of 1.5σ
    [(*r, None) for r in RESTS] + [(*RESTS[0], 0.15)],
)
def test_a_rest_at_the_minimum_length_keeps_its_r_to_use(seed, n, at, length, step):
    z = rest_in_motion(seed, n, at, length)
    z = z if step is None else np.round(z / step) * step
    base = _to_use(noisevar.estimate(z))
    assert base is not None and base is not noisevar.estimate(z)  # the rest's own R
    lo, hi = base.ci95
    for x in (z[::-1], z[1:], z[2:], z[3:]):  # main: none with 1-3 (or 2-3) dropped
        use = _to_use(noisevar.estimate(x))
        assert use is not None
        assert lo <= use.variance <= hi


@pytest.mark.parametrize(("seed", "n", "at", "length"), RESTS)
def test_the_rest_is_read_on_its_own_samples(seed, n, at, length):
    z = rest_in_motion(seed, n, at, length)
    still = noisevar.estimate(z).still
    assert still is not None
    (a, b), *more = still.stretches
    assert not more
    assert b - a >= 64
    assert at - 4 <= a and b <= at + length + 4  # the rest, not the motion beside it
    for d in (1, 2, 3):
        again = noisevar.estimate(z[d:]).still
        assert again is not None
        (c, e), *_ = again.stretches
        assert abs(c + d - a) <= 3 and abs(e + d - b) <= 3  # the same samples, to a few

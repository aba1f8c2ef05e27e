"""A still stretch whose end moves by a profile block with the grid's phase (issue 26 class 4).

A record on a grid of 0.1 (a humidity logger's night, real_audit5's SURFRAD ``rh``):
still at the start, motion, then a short noisier stretch and a quiet end. Which block the
quiet end starts at depends on where the block grid starts, so dropping 2 leading samples
moved the still R from 0.0212 to 0.0118, outside its ci95 (0.0144-0.0341). The still R's
interval now holds its readings on the stretches grown to either grid's and shrunk by a
block at their inner ends (``still_grids.over_either_grid``), so it does not claim to know
the stretch's end better than a block.
"""

from __future__ import annotations

import numpy as np

import noisevar as nv


def quiet_end(seed: int = 57, n: int = 1440) -> np.ndarray:
    """Seeded: 0.35 still, then motion (1.5 or 3), a stretch at 1.5-2.2 x the quiet end's
    0.1 with random ends, on a grid of 0.1."""
    rng = np.random.default_rng(seed)
    s = np.ones(n)
    s[:400] = 0.35
    s[400:1290] = rng.choice([1.5, 3.0], size=1)[0]
    b, c = int(rng.integers(1250, 1340)), int(rng.integers(1340, 1380))
    s[b:c] = 0.1 * rng.uniform(1.5, 2.2)
    s[c:] = 0.1
    return np.round(rng.normal(size=n) * s * 10) / 10


def test_dropping_leading_samples_keeps_the_still_r_in_its_interval():
    z = quiet_end()
    est = nv.estimate(z)
    assert est.still is not None
    lo, hi = est.still.ci95
    for d in (1, 2, 3):
        again = nv.estimate(z[d:])
        assert again.still is not None
        assert lo <= again.still.variance <= hi, (d, again.still.variance, (lo, hi))


def test_the_interval_says_why_it_is_wide_and_reversal_keeps_the_value():
    z = quiet_end()
    est = nv.estimate(z)
    back = nv.estimate(z[::-1])
    assert back.still.variance == est.still.variance
    assert any("known to a profile block" in note for note in est.still.notes)
    # the quiet end's own level (0.01 + 0.1²/12) inside, the value unchanged
    assert est.still.ci95[0] <= 0.01 + 0.01 / 12 <= est.still.ci95[1]

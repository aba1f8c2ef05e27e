"""The samples past a grid's last block take its level but do not make it: otherwise the
back grid's last level (from the record's end) moved with the record's first samples, and
a lone step confirmed at 0.998-1.026 of that threshold came and went with 2 or 5 samples
dropped (real_audit12's floating lidar, 50 m speed: R x2.3, issue 26)."""

from __future__ import annotations

import numpy as np

from noisevar.estimators.auto._levels import Grids, kept_levels


def test_dropping_leading_samples_moves_no_back_level() -> None:
    rng = np.random.default_rng(5)
    block, m = 256, 6 * 256 + 48
    sq = rng.chisquare(1, m)
    sq[:3] = [40.0, 0.01, 25.0]  # the edge residuals of a record's first samples
    idx = np.array([100, 101, 700, 1500])
    _, back = kept_levels(sq, idx, Grids.make(m, block), 1.0)
    for d in (1, 2, 3, 47):
        _, moved = kept_levels(sq[d:], idx - d, Grids.make(m - d, block), 1.0)
        np.testing.assert_array_equal(moved, back)

"""A log whose stamps have many gaps leaves short pieces between them; ``auto``'s second,
coloured-noise pass (a fixed span of 5) reached pieces of 10-15 samples, shorter than its
16-sample block, and raised ``ValueError`` (the CLI: exit 3). Found on two bags nobody here
wrote (evo's ROS 1 SLAM poses, a ROS 2 ship IMU: benchmarks/real_audit4.py, issue 26).
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar

#: the steps (in periods) of 165 poses of evo's ROS_example.bag ``groundtruth`` topic
STEPS = [1, 2, 1, 6, *[1] * 10, 3, 4, 6, 2, 2, 1, 2, 2, 4, 3, 2, 6, 5, 34, 34, 7, 31, 3,
         *[1] * 30, 2, 2, 2, *[1] * 64, 2, *[1] * 34]  # fmt: skip


def test_a_short_piece_is_refused_with_a_message():
    """Under 10 samples a piece is refused in one line; from 10 it has an R (tiny26)."""
    z = np.random.default_rng(0).normal(size=11)
    with pytest.raises(noisevar.NoisevarError, match="too few samples"):
        noisevar.estimate(z[:9], span=5)
    est = noisevar.estimate(z, span=5)
    assert np.isfinite(est.variance) and est.ci95[0] <= est.variance <= est.ci95[1]


def test_pieces_between_a_logs_gaps_give_an_answer():
    t = np.r_[0.0, np.cumsum(STEPS)]  # in periods
    rng = np.random.default_rng(223)  # a trajectory (random walk) and white noise
    z = 0.3 * np.cumsum(rng.normal(size=t.size)) + rng.normal(size=t.size)
    est = noisevar.estimate(z, t=t)
    assert np.isfinite(est.variance) and est.ci95[0] <= est.variance <= est.ci95[1]

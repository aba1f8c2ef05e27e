"""A logger that drops samples often (PX4's ``vehicle_angular_velocity``: every other
sample missing about 45 % of the time): splitting at each long step left segments of a
dozen samples and the record was refused ("no uniform segment ... could be estimated").
Now the shortest steps are bridged when splitting at them leaves less than half of the
record usable, and the note says the samples were taken in order as if uniform."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv
from noisevar.diagnostics.segments import SEGMENT_USABLE, split_times

RATE = 409.0


def _times(rng: np.random.Generator, n: int, p: float) -> np.ndarray:
    steps = np.where(rng.random(n - 1) < p, 2.0, 1.0) / RATE
    return np.r_[0.0, np.cumsum(steps)]


@pytest.mark.parametrize("p", [0.2, 0.45])
def test_a_record_with_dropped_samples_is_estimated(p):
    rng = np.random.default_rng(0)
    n = 1800
    t, z = _times(rng, n, p), rng.normal(size=n)
    est = nv.estimate(z, t=t)
    assert est.ci95[0] <= 1.0 <= est.ci95[1]
    assert abs(est.variance / nv.estimate(z).variance - 1) < 0.05
    assert any("as if uniform" in note for note in est.notes)


def test_real_gaps_still_split():
    """A few long gaps in a regularly sampled record: split there, as before."""
    rng = np.random.default_rng(1)
    t = np.arange(3000) / 100.0
    t[1000:] += 5.0
    t[2000:] += 3.0
    seg = split_times(t)
    assert seg.segments == ((0, 1000), (1000, 2000), (2000, 3000))
    assert seg.jitter < 1e-9
    est = nv.estimate(rng.normal(size=3000), t=t)
    assert not any("as if uniform" in note for note in est.notes)


def test_bridging_keeps_long_gaps_and_is_needed():
    rng = np.random.default_rng(2)
    t = _times(rng, 4000, 0.45)
    t[2000:] += 10.0  # a pause of 10 s
    seg = split_times(t)
    assert 2000 in [a for a, _ in seg.segments]  # the pause still splits
    assert sum(b - a for a, b in seg.segments if b - a >= SEGMENT_USABLE) >= 2000
    assert seg.jitter >= 0.5  # said: steps of 2 periods inside the segments


def test_a_short_record_is_not_bridged():
    """Nothing can be made usable in 50 samples: the gap is kept (not bridged for nothing)."""
    t = np.r_[np.arange(25), np.arange(25) + 40.0]
    assert split_times(t).segments == ((0, 25), (25, 50))


def test_fixes_logged_at_irregular_times_are_estimated():
    """A track whose fixes are 1 s to a minute apart: no step is typical; taken in order."""
    rng = np.random.default_rng(0)
    t = np.r_[0.0, np.cumsum(rng.choice([1.0, 2.0, 3.0, 5.0, 10.0, 60.0], size=299))]
    est = nv.estimate(rng.normal(size=300), t=t)
    assert est.ci95[0] <= 1.0 <= est.ci95[1]
    assert any("as if uniform" in note for note in est.notes)

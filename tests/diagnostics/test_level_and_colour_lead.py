"""Where the level changes and the still stretches are as coloured as the whole record, the
lead names both, in one order, whatever the still level's ratio to R (issue 26, item 4).

AR(1) noise (φ 0.7) 1.9x louder over 35 % of the record: the still R sits 1.30-1.32x
under R, its 95 % interval's top just under R or not as 0-3 leading samples are dropped, and
on main the lead flipped between "the noise level changes along the record" (drop 0) and
"the noise is coloured" (drops 1-3), as real_audit11's watch_ride v_north did (R 1.45-1.48x
its still level, lag-1 +0.67 whole and +0.64 still; benchmarks/verdict_lead_flip.py)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar as nv
from noisevar.diagnostics.verdict_parts import BOTH, CHANGES


def _record(seed: int, louder: float) -> np.ndarray:
    x = lfilter([1.0], [1.0, -0.7], np.random.default_rng(seed).normal(size=8000))
    x[2000:4800] *= np.sqrt(louder)
    return x


@pytest.mark.parametrize("drop", range(4))
def test_one_lead_under_dropped_samples(drop):
    e = nv.estimate(_record(4, 1.9)[drop:])
    v = e.diagnostics.verdict
    assert e.still is not None and e.still.variance < e.variance < 2.0 * e.still.variance
    assert v.startswith(CHANGES), v  # one finding: the level change, the colour said with it
    assert v.startswith(BOTH + ":"), v
    assert "not white" in v  # the still stretches' own colour, said as before
    assert nv.format.eng(e.still.variance) in v


def test_both_names_the_records_colour():
    """GPS 1PPS (benchmarks/real_noise.py) led with both findings and no longer said which
    colour ("flicker at 4-16 samples"), its target: the still clause names the power law."""
    v = nv.estimate(_record(4, 1.9)).diagnostics.verdict
    assert v.startswith(BOTH + ":"), v
    assert "the whole record: random walk at 1 sample" in v and "power-law identification" in v

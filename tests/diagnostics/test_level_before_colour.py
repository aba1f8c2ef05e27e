"""Where the regimes split the record, a still R below R makes the level change the finding,
whatever its ratio (issue 26, item 4).

AR(1) noise (0.5) whose level is 2.5x over 35 % of the record: R 0.77 is an average of
two levels and the still R 0.50 the quiet one's, yet the verdict read "the noise is
coloured ... R is its white part" since R was under 2x the still R; SURFRAD's wind speed
flipped between the two findings with one sample dropped (R / still R 2.05 and 1.84)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar as nv


@pytest.mark.parametrize("seed", range(4))
def test_a_level_change_under_two_x_leads(seed):
    rng = np.random.default_rng(seed)
    x = lfilter([1.0], [1.0, -0.5], rng.normal(size=8000))
    x[2000:4800] *= np.sqrt(2.5)
    e = nv.estimate(x)
    v = e.diagnostics.verdict
    assert e.diagnostics.level_varies and e.still is not None
    assert e.still.variance < e.variance < 2.0 * e.still.variance
    assert v.startswith("the noise level changes along the record"), v
    assert "not white" in v  # the still stretches' own colour is still said
    assert nv.format.eng(e.still.variance) in v

"""Some outlying samples (1-5 %) holding nearly all of R are said on a record of one level
too, whatever the finding that leads (issue 26 item 4; benchmarks/real_audit13.py: a
runner's pace, 2.7 % holding 95 % of R, read "the noise is coloured" and nothing of them
when the level did not vary, and said them when it did)."""

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar as nv


@pytest.mark.parametrize("seed", range(8))
def test_some_outliers_holding_r_are_said(seed):
    rng = np.random.default_rng(seed)
    n = 1000
    x = lfilter([1.0], [1.0, -0.9], rng.normal(0, 0.05, n))  # coloured noise
    at = rng.choice(n, 25, replace=False)  # 2.5 % glitches of about 10 sigma
    x[at] += rng.choice([-1, 1], 25) * 1.2
    e = nv.estimate(x)
    assert e.core_variance is not None and e.variance > 10 * e.core_variance
    assert "outl" in e.diagnostics.verdict, e.diagnostics.verdict

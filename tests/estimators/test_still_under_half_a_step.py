"""No still R apart from R when R is under half a grid step's error (issue 26 class 4).

Under half a step the level a block reads follows where the signal sits within a step
(docs/algorithms.md §E3), so the regimes' levels are quantisation, not a sensor at rest:
an 8-bit PPG (real_audit6's systole ``ppg``, R 0.1375 on a grid of 1) had no quiet block,
and with one sample dropped one block of 125 samples turned quiet and its still R, 0.0876
(0.64x R, outside R's ci95), became the R to use. The still R was decided on the first R
(per-block spans, 1.73 there), the R quoted being the coloured-noise one (0.1375); it is
now decided on the R quoted (``still_set.kept_still``).
"""

from __future__ import annotations

import numpy as np

import noisevar as nv
from noisevar.diagnostics.quantisation import half_a_step
from noisevar.estimators.regimes import variance_for, why_no_still


def held_record(seed: int = 0, n: int = 6000) -> np.ndarray:
    """Seeded: noise 0.1 and 0.45 of a step in alternate 1000-sample stretches, on a slow
    sine of 3 steps, rounded to whole steps."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    s = np.where((t // 1000) % 2 == 0, 0.1, 0.45)
    return np.round(50 + 3.0 * np.sin(2 * np.pi * t / 3000) + rng.normal(size=n) * s)


def test_under_half_a_step_the_r_to_use_is_r():
    z = held_record()
    est = nv.estimate(z)
    assert est.diagnostics.lsb == 1.0
    assert est.variance < half_a_step(1.0)
    # before: a still R of 0.262 above R 0.165, "the R to use"
    assert est.still is None
    assert why_no_still(est) is None
    assert variance_for(est, "still") == est.variance


def test_dropping_samples_keeps_the_r_to_use():
    z = held_record(1)
    est = nv.estimate(z)
    lo, hi = est.ci95
    for d in (1, 2, 3):
        again = nv.estimate(z[d:])
        assert again.still is None
        assert lo <= variance_for(again, "still") <= hi


def test_a_trend_keeps_the_r_to_use():
    """Under the audits' trend (1e3 x the std over the record) the samples leave the grid
    but their second differences stay on it (``diagnostics.grid``): still no still R."""
    z = held_record()
    est = nv.estimate(z)
    lo, hi = est.ci95
    trended = nv.estimate(z + np.linspace(0.0, 1e3 * np.std(z), z.size))
    assert trended.still is None
    assert lo <= variance_for(trended, "still") <= hi

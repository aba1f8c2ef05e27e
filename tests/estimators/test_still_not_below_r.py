"""A still R not below R is quoted as the sensor's noise only when told apart from R
(issue 26, class 5).

sktime's solar generation (289 half-hours, 38 % exact zeros at night): on one phase of
the block grid R's method read the still regime at 1.77e-4 against R 7.33e-5 (the
coloured R's white part; 1.27x the first, white R), its interval 0.68x-77x R, and the
verdict quoted it as the R to use; reversed, or less one sample, there was no still R.
A seeded day curve with exact zeros at night and clear days between cloudy ones (noise
4e-6 on the clear days) had a still R of 2.9e-4, 1.8x R, quoted as the R to use.
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import noisevar
from noisevar.estimators.regimes import variance_for
from noisevar.estimators.still_set import ABOVE, SAME, not_quieter


def solar_like(seed: int, per: int = 48, day: int = 20) -> np.ndarray:
    """6 days of half-hours: a sin² day curve, exact zeros at night, 3 clear days (noise
    0.002) between cloudy ones (0.03), clipped at 0 and written to 5 decimals."""
    rng = np.random.default_rng(seed)
    n = 6 * per + 1
    t = np.arange(n) % per
    shape = np.where(t < day, np.sin(np.pi * t / day) ** 2, 0.0)
    amp = 0.4 * np.exp(0.1 * rng.standard_normal(7)).repeat(per)[:n]
    sd = np.array([0.03, 0.03, 0.002, 0.002, 0.002, 0.03, 0.03]).repeat(per)[:n]
    z = amp * shape + np.where(shape > 0, sd * rng.standard_normal(n), 0.0)
    return np.round(np.maximum(z, 0.0), 5)


@pytest.mark.parametrize("seed", [4, 42])
def test_a_still_r_above_r_and_not_told_apart_is_not_quoted(seed: int) -> None:
    z = solar_like(seed)
    for x in (z, z[::-1], z[1:], z[2:]):
        e = noisevar.estimate(x)
        q = e.diagnostics.quiet
        assert e.still is None, (e.still.variance / e.variance, e.verdict)
        assert q is not None and q.source in (ABOVE, SAME) and "no quieter level than R" in q.reason
        if q.source == SAME:  # R inside the still R's interval: R is the R to use
            assert variance_for(e, "still") == e.variance
        assert "the R to use" not in e.verdict
        # no level change claimed on one grid's phase and colour on another's
        assert e.verdict.startswith("the noise is coloured"), e.verdict


def test_a_still_r_above_r_told_apart_by_under_twice_stays() -> None:
    # heartpy's PPG: a dropout of 840 zeros pulls R down; the still R, 1.05x R, is the noise's
    e = noisevar.estimate(solar_like(42))
    r = e.variance
    ppg = replace(e, variance=1.05 * r, ci95=(1.02 * r, 1.08 * r))
    assert not_quieter(ppg, r) is None
    assert "inside their 95 % interval" in not_quieter(replace(ppg, ci95=(0.9 * r, 2 * r)), r)
    assert "over 2 times" in not_quieter(replace(ppg, variance=2.1 * r, ci95=(2 * r, 2.2 * r)), r)


def test_a_still_r_not_told_apart_from_twice_r_stays() -> None:
    # UT1-UTC (real_audit7): still R 1.9x R, then 2.8x with 2 samples dropped (ci95 1.9-4.4x):
    # its value crossed twice R with the grid's phase while its interval did not leave it
    e = noisevar.estimate(solar_like(42))
    r = e.variance
    near = replace(e, variance=2.3 * r, ci95=(1.5 * r, 3.5 * r))
    assert not_quieter(near, r) is None
    assert "over 2 times" in not_quieter(replace(near, ci95=(2.05 * r, 3.5 * r)), r)

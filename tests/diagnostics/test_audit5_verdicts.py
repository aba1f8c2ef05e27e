"""Failure classes of the fifth real-record audit (benchmarks/real_audit5.py: radiation and
weather stations' logs), seeded."""

import dataclasses

import numpy as np
import scipy.signal as ss

import noisevar
from noisevar import synth
from noisevar.diagnostics.results import QuietLevel
from noisevar.diagnostics.verdict import make_verdict


def test_no_quiet_block_quotes_no_still_level():
    """BSRN Payerne's pressure class: logged in whole hPa, slow weather drift and slow
    fluctuations (the noise is under half a step). The verdict said "the sensor noise
    measured in its still stretches (0% of it) is 0 (std 0)". Its regimes held on the grid
    are now one still level (docs/algorithms.md §E3 Held values), whose R is the rounding
    error lsb²/12, not 0."""
    rng = np.random.default_rng(0)
    n = 40000
    drift = np.cumsum(rng.normal(0, 0.02, n))
    z = np.round(950 + drift + ss.lfilter([1.0], [1.0, -0.9], rng.normal(0, 0.1, n)))
    est = noisevar.estimate(z)
    d = est.diagnostics
    assert d.level_varies
    assert est.still is None or est.still.variance >= 1.0 / 12.0 * (1 - 1e-9)
    assert "still stretches (0% of it)" not in d.verdict
    assert "is 0 (std 0)" not in d.verdict


def test_a_quiet_level_equal_to_r_is_not_quoted_as_the_sensors():
    """BSRN Payerne's global irradiance class (30 days at 1 min): the quiet level on R's
    residual came back as R itself (the profile's one quiet level), and the verdict read
    "the sensor noise measured in its still stretches (1% of it) is 625.9 ... against
    625.9 over the whole record". A level not below R is not a quieter one."""
    z = synth.still_start(800, n=3000, rng=np.random.default_rng(26), sigma=0.03)
    est = noisevar.estimate(z)
    d = est.diagnostics
    share = d.level_profile.quiet_share
    assert d.level_varies and not d.white and 0 < share < 0.5
    same = dataclasses.replace(d, quiet=QuietLevel(est.variance, *est.ci95, share, "record"))
    verdict = make_verdict(same, est.variance)
    assert "mostly motion" not in verdict
    assert "no stretch of it is measurably quieter" in verdict

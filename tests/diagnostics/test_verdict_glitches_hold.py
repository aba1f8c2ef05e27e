"""Outlying samples that hold nearly all of R are said on every verdict (issue 26).

traffic's ADS-B altitude (benchmarks/real_audit9.py): R = 424,591 ft² is 13,153x its core
variance, held by 2.2 % of the samples, and the verdict led "the noise level changes along
the record: R ... is an average", never naming them, then said "but even there the noise is
not white (lag-1 autocorrelation +0.00 beyond white noise's ...)".
"""

from __future__ import annotations

from types import SimpleNamespace

import numpy as np

import noisevar
from noisevar.diagnostics.verdict import CHANGES, still_colour
from noisevar.diagnostics.verdict_parts import GLITCHES_HOLD
from noisevar.diagnostics.whiteness import WhitenessTest
from noisevar.format import eng


def test_glitches_that_hold_r_lead_the_verdict(glitched_altitude) -> None:
    e = noisevar.estimate(glitched_altitude)
    v = e.verdict
    assert e.variance > 1e4 * e.core_variance
    assert v.startswith(GLITCHES_HOLD + ":"), v
    assert f"the core variance {eng(e.core_variance)}" in v, v
    assert "is an average" not in v, v


def test_the_still_stretches_colour_does_not_contradict_itself(glitched_altitude) -> None:
    """The record tests white (p = 0.99), its still stretches fail weakly (p = 0.03): no
    "not white ... +0.00" clause."""
    e = noisevar.estimate(glitched_altitude)
    d = e.diagnostics
    assert d.white and d.still_whiteness is not None and not d.still_whiteness.white
    assert "not white" not in e.verdict and "+0.00" not in e.verdict, e.verdict


def _departing_at(lag: int) -> WhitenessTest:
    k = 20
    acf, expected, band = np.zeros(k), np.zeros(k), np.full(k, 0.03)
    acf[lag - 1] = 0.2
    return WhitenessTest(acf, expected, band, 60.0, 1e-4, 4000, True)


def test_the_still_colour_names_the_lag_that_departs() -> None:
    diag = SimpleNamespace(
        still_whiteness=_departing_at(6),
        whiteness=None,
        level_varies=True,
        white=False,
        still_a_walk=False,
        smoothed=None,  # not a smoothed output; mostly still: not calm stretches either
        level_profile=SimpleNamespace(quiet_share=1.0),
        power_law=(),  # no colour named on the whole record
    )
    said = still_colour(diag)
    assert "lag-6 autocorrelation +0.20" in said, said


def test_glitches_beside_a_burst_are_named_after_the_finding() -> None:
    """White noise with one burst of motion (the level changes) and 40 glitches holding
    99.8 % of R: the burst leads, the glitches are named after it, with the core variance."""
    rng = np.random.default_rng(1)
    n = 8000
    z = rng.normal(0, 1, n)
    t = np.arange(1500)
    z[2000:3500] += 30 * np.sin(t / 3.0) * np.sin(np.pi * t / 1500)
    z[rng.choice(np.arange(100, n - 100), 40, replace=False)] += 300
    e = noisevar.estimate(z)
    v = e.verdict
    assert v.startswith(CHANGES), v
    assert "of the samples are outlying and hold" in v, v
    assert f"({eng(e.core_variance)})" in v, v

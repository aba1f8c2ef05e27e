"""How far a quantised record's signal travels does not depend on the samples dropped
before it (issue 26).

The correction for the rounding error that follows the signal (docs/algorithms.md §E3) is
made only where the signal crosses enough grid steps per span of the fit. The travel was
read off one phase of a subsample every quarter span: traffic's A320 pitch read 24.6
steps, 35.0 with its first sample dropped, and R moved x3.5 as the correction was made or
not. It is now the mean over every phase."""

from __future__ import annotations

import numpy as np

from noisevar.estimators.auto._quantised import Offsets


def _travel(c: np.ndarray, fit: int) -> float:
    off = Offsets(z=[c], c=[c], keep=[(0, c.size)], fit=fit)
    return off.travel(c.size)


def test_travel_is_the_same_whatever_the_phase():
    fit = 200
    i = np.arange(20_000)
    # a wiggle of twice the subsample's step: one phase sees it still, another at full swing
    c = 0.5 * np.sin(np.pi * i / (fit // 4)) + i / 500.0
    got = [_travel(c[k:], fit) for k in (0, 12, 25)]
    assert max(got) / min(got) < 1.02, got


def test_travel_of_a_ramp_is_its_rise():
    c = np.linspace(0.0, 40.0, 10_001)
    assert abs(_travel(c, 400) - 40.0) < 0.01

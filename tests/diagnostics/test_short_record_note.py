"""A record too short for the diagnostics (32-40 samples: a GPS topic's fixes) said "the
residual is degenerate (no variation to correlate)", untrue of the data: every residual
was left out at the record's edges. The note now says why there is no verdict."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv


@pytest.mark.parametrize("n", [32, 40])
def test_a_short_record_says_why_it_has_no_verdict(n):
    est = nv.estimate(np.random.default_rng(0).normal(size=n))
    said = [note for note in est.notes if note.startswith("no diagnostics")]
    assert said and "too short for the whiteness test" in said[0]
    assert not any("degenerate" in note for note in est.notes)
    assert np.isfinite(est.variance) and est.ci95[0] < est.variance < est.ci95[1]

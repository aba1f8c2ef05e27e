"""A record too short for the diagnostics (32-40 samples: a GPS topic's fixes) said "the
residual is degenerate (no variation to correlate)", untrue of the data: every residual
was left out at the record's edges. The note now says why there are no diagnostics, and
the verdict what could not be checked (``test_short_records.py``)."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv


@pytest.mark.parametrize("n", [32, 40])
def test_a_short_record_says_why_it_has_no_verdict(n):
    est = nv.estimate(np.random.default_rng(0).normal(size=n))
    said = [note for note in est.notes if note.startswith("no diagnostics")]
    assert said and "too short to diagnose" in said[0]
    assert est.verdict.startswith(f"only {n} samples")
    assert not any("degenerate" in note for note in est.notes)
    assert np.isfinite(est.variance) and est.ci95[0] < est.variance < est.ci95[1]

"""A record split at its gaps into segments too short to estimate says how it was split."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar


def test_the_refusal_counts_the_records_samples_and_its_longest_segment():
    """radvel's EPIC 203771098 (32 unevenly timed radial velocities) read "the signal has only
    3 samples", as if the record held 3."""
    rng = np.random.default_rng(0)
    t = np.cumsum(rng.uniform(0.5, 9.0, size=32))
    z = rng.normal(size=32)
    with pytest.raises(noisevar.NoisevarError) as err:
        noisevar.estimate(z, t=t)
    msg = str(err.value)
    assert "its 32 samples split at their gaps into" in msg
    assert "without t" in msg and "\n" not in msg

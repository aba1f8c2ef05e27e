"""A short record whose R is a few outlying samples says so (audit 11: Edge's smart-recorded
cadence, 96 samples, R 122x its core from 3 samples, read as "a first value")."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_outlying_samples_that_hold_r_are_named_on_96_samples(seed) -> None:
    rng = np.random.default_rng(seed)
    z = rng.normal(size=96)
    z[[20, 50, 80]] += 30.0
    est = noisevar.estimate(z)
    assert est.variance > 10 * est.core_variance
    # was: "only 96 samples: ... too few samples to check ... its tails and glitches", alone
    assert est.verdict.startswith("only 96 samples")
    assert "3.1% of the samples are outlying and hold" in est.verdict

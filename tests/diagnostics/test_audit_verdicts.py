"""Verdicts that must hold on any record, from benchmarks/real_audit.py's real records (issue 26).

On scikit-kinematics' Xsens record moved by hand (50 Hz, acc_x and gyr_y) no block is quiet,
and the verdict said "the sensor noise measured in its still stretches (0% of it) is 0
(std 0)": a filter told R = 0. A seeded record of white noise whose level changes every
50 samples (log-normal, sigma 1.5) reproduces it.
"""

from __future__ import annotations

import numpy as np

import noisevar


def level_changing(seed: int, n: int = 1000) -> np.ndarray:
    """White noise whose level is log-normal and changes every 50 samples."""
    rng = np.random.default_rng(seed)
    e = rng.normal(size=n)
    return e * np.exp(1.5 * rng.normal(size=n // 50).repeat(50))


def test_no_quiet_stretch_quotes_no_zero_level() -> None:
    est = noisevar.estimate(level_changing(6))  # (seed 2: a quiet block on the reversed grid)
    diag = est.diagnostics
    assert diag.level_varies and not diag.level_profile.any_quiet  # the case reproduced
    assert "no stretch of it is quiet" in diag.verdict
    assert " is 0 (std 0)" not in diag.verdict and "(0% of it)" not in diag.verdict
    assert est.still is None


def test_quoted_still_level_is_never_zero() -> None:
    for seed in range(4):
        verdict = noisevar.estimate(level_changing(seed)).diagnostics.verdict
        assert "give 0 " not in verdict and "is 0 (std 0)" not in verdict, verdict

"""The R a filter should use on real logs: the still regimes' estimate, and differenced data."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.estimators import estimate_chunked


def _still_start(n: int = 100000, seed: int = 3) -> np.ndarray:
    rng = np.random.default_rng(seed)
    z = rng.normal(0, 0.15, n)
    t = np.arange(n - 3000)
    z[3000:] += 20 * np.sin(t / 5.0) + 3 * np.sin(t / 1.7) + rng.normal(0, 2.0, n - 3000)
    return z


def test_a_short_still_start_gives_the_sensor_noise_on_the_same_residual():
    # issue 26 class 2 and 5: 3 % still, then motion; the still R is the same method's
    est = noisevar.estimate(_still_start())
    assert est.diagnostics.level_varies
    assert est.still is not None
    lo, hi = est.still.ci95
    assert lo < 0.0225 < hi
    assert est.variance > 50 * est.still.variance
    assert f"{est.still.variance:.4g}" in est.diagnostics.verdict
    row = est.to_row()
    assert row["still_variance"] == est.still.variance
    assert row["still_ci95_low"] == lo


def test_the_still_estimate_is_in_the_record_units():
    z = _still_start()
    one, big = noisevar.estimate(z), noisevar.estimate(z * 2.0**70)
    assert big.still.variance == pytest.approx(one.still.variance * 2.0**140, rel=1e-12)


def test_one_regime_has_no_still_estimate():
    est = noisevar.estimate(np.random.default_rng(1).normal(size=20000))
    assert est.still is None and est.to_row()["still_variance"] is None


def test_fast_motion_streamed_equals_in_memory():
    # the whole record's jump switch made the chunked engine read 3.57 (or fail, with chunks
    # of 4096) where the record in memory read 3.86; the jump rule is now each block's own
    z = _still_start(n=60000)
    one = noisevar.estimate(z)
    for chunk in (4096, 65536):
        many = estimate_chunked(lambda a, b: z[max(a, 0) : b].copy(), z.size, chunk=chunk)
        np.testing.assert_allclose(many.variance, one.variance, rtol=1e-9)
        np.testing.assert_allclose(many.still.variance, one.still.variance, rtol=1e-9)


def test_the_streamed_still_estimate_equals_the_one_in_memory():
    rng = np.random.default_rng(3)
    n = 60000
    z = rng.normal(0, 0.15, n) + np.sin(np.arange(n) / 3000)
    z[3000:20000] += rng.normal(0, 2.0, 17000)
    z[40000:45000] += rng.normal(0, 1.0, 5000)
    one = noisevar.estimate(z)
    assert one.still is not None
    many = estimate_chunked(lambda a, b: z[max(a, 0) : b].copy(), z.size, chunk=4096)
    np.testing.assert_allclose(many.still.variance, one.still.variance, rtol=1e-9)
    np.testing.assert_allclose(many.still.ci95, one.still.ci95, rtol=1e-9)


@pytest.mark.parametrize("method", ["auto", "diff2", "rice"])
def test_differenced_white_noise_gives_the_variance_per_sample(method):
    # issue 26 class 1: z = diff(white), variance 2 per sample; auto read 3.6 before
    rng = np.random.default_rng(0)
    z = np.diff(rng.normal(size=20001)) + 5 * np.sin(np.arange(20000) / 200)
    est = noisevar.estimate(z, method=method)
    assert est.variance == pytest.approx(2.0, rel=0.04)
    assert any("differenced" in n for n in est.notes)


def test_a_short_differenced_record_is_estimated_not_a_traceback():
    # 100 samples of diff(white): not white (p 1e-4..0.05) yet above the coloured-noise
    # threshold, so auto kept its span per block, and the differenced correction asked the
    # residual filter of span None: TypeError on 111 of 270 short MA(1) records (issue 26)
    v = []
    for seed in range(10):
        z = np.diff(np.random.default_rng(seed).normal(size=101))
        est = noisevar.estimate(z)
        assert np.isfinite(est.variance)
        if est.diagnostics.flags["differenced"]:  # corrected through span 5's own filter
            assert est.params["span"] is not None
        v.append(est.variance)
    assert np.mean(v) == pytest.approx(2.0, rel=0.15)

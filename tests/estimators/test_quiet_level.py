"""The quiet level on the same residual as R; absent, with a reason, when there is none.

Issue 26 item 5 (benchmarks/real_audit2.py): the quiet level of a one-level record was the
level profile's, on the diagnostics' fixed-span residual, which a smooth signal leaks
through: a monthly seasonal series read 2.3 against R 0.01 (ECG x0.27, nino3 SST x0.011
on real records), and the JSON, exports and pages carried both.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import noisevar
from noisevar.diagnostics.panel import noise_panel_data
from noisevar.estimators.still_set import still_gap
from noisevar.figures.noise import level_profile_plot


def _within_r(est: noisevar.VarianceEstimate) -> bool:
    """The quiet level inside R's ci95, and R inside the quiet level's."""
    q = est.diagnostics.quiet
    lo, hi = est.ci95
    return q.variance is not None and lo <= q.variance <= hi and q.lo <= est.variance <= q.hi


def _seasonal(seed: int = 0) -> np.ndarray:
    """benchmarks/real_audit2.py's: 800 months, period 12, a slow walk, white noise 0.1."""
    m = np.arange(800)
    rng = np.random.default_rng(seed)
    sst = 25 + 2 * np.sin(2 * np.pi * m / 12) + np.cumsum(rng.normal(0, 0.05, 800))
    return sst + rng.normal(0, 0.1, 800)


def test_a_seasonal_one_level_record_has_r_as_its_quiet_level() -> None:
    est = noisevar.estimate(_seasonal())
    d = est.diagnostics
    assert not d.level_varies and d.level_profile.quiet.all()
    assert d.quiet.source == "record" and d.quiet_variance == est.variance
    # the level profile's own level, on the diagnostics' residual, is the signal leaking
    assert d.level_profile.quiet_variance > 50 * est.ci95[1]
    out = json.loads(json.dumps(est.to_dict(), allow_nan=False))["diagnostics"]
    assert out["quiet_variance"] == est.variance
    assert out["quiet_level"]["source"] == "record"


@pytest.mark.parametrize(
    ("name", "signal"),
    [
        ("white", lambda t: 0.0 * t),
        ("slow sine", lambda t: 10.0 * np.sin(2 * np.pi * t / 500)),
        ("sine of 20 samples", lambda t: 5.0 * np.sin(2 * np.pi * t / 20)),
    ],
)
def test_one_level_records_quiet_level_within_r_interval(name: str, signal) -> None:
    for seed in range(3):
        t = np.arange(1000)
        est = noisevar.estimate(signal(t) + np.random.default_rng(seed).normal(size=t.size))
        assert not est.diagnostics.level_varies, (name, seed)
        assert _within_r(est), (name, seed, est.diagnostics.quiet, est.ci95)


def test_heavy_tails_are_the_noise_so_the_quiet_level_is_r() -> None:
    # blocks of t(4) noise left out of the quiet set by a spike change nothing the quiet
    # level's interval can tell (LevelProfile.one_quiet_level): the tails are the noise
    for seed in range(3):
        est = noisevar.estimate(np.random.default_rng(seed).standard_t(4, 4000))
        d = est.diagnostics
        assert not d.level_varies and d.quiet.source == "record" and _within_r(est)


def test_short_bursts_the_medians_miss_are_left_out_of_the_quiet_level() -> None:
    # one level for the regimes and no stretch apart (no .still), but R includes two short
    # bursts: the quiet level is R's method on the quiet stretches, the sensor's noise
    rng = np.random.default_rng(1)
    noise = rng.normal(size=6000)
    z = noise.copy()
    for c in (1500, 4000):
        z[c : c + 24] += 6 * np.sin(np.arange(24) / 1.1) + rng.normal(0, 4, 24)
    est = noisevar.estimate(z)
    d = est.diagnostics
    assert not d.level_varies and est.still is None
    assert d.quiet.source == "quiet stretches" and d.quiet.variance < est.variance
    assert d.quiet.variance == pytest.approx(np.var(noise), rel=0.05)
    assert d.quiet.lo <= est.ci95[1]


def test_with_motion_the_quiet_level_is_the_still_r() -> None:
    rng = np.random.default_rng(0)
    n = 20000
    z = rng.normal(0, 0.15, n)
    k = np.arange(n - 400)
    z[400:] += 20 * np.sin(k / 5.0) + rng.normal(0, 2.0, n - 400)  # a 2 % still start
    est = noisevar.estimate(z)
    d = est.diagnostics
    assert d.level_varies and est.still is not None
    assert d.quiet.source == "still" and d.quiet_variance == est.still.variance
    assert d.quiet_variance == pytest.approx(0.0225, rel=0.15)


def test_no_quiet_level_when_still_stretches_are_too_short() -> None:
    rng = np.random.default_rng(0)
    n = 20000
    z = rng.normal(0, 0.15, n)
    k = np.arange(n - 150)
    z[150:] += 20 * np.sin(k / 5.0) + rng.normal(0, 2.0, n - 150)
    est = noisevar.estimate(z)
    d = est.diagnostics
    assert d.level_varies and est.still is None
    gap = still_gap(d, est.variance, est.still)
    assert d.quiet_variance is None and d.quiet.reason == gap.removeprefix("regimes='still': ")
    out = json.loads(json.dumps(est.to_dict(), allow_nan=False))["diagnostics"]
    assert out["quiet_variance"] is None and out["quiet_level"]["reason"]
    panel = noise_panel_data(z, d)
    assert panel.quiet_variance is None
    json.dumps(panel.to_dict(), allow_nan=False)
    names = [tr.name for tr in level_profile_plot(panel).data]
    assert not any(str(n).startswith("quiet level") for n in names)


def test_no_quiet_level_when_no_stretch_is_quiet() -> None:
    # tests/estimators/test_still_set.py's level-changing noise (seed 2 has a quiet block on
    # the reversed record's grid, which the quiet set reads too: seed 6 has none on either)
    rng = np.random.default_rng(6)
    est = noisevar.estimate(rng.normal(size=1000) * np.exp(1.5 * rng.normal(size=20).repeat(50)))
    d = est.diagnostics
    assert not d.level_profile.any_quiet
    assert d.quiet_variance is None and "no stretch of the record is quiet" in d.quiet.reason


@pytest.mark.parametrize("scale", [1e-150, 1e150])
def test_the_quiet_level_in_the_record_units(scale: float) -> None:
    one = noisevar.estimate(_seasonal())
    est = noisevar.estimate(_seasonal() * scale)
    assert est.diagnostics.quiet_variance == est.variance
    assert est.diagnostics.quiet.hi == pytest.approx(one.diagnostics.quiet.hi * scale**2)


@settings(max_examples=60)
@given(
    n=st.integers(120, 3000),
    period=st.floats(6.0, 600.0),
    amplitude=st.floats(0.0, 50.0),
    walk=st.floats(0.0, 0.3),
    sigma=st.floats(1e-3, 1e3),
    seed=st.integers(0, 2**16),
)
def test_short_one_level_records_quiet_level_agrees_with_r(
    n: int, period: float, amplitude: float, walk: float, sigma: float, seed: int
) -> None:
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    z = amplitude * np.sin(2 * np.pi * t / period) + np.cumsum(rng.normal(0, walk, n))
    est = noisevar.estimate(sigma * (z + rng.normal(size=n)))
    d = est.diagnostics
    if d is None or d.level_varies:  # too short to diagnose ("no diagnostics: ..."), or motion
        return
    q = d.quiet
    assert q is not None and (q.variance is None) == bool(q.reason)
    assert q.source == "record" or not d.level_profile.quiet.all()  # 100 % quiet: R itself
    if q.source == "record":
        assert _within_r(est)
    elif q.variance is not None:  # the quiet blocks on R's residual: never above R
        assert q.source == "quiet stretches" and q.lo <= est.ci95[1], (q, est.ci95)

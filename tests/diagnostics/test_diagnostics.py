"""Noise diagnostics (issue 13): whiteness calibration and power, grid, gaps, quiet level,
identifiability, heavy tails, JSON. Seeded; rates over enough runs to be stable."""

from __future__ import annotations

import json

import numpy as np
import pytest
from scipy import special, stats

import noisevar.diagnostics.profile as profile
from noisevar import estimate, synth
from noisevar.diagnostics import diagnose

N = 6000


def _fast_ppf(q, nu):
    # χ²'s quantile as scipy.special's inverse survival function (scipy.stats.chi2.ppf
    # called block by block dominates diagnose's time; same numbers, see the test below)
    return special.chdtri(nu, 1.0 - np.asarray(q, dtype=float))


@pytest.fixture
def fast_chi2(monkeypatch):
    """Run diagnose many times: the quiet set's χ² quantiles through scipy.special."""
    monkeypatch.setattr(profile, "chi2_ppf", _fast_ppf)


def test_fast_chi2_quantile_is_scipys():
    q = np.array([0.025, 0.5, 0.975, 1 - 0.05 / 200, 1 - 0.05 / 2])
    nu = np.array([2.0, 37.5, 400.0, 7000.0, 15.0])
    np.testing.assert_allclose(_fast_ppf(q, nu), stats.chi2.ppf(q, nu), rtol=1e-12)


def _smooth(n: int = N) -> np.ndarray:
    x = np.arange(n)
    return 3.0 * np.sin(x / 500.0) + 1e-4 * x


def _white_rate(records: np.ndarray) -> float:
    return float(np.mean([diagnose(z).white for z in records]))


def test_whiteness_false_alarm_rate_on_white_noise(fast_chi2):
    runs = 200
    z = np.random.default_rng(101).standard_normal((runs, N)) + _smooth()
    false_alarm = 1.0 - _white_rate(z)
    assert 0.02 <= false_alarm <= 0.09, false_alarm


@pytest.mark.parametrize(
    ("kind", "params"), [("ar1", {"phi": 0.3}), ("white+flicker", {"ratio": 1.0})]
)
def test_whiteness_power_on_coloured_noise(fast_chi2, kind, params):
    runs = 40
    z = synth.noise(kind, N, rng=202, runs=runs, **params).values + _smooth()
    assert 1.0 - _white_rate(z) >= 0.9


@pytest.mark.parametrize("std_lsb", [0.5, 1.0, 3.0])
def test_lsb_found_exactly_on_quantised_data(fast_chi2, std_lsb):
    lsb = 0.0125
    rng = np.random.default_rng(int(std_lsb * 10))
    clean = _smooth() * 0.2
    zq, _ = synth.quantise(clean + rng.normal(0.0, std_lsb * lsb, N), lsb, (std_lsb * lsb) ** 2)
    diag = diagnose(zq)
    assert diag.lsb is not None
    assert diag.lsb == pytest.approx(lsb, rel=1e-9)
    assert diag.flags["quantised"]
    assert any("grid" in note for note in diag.notes)


def test_lsb_none_on_continuous_data(fast_chi2):
    z = np.random.default_rng(5).standard_normal((5, N)) * 0.3 + _smooth()
    assert all(diagnose(r).lsb is None for r in z)


def test_gap_from_times():
    rng = np.random.default_rng(6)
    z = rng.standard_normal(N) + _smooth()
    t = np.arange(N, dtype=float) * 0.1
    t[3000:] += 12.0  # 120 samples missing before sample 3000
    gaps = estimate(z, t=t).diagnostics.gaps
    assert len(gaps) == 1
    g = gaps[0]
    assert (g.index, g.kind) == (3000, "gap")
    assert g.missing == pytest.approx(120, abs=1)
    assert g.before == pytest.approx(t[2999]) and g.after == pytest.approx(t[3000])


def test_gap_from_dropped_nan():
    z = np.random.default_rng(7).standard_normal(N) + _smooth()
    z[1000:1100] = np.nan
    diag = estimate(z, drop_nonfinite=True).diagnostics
    assert diag.n == N - 100
    assert [(g.index, g.missing, g.kind) for g in diag.gaps] == [(1000, 100, "nan")]
    assert diag.flags["gaps"]


@pytest.mark.parametrize("seed", [11, 12, 13])
def test_quiet_variance_with_a_loud_half(seed):
    rng = np.random.default_rng(seed)
    noise = 0.5 * rng.standard_normal(N)
    k = np.arange(N)
    motion = np.where(k < N // 2, 20.0 * np.sin(2 * np.pi * k / 9.0), 0.0)  # a burst of motion
    diag = estimate(_smooth() + noise + motion).diagnostics
    quiet_truth = float(np.var(noise[N // 2 :]))
    assert diag.quiet_variance == pytest.approx(quiet_truth, rel=0.15)
    assert diag.level_varies


def test_identifiable_false_on_a_random_walk(fast_chi2):
    # identifiable only through a false alarm of the increments' whiteness test (about 5 %)
    walks = np.cumsum(np.random.default_rng(21).standard_normal((200, N // 2)), axis=1)
    rate = np.mean([diagnose(w).identifiable for w in walks])
    assert rate <= 0.1, rate


def test_identifiable_true_on_white_noise_plus_signal(fast_chi2):
    z = np.random.default_rng(22).standard_normal((20, N)) + _smooth()
    assert all(diagnose(r).identifiable for r in z)


def test_heavy_tails(fast_chi2):
    t5 = synth.noise("student_t", N, rng=31, runs=20, dof=5.0).values + _smooth()
    diags5 = [diagnose(r) for r in t5]
    assert np.mean([d.kurtosis > 4.0 for d in diags5]) >= 0.9
    assert np.mean([d.heavy_tailed for d in diags5]) >= 0.9
    t3 = synth.noise("student_t", N, rng=32, runs=20, dof=3.0).values + _smooth()
    diags3 = [diagnose(r) for r in t3]
    assert np.mean([d.fourth_moment_unreliable for d in diags3]) >= 0.9
    gauss = np.random.default_rng(33).standard_normal((20, N)) + _smooth()
    assert not any(diagnose(r).fourth_moment_unreliable for r in gauss)


def test_to_dict_is_strict_json():
    rng = np.random.default_rng(41)
    records = {
        "gauss": rng.standard_normal(N),
        "t3": synth.noise("student_t", N, rng=42, dof=3.0).values,
        "ar": synth.noise("ar1", N, rng=43, phi=0.7).values,
        "walk": np.cumsum(rng.standard_normal(N)),
        "grid": np.round(rng.standard_normal(N) * 2.0),
    }
    for name, z in records.items():
        d = estimate(z + _smooth()).diagnostics.to_dict()
        text = json.dumps(d, allow_nan=False)
        assert json.loads(text)["verdict"], name
        assert set(d["flags"]) == {
            "white",
            "heavy_tailed",
            "quantised",
            "gaps",
            "level_varies",
            "identifiable",
            "differenced",
        }

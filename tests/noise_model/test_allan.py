"""noisevar.allan: known answers, allantools agreement, intervals and bad input (§E4)."""

from __future__ import annotations

import json

import allantools
import numpy as np
import pytest

import noisevar
from noisevar.noise_model import allan


def test_white_phase_noise_gives_sqrt3_sigma_over_tau() -> None:
    sigma, rate = 2.0, 10.0
    x = sigma * np.random.default_rng(1).standard_normal(50_000)
    res = allan(x, rate=rate, data="phase")
    expected = np.sqrt(3.0) * sigma / res.taus
    np.testing.assert_allclose(res.deviation, expected, rtol=0.02)
    assert set(res.noise_type[:10]) == {"WPM"}
    np.testing.assert_allclose(res.slope, -1.0, atol=0.05)


def test_one_sigma_intervals_cover_about_68_percent() -> None:
    sigma, covered = 1.0, []
    for seed in range(20):
        x = sigma * np.random.default_rng(seed).standard_normal(20_000)
        res = allan(x, data="phase")
        expected = np.sqrt(3.0) * sigma / res.taus
        covered.append((res.interval[0] <= expected) & (expected <= res.interval[1]))
    assert 0.55 <= np.mean(covered) <= 0.8


def test_random_walk_phase_is_white_rate() -> None:
    """A random walk of phase (steps of std s) is white frequency: ADEV = s / sqrt(tau tau0)."""
    s, rate = 0.5, 4.0
    steps = s * np.random.default_rng(2).standard_normal(40_000)
    res = allan(np.cumsum(steps), rate=rate, data="phase")
    # frequency y = s * rate, white: sigma_y(tau) = s * rate / sqrt(m), m = tau * rate
    expected = s * rate / np.sqrt(res.taus * rate)
    np.testing.assert_allclose(res.deviation[:8], expected[:8], rtol=0.04)
    assert set(res.noise_type[:8]) == {"WFM"}
    np.testing.assert_allclose(res.slope[:8], -0.5, atol=0.08)


def test_rate_input_equals_its_integral_as_phase() -> None:
    y = np.random.default_rng(3).standard_normal(5000)
    rate = 2.0
    a = allan(y, rate=rate, data="rate")
    b = allan(np.concatenate([[0.0], np.cumsum(y - y.mean()) / rate]), rate=rate)
    np.testing.assert_allclose(a.deviation, b.deviation, rtol=1e-12)


@pytest.mark.parametrize(
    "kind, function",
    [("oadev", allantools.oadev), ("mdev", allantools.mdev), ("hdev", allantools.ohdev)],
)
def test_matches_allantools(kind: str, function) -> None:
    x = np.cumsum(np.random.default_rng(4).standard_normal(70_000))
    res = allan(x, rate=5.0, kind=kind)
    taus, dev, _, n = function(x, 5.0, "phase", res.taus)
    np.testing.assert_allclose(res.deviation, dev, rtol=1e-12)
    np.testing.assert_array_equal(res.n, n)
    np.testing.assert_allclose(res.taus, taus)


def test_all_taus_and_given_taus() -> None:
    x = np.random.default_rng(5).standard_normal(200)
    every = allan(x, taus="all")
    assert every.taus.tolist() == list(range(1, 100))
    given = allan(x, rate=2.0, taus=[0.5, 2.0, 8.0])
    np.testing.assert_allclose(given.taus, [0.5, 2.0, 8.0])
    # the same phase terms over half the time: twice the deviation
    np.testing.assert_allclose(given.deviation, 2 * every.deviation[[0, 3, 15]], rtol=1e-12)


def test_to_dict_is_json_safe() -> None:
    x = np.random.default_rng(6).standard_normal(300)
    d = allan(x, rate=1.0).to_dict()
    text = json.dumps(d, allow_nan=False)
    assert d["noise_type"][-1] is None and d["alpha"][-1] is None  # too few points to identify
    assert len(json.loads(text)["taus"]) == len(d["deviation"])
    assert noisevar.allan is allan and noisevar.AllanResult is type(allan(x))


@pytest.mark.parametrize(
    "kwargs, message",
    [
        ({"rate": 0.0}, "positive"),
        ({"rate": -1.0}, "positive"),
        ({"rate": None}, "positive"),
        ({"data": "freq"}, "'phase' or 'rate'"),
        ({"kind": "tdev"}, "kind"),
        ({"taus": "decade"}, "taus"),
        ({"taus": [0.1]}, "at least one sample period"),
        ({"taus": [1000.0]}, "too short"),
        ({"ci": 1.5}, "ci"),
    ],
)
def test_bad_input_says_what_is_wrong(kwargs: dict, message: str) -> None:
    with pytest.raises(noisevar.NoisevarError, match=message):
        allan(np.arange(100.0), **kwargs)


def test_too_short_and_non_finite_records() -> None:
    with pytest.raises(noisevar.NoisevarError, match="too short"):
        allan([1.0, 2.0, 3.0])
    with pytest.raises(noisevar.NoisevarError, match="NaN"):
        allan([1.0, np.nan, 3.0, 4.0, 5.0, 6.0])
    with pytest.raises(noisevar.NoisevarError, match="does not vary"):
        allan(np.full(100, 3.0), data="rate")
    with pytest.raises(noisevar.NoisevarError, match="one-dimensional"):
        allan(np.zeros((10, 2)))

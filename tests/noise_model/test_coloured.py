"""fit_coloured_noise: model choice and parameters on seeded records, augmented state, bad input."""

from __future__ import annotations

import json

import numpy as np
import pytest
import scipy.signal

import noisevar
from noisevar.errors import NoisevarError
from noisevar.noise_model import fit_coloured_noise

N = 6000


def _ar1(rng, phi, s2, n=N):
    return scipy.signal.lfilter([1.0], [1.0, -phi], rng.normal(0, np.sqrt(s2 * (1 - phi**2)), n))


def test_white_plus_ar1_is_found_with_its_parameters():
    rng = np.random.default_rng(1)
    z = _ar1(rng, 0.9, 1.0) + rng.normal(0, np.sqrt(0.5), N) + 0.01 * np.arange(N)
    f = fit_coloured_noise(z, rate=10.0)
    assert noisevar.fit_coloured_noise is fit_coloured_noise
    assert f.model == "white+ar1"
    assert f.r == pytest.approx(0.5, rel=0.15)
    assert f.phi[0] == pytest.approx(0.9, abs=0.02)
    assert f.sigma2_ar == pytest.approx(1.0, rel=0.25)
    # phi = exp(-T / tau_c)
    assert f.tau_c == pytest.approx(-0.1 / np.log(f.phi[0]))
    assert f.F.shape == (1, 1) and f.Q[0, 0] == f.q[0] and f.R[0, 0] == f.r


def test_white_plus_random_walk_is_found():
    rng = np.random.default_rng(2)
    z = np.cumsum(rng.normal(0, 0.1, N)) + rng.normal(0, 1.0, N)
    f = fit_coloured_noise(z)
    assert f.model == "white+rw"
    assert f.phi == (1.0,)
    assert f.q[0] == pytest.approx(0.01, rel=0.35)
    assert f.r == pytest.approx(1.0, rel=0.1)


def test_white_noise_stays_white_and_every_fit_is_reported():
    rng = np.random.default_rng(3)
    f = fit_coloured_noise(rng.normal(0, 2.0, N), criterion="bic")
    assert f.model == "white" and f.phi == () and f.F.shape == (0, 0)
    assert f.r == pytest.approx(4.0, rel=0.05)
    assert [m.name for m in f.fits] == ["white", "white+ar1", "white+rw"]
    best = min(f.fits, key=lambda m: m.bic)
    assert best.name == "white"
    d = json.loads(json.dumps(f.to_dict(), allow_nan=False))
    assert d["model"] == "white" and len(d["fits"]) == 3


@pytest.mark.parametrize(
    "kwargs,match",
    [
        ({"models": ("white", "pink")}, "unknown noise model"),
        ({"criterion": "hqic"}, "unknown criterion"),
        ({"rate": 0.0}, "rate"),
        ({"models": ()}, "non-empty"),
    ],
)
def test_bad_arguments(kwargs, match):
    with pytest.raises(NoisevarError, match=match):
        fit_coloured_noise(np.random.default_rng(0).normal(size=200), **kwargs)


@pytest.mark.parametrize("z", [np.ones(100), np.arange(10.0), np.r_[np.inf, np.ones(99)]])
def test_bad_signals(z):
    with pytest.raises(NoisevarError):
        fit_coloured_noise(z)

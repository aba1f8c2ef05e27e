"""noisevar.inertial_noise: recovery of simulated IEEE-952 terms, units, axes (§E4)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

import noisevar
from noisevar.noise_model import inertial_noise
from noisevar.noise_model.inertial import TERM_NAMES, fit_terms
from noisevar.noise_model.simulate import simulate_inertial

RATE = 100.0
TRUE = {"random_walk": 1e-3, "bias_instability": 1e-3, "rate_random_walk": 3e-4}


@pytest.fixture(scope="module")
def gyro() -> noisevar.InertialNoise:
    y = simulate_inertial(400_000, RATE, seed=7, **TRUE)
    return inertial_noise(y, RATE, unit="rad/s")


def test_recovers_n_b_k(gyro: noisevar.InertialNoise) -> None:
    assert gyro.random_walk == pytest.approx(TRUE["random_walk"], rel=0.02)
    assert gyro.bias_instability == pytest.approx(TRUE["bias_instability"], rel=0.15)
    assert gyro.rate_random_walk == pytest.approx(TRUE["rate_random_walk"], rel=0.3)
    # absent terms stay small: their deviation is under a tenth of the data's everywhere
    parts, total = gyro.model()
    assert np.all(parts["quantization"] < 0.1 * total)
    assert np.all(parts["rate_ramp"] < 0.1 * total)


def test_intervals_bracket_the_estimates(gyro: noisevar.InertialNoise) -> None:
    for t in gyro.terms:
        assert t.interval[0] <= t.value <= t.interval[1]
    n = gyro.term("N")
    assert n.interval[0] <= TRUE["random_walk"] <= n.interval[1] * 1.01


def test_units_and_discrete_equivalents(gyro: noisevar.InertialNoise) -> None:
    n, k, q = gyro.term("random_walk"), gyro.term("K"), gyro.term("Q")
    assert (n.unit, k.unit, q.unit) == ("rad/s/√Hz", "rad/s²/√Hz", "rad/s·s")
    assert n.discrete == pytest.approx(n.value * math.sqrt(RATE))
    assert k.discrete == pytest.approx(k.value / math.sqrt(RATE))
    assert [t.slope for t in gyro.terms] == [-1.0, -0.5, 0.0, 0.5, 1.0]
    assert [t.name for t in gyro.terms] == list(TERM_NAMES)


def test_quantization_and_ramp_are_recovered() -> None:
    y = simulate_inertial(
        200_000, RATE, quantization=2e-4, random_walk=1e-4, rate_ramp=1e-5, seed=3
    )
    fit = inertial_noise(y, RATE)
    assert fit.quantization == pytest.approx(2e-4, rel=0.05)
    assert fit.rate_ramp == pytest.approx(1e-5, rel=0.2)


def test_exact_allan_variance_gives_exact_terms() -> None:
    taus = np.geomspace(0.01, 1000.0, 18)
    coef = np.array([1e-8, 4e-6, 1e-6, 1e-9, 1e-12])
    a = np.column_stack(
        [3 / taus**2, 1 / taus, np.full(18, 2 * np.log(2) / np.pi), taus / 3, taus**2 / 2]
    )
    # exact and precise (large edf): every term is supported and recovered
    fitted, _ = fit_terms(taus, a @ coef, np.full(18, 1e6))
    np.testing.assert_allclose(fitted, coef, rtol=1e-6)
    # at edf 100 the small K is not told from 0 among the others: the choice leaves it out
    fitted, _ = fit_terms(taus, a @ coef, np.full(18, 100.0))
    assert fitted[3] == 0.0 and fitted[1] == pytest.approx(coef[1], rel=0.05)


def test_several_axes_along_either_axis() -> None:
    ys = np.stack(
        [simulate_inertial(50_000, RATE, random_walk=s, seed=i) for i, s in enumerate([1e-3, 4e-3])]
    )
    rows = inertial_noise(ys, RATE, axis=1)
    cols = inertial_noise(ys.T, RATE, axis=0, workers=1)
    assert len(rows) == len(cols) == 2
    for r, c, s in zip(rows, cols, [1e-3, 4e-3], strict=True):
        assert r.random_walk == c.random_walk == pytest.approx(s, rel=0.03)


def test_to_dict_is_json_safe(gyro: noisevar.InertialNoise) -> None:
    d = json.loads(json.dumps(gyro.to_dict(), allow_nan=False))
    assert set(d["terms"]) == set(TERM_NAMES)
    assert d["terms"]["random_walk"]["unit"] == "rad/s/√Hz"
    assert d["allan"]["kind"] == "oadev" and d["allan"]["data"] == "rate"


def test_bad_input() -> None:
    with pytest.raises(noisevar.NoisevarError, match="positive"):
        inertial_noise(np.zeros(100), 0.0)
    with pytest.raises(noisevar.NoisevarError, match="too short"):
        inertial_noise(np.random.default_rng(0).standard_normal(4), 10.0)
    with pytest.raises(noisevar.NoisevarError, match="1-D or 2-D"):
        inertial_noise(np.zeros((2, 2, 50)), 10.0)
    with pytest.raises(noisevar.NoisevarError, match="No term"):
        inertial_noise(np.random.default_rng(0).standard_normal(100), 1.0).term("X")


def test_k_interval_is_as_wide_as_the_information_allows() -> None:
    # WN + RW with the corner 40 Fourier frequencies up (allan_variance_ros's
    # accelerometer): K's 68 % interval's log half-width against fisher_bound's sd. The
    # bootstrap's Allan variances drawn independently across taus gave 0.61-1.05x (median
    # 0.7: K's interval covered 43-52 % of 150 axes); correlated as the fitted model's
    # they give 1.16-1.94x (the NNLS is not efficient)
    n, white = 2**20, 1e-3
    walk = 40 * 2 * math.pi / n * white * RATE
    cols = [
        simulate_inertial(n, RATE, random_walk=white, rate_random_walk=walk, seed=4000 + i)
        for i in range(6)
    ]
    sd = noisevar.noise_model.fisher_bound("WN+RW", {"N": white, "K": walk}, n, RATE).sd("K")
    half = [
        math.log(f.term("K").interval[1] / f.term("K").interval[0]) / 2
        for f in inertial_noise(np.column_stack(cols).T, RATE)
    ]
    assert 0.9 * sd < np.median(half) < 2.0 * sd


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_a_term_left_out_never_has_a_zero_width_interval(seed: int) -> None:
    """A short record (6.5 s at 200 Hz, like a small flight log): the refits all put K at
    0, and its interval was [0, 0], as if K were measured to be nothing. Its upper limit is
    now what the Allan variances alone allow, and holds the truth."""
    rng = np.random.default_rng(seed)
    k_true = 1e-5 * math.sqrt(200.0)  # the random walk's density, u/s/√Hz
    z = rng.normal(0, 0.003, 1300) + np.cumsum(rng.normal(0, 1e-5, 1300))
    res = inertial_noise(z, rate=200.0)
    for t in res.terms:
        assert t.interval[1] > 0, t.symbol
    k = next(t for t in res.terms if t.symbol == "K")
    assert k.interval[0] <= k_true <= k.interval[1]
    assert units_shown("m/s**2") == ["m/s²·s", "m/s²/√Hz", "m/s²", "m/s³/√Hz", "m/s³"]


def units_shown(unit: str) -> list[str]:
    from noisevar.units import term_unit

    return [term_unit(unit, s) for s in "QNBKR"]

"""GMWM composite IMU models: wavelet variance, processes, fit, choice, robust, axes (§F4)."""

from __future__ import annotations

import json
import math

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.noise_model.gmwm import estimator as est
from noisevar.noise_model.gmwm import fit_imu_model, fit_imu_records
from noisevar.noise_model.gmwm.processes import PROCESSES
from noisevar.noise_model.gmwm.wavelet import (
    dyadic_scales,
    flicker_wv,
    haar_wv,
    robust_inflation,
)
from noisevar.noise_model.simulate import flicker, gauss_markov_bias, simulate_inertial

TAU = 2.0 ** np.arange(1, 12)


def _sim(key: str, n: int, rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A record of one process (per-sample parameters) and its internal parameters."""
    if key == "WN":
        return 2.0 * rng.standard_normal(n), np.array([4.0])
    if key == "QN":
        return np.diff(0.5 * rng.standard_normal(n + 1)), np.array([0.25])
    if key == "RW":
        return np.cumsum(0.1 * rng.standard_normal(n)), np.array([0.01])
    if key == "GM":
        return gauss_markov_bias(n, 1.0, 1.0, 20.0, rng), np.array([1.0, 20.0])
    if key == "FL":
        return flicker(n, 1.0, 1.0, rng), np.array([1.0])
    return 0.01 * np.arange(n, dtype=float), np.array([1e-4])


@pytest.mark.parametrize("key", ["WN", "QN", "RW", "GM", "FL", "DR"])
def test_theoretical_wv_matches_simulation(key: str) -> None:
    rng = np.random.default_rng(5)
    n = 2**14
    tau = dyadic_scales(n)[:9]
    nus = []
    for _ in range(40):
        x, p = _sim(key, n, rng)
        nus.append(haar_wv(x[None, :], tau)[0][0])
    ratio = np.mean(nus, axis=0) / PROCESSES[key].wv(p, tau)
    # the drift's is exact; the others' means over 40 records within a few percent
    assert ratio == pytest.approx(np.ones(tau.size), abs=0.06)


def test_closed_forms() -> None:
    t = TAU
    assert PROCESSES["WN"].wv(np.array([3.0]), t) == pytest.approx(3.0 / t, rel=1e-12)
    assert PROCESSES["QN"].wv(np.array([2.0]), t) == pytest.approx(12.0 / t**2, rel=1e-12)
    assert PROCESSES["RW"].wv(np.array([1.0]), t) == pytest.approx((t**2 + 2) / (12 * t))
    assert PROCESSES["DR"].wv(np.array([4.0]), t) == pytest.approx(t**2 / 4.0, rel=1e-12)
    # GM: v (1 - phi) / 2 at t = 2, white with the long-run variance at large t, and a
    # random walk of increments 2 v / tc for a long tc
    v, tc = 2.0, 7.0
    phi = math.exp(-1 / tc)
    gm = PROCESSES["GM"].wv(np.array([v, tc]), np.array([2.0, 2.0**30]))
    assert gm[0] == pytest.approx(v * (1 - phi) / 2, rel=1e-9)
    long_run = v * (1 - phi**2) / (1 - phi) ** 2
    assert gm[1] == pytest.approx(long_run / 2.0**30, rel=1e-7)
    slow = PROCESSES["GM"].wv(np.array([1.0, 1e9]), t)
    rw = PROCESSES["RW"].wv(np.array([1.0 - math.exp(-2e-9)]), t)
    assert slow == pytest.approx(rw, rel=1e-6)
    # flicker: flat at ln 2 / pi at large scales
    assert flicker_wv(np.array([2.0**20]))[0] == pytest.approx(math.log(2) / math.pi, rel=1e-3)


def test_haar_wv_is_half_the_allan_variance() -> None:
    import allantools

    x = np.random.default_rng(1).standard_normal(4096)
    tau = dyadic_scales(x.size)[:8]
    nu, m = haar_wv(x[None, :], tau)
    _, dev, _, _ = allantools.oadev(x, rate=1.0, data_type="freq", taus=tau / 2)
    assert nu[0] == pytest.approx(dev**2 / 2, rel=1e-9)
    assert m == pytest.approx(x.size - tau + 1)


def test_covariance_matches_simulation() -> None:
    rng = np.random.default_rng(2)
    n, keys, p = 2**13, ("WN", "RW"), np.array([1.0, 1e-3])
    tau = dyadic_scales(n)[:8]
    nus = [
        haar_wv((rng.standard_normal(n) + np.cumsum(0.0316 * rng.standard_normal(n)))[None], tau)[
            0
        ][0]
        for _ in range(120)
    ]  # noqa: E501
    nu = est.model_wv(keys, p, tau)
    cov = est.model_cov(keys, p, est.WaveletVariance(tau, nu, n - tau + 1))
    sd_ratio = np.std(nus, axis=0) / np.sqrt(np.diag(cov))
    assert sd_ratio == pytest.approx(np.ones(tau.size), abs=0.2)


@pytest.fixture(scope="module")
def composite() -> tuple[np.ndarray, float]:
    rate = 100.0
    y = simulate_inertial(
        2**20,
        rate,
        quantization=2e-4,
        random_walk=1e-3,
        rate_random_walk=3e-5,
        gauss_markov=((1e-3, 5.0),),
        seed=3,
    )
    return y, rate


def test_composite_fit_recovers_the_model(composite: tuple[np.ndarray, float]) -> None:
    y, rate = composite
    fit = fit_imu_model(y, rate, unit="rad/s")
    assert fit.model == "QN+WN+GM+RW"
    assert fit.value("N") == pytest.approx(1e-3, rel=0.03)
    assert fit.value("Q") == pytest.approx(2e-4, rel=0.1)
    assert fit.value("GM1.sigma") == pytest.approx(1e-3, rel=0.3)
    assert fit.value("GM1.tau_c") == pytest.approx(5.0, rel=0.4)
    for p in fit.parameters:  # intervals exist, are finite and hold the estimate
        lo, hi = p.interval
        assert math.isfinite(lo) and math.isfinite(hi) and lo <= p.value <= hi
    chosen = [r for r in fit.table if r.chosen]
    assert len(chosen) == 1 and chosen[0].model == fit.model
    assert all(math.isfinite(r.wvic) and math.isfinite(r.bic) for r in fit.table)
    parts = fit.components()
    assert set(parts) == {"QN", "WN", "GM1", "RW"}
    assert np.sum(list(parts.values()), axis=0) == pytest.approx(fit.model_wv(), rel=1e-12)
    json.dumps(fit.to_dict())


def test_filter_bias_conversion(composite: tuple[np.ndarray, float]) -> None:
    y, rate = composite
    fit = fit_imu_model(y, rate, models=["WN+GM"], horizon=1.0)
    (s2,), (tc,) = np.square(fit.filter_bias.gm_sigma), fit.filter_bias.gm_tau_c
    # the continuous GM's Allan variance at T = 1 s, and K_eq^2 = 3 AVAR(T) / T
    avar = s2 * tc**2 * (2 / tc - 3 + 4 * math.exp(-1 / tc) - math.exp(-2 / tc))
    assert fit.filter_bias.random_walk == pytest.approx(math.sqrt(3 * avar), rel=0.01)
    # below tau_c this is about sigma sqrt(2 / tau_c), the short-horizon limit
    assert fit.filter_bias.random_walk == pytest.approx(math.sqrt(2 * s2 / tc), rel=0.1)
    assert "T = 1 s" in fit.filter_bias.note
    lo, hi = fit.filter_bias.interval  # the delta method on log K_eq: around K_eq
    assert 0 < lo < fit.filter_bias.random_walk < hi
    with pytest.raises(NoisevarError):
        fit_imu_model(y, rate, horizon=0.001)


def test_choice_picks_white_plus_random_walk() -> None:
    rate = 100.0
    y = simulate_inertial(2**19, rate, random_walk=2e-3, rate_random_walk=2e-4, seed=11)
    fit = fit_imu_model(y, rate)
    assert fit.model == "WN+RW"
    assert fit.value("K") == pytest.approx(2e-4, rel=0.3)
    # a random walk alone: K_eq is K at any horizon, and so is its interval
    assert fit.filter_bias.random_walk == pytest.approx(fit.value("K"), rel=1e-6)
    assert fit.filter_bias.interval == pytest.approx(fit.parameter("K").interval, rel=1e-6)
    white = fit_imu_model(np.random.default_rng(0).standard_normal(2**14), 1.0)
    assert white.model == "WN"
    assert white.value("N") == pytest.approx(1.0, rel=0.03)
    assert white.filter_bias.random_walk == 0.0 and white.filter_bias.interval == (0.0, 0.0)


def test_robust_wv_with_outliers() -> None:
    rate = 100.0
    y = simulate_inertial(2**17, rate, random_walk=1e-3, seed=4)
    rng = np.random.default_rng(9)
    bad = rng.choice(y.size, y.size // 1000, replace=False)
    y[bad] += 20.0 * 1e-3 * math.sqrt(rate) * rng.choice([-1.0, 1.0], bad.size)
    robust = fit_imu_model(y, rate, models=["WN"], robust=True)
    classical = fit_imu_model(y, rate, models=["WN"])
    assert robust.value("N") == pytest.approx(1e-3, rel=0.05)
    assert abs(classical.value("N") / 1e-3 - 1) > abs(robust.value("N") / 1e-3 - 1)
    assert robust_inflation() > 1.0


def test_multi_axis_equals_per_axis_loop() -> None:
    rate = 50.0
    x = np.column_stack(
        [simulate_inertial(2**14, rate, random_walk=1e-3 * (k + 1), seed=k) for k in range(3)]
    )
    together = fit_imu_model(x, rate, workers=2)
    for k, fit in enumerate(together):
        alone = fit_imu_model(x[:, k], rate)
        assert fit.model == alone.model
        assert fit.internal == pytest.approx(alone.internal, rel=1e-12)
    assert fit_imu_model(x.T, rate, axis=1)[2].internal == pytest.approx(together[2].internal)


def test_pooled_records() -> None:
    rate = 50.0
    recs = [simulate_inertial(2**14 + 1000 * k, rate, random_walk=1e-3, seed=k) for k in range(3)]
    fit = fit_imu_records(recs, rate, models=["WN"])
    assert fit.value("N") == pytest.approx(1e-3, rel=0.02)
    assert fit.scales.size == dyadic_scales(recs[-1].size).size


@pytest.mark.parametrize(
    "call",
    [
        lambda: fit_imu_model(np.array([1.0, np.nan] * 100), 1.0),
        lambda: fit_imu_model(np.ones(10), 1.0),
        lambda: fit_imu_model(np.ones(1000), 1.0),
        lambda: fit_imu_model(np.random.default_rng(0).standard_normal(100), -1.0),
        lambda: fit_imu_model(np.random.default_rng(0).standard_normal(100), 1.0, models=["XX"]),
        lambda: fit_imu_model(np.zeros((2, 2, 2)), 1.0),
        lambda: fit_imu_records([], 1.0),
    ],
)
def test_bad_input(call) -> None:  # noqa: ANN001
    with pytest.raises(NoisevarError):
        call()


def test_covariance_of_the_top_scales_is_a_valid_one() -> None:
    """Two scales' covariance divides by the smaller scale's (larger) count: dividing by
    the larger scale's made the top two scales' correlation exceed 1 (the matrix was
    indefinite and the choice's objective fell back to the diagonal)."""
    rng = np.random.default_rng(4)
    n, keys, p = 2**12, ("WN", "RW"), np.array([1.0, 1e-2])
    tau = dyadic_scales(n)
    x = rng.standard_normal((400, n)) + np.cumsum(0.1 * rng.standard_normal((400, n)), axis=1)
    emp = np.corrcoef(haar_wv(x, tau)[0].T)
    nu = est.model_wv(keys, p, tau)
    cov = est.model_cov(keys, p, est.WaveletVariance(tau, nu, n - tau + 1))
    corr = cov / np.sqrt(np.outer(np.diag(cov), np.diag(cov)))
    assert np.linalg.eigvalsh(corr)[0] > 0
    assert np.diag(corr, 1)[-3:] == pytest.approx(np.diag(emp, 1)[-3:], abs=0.08)

"""The Whittle information bound of composite IMU models (§E10): closed forms, binning."""

from __future__ import annotations

import math

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.noise_model import fit_imu_model
from noisevar.noise_model.gmwm import bound
from noisevar.noise_model.gmwm.bound import fisher_bound
from noisevar.noise_model.gmwm.processes import PROCESSES
from noisevar.noise_model.simulate import simulate_inertial

RATE = 400.0
N_3H = int(3 * 3600 * RATE)
ONE_GM = {"Q": 1.29e-4, "N": 1e-3, "GM1.sigma": 5e-4, "GM1.tau_c": 50.0, "K": 1e-5}


def test_white_noise_alone_is_the_sample_variance_bound() -> None:
    # var(s^2) = 2 sigma^4 / n: sd(N) / N = 1 / sqrt(2 n), on the n - 1 differences n - 2
    n = 10**6
    b = fisher_bound("WN", {"N": 1e-3}, n, 100.0)
    assert b.sd("N") == pytest.approx(1.0 / math.sqrt(2.0 * (n - 2)), rel=1e-9)


@pytest.mark.parametrize("nd,kd", [(0.002502, 6.97e-5), (1.888e-4, 2.557e-6)])
def test_random_walk_bound_is_its_corner_frequency_count(nd: float, kd: float) -> None:
    # sum_k 1 / (1 + (k / kc)^2)^2 ~ pi kc / 4 frequencies below the corner kc, where the
    # walk's spectrum meets the white noise's: sd(K) / K ~ 1 / sqrt(pi kc)
    b = fisher_bound("WN+RW", {"N": nd, "K": kd}, N_3H, RATE)
    kc = N_3H * (kd / math.sqrt(RATE)) / (2.0 * math.pi * nd * math.sqrt(RATE))
    assert b.sd("K") == pytest.approx(1.0 / math.sqrt(math.pi * kc), rel=0.03)
    assert b.sd("N") == pytest.approx(1.0 / math.sqrt(2.0 * N_3H), rel=1e-3)


def test_binned_information_equals_the_full_sum() -> None:
    n = 300_001  # 150 000 frequencies: binned above the first 4096
    b = fisher_bound("QN+WN+GM+RW", ONE_GM, n, 200.0)
    f = np.arange(1, (n - 1) // 2 + 1) / (n - 1)
    p = {"QN": (ONE_GM["Q"] * 200.0) ** 2, "WN": ONE_GM["N"] ** 2 * 200.0}
    gm = np.array([ONE_GM["GM1.sigma"] ** 2, ONE_GM["GM1.tau_c"] * 200.0])
    parts = [
        PROCESSES["QN"].spectrum(np.array([p["QN"]]), f),
        PROCESSES["WN"].spectrum(np.array([p["WN"]]), f),
        PROCESSES["GM"].spectrum(gm, f),
    ]
    h = 1e-5  # the GM's correlation time by central differences
    up = PROCESSES["GM"].spectrum(gm * [1.0, math.exp(h)], f)
    down = PROCESSES["GM"].spectrum(gm * [1.0, math.exp(-h)], f)
    parts.append((up - down) / (2.0 * h))
    parts.append(PROCESSES["RW"].spectrum(np.array([ONE_GM["K"] ** 2 / 200.0]), f))
    g = np.array(parts) / (parts[0] + parts[1] + parts[2] + parts[4])
    cov = np.linalg.inv(g @ g.T)
    # public logs: Q, N, sigma, K are square roots of theirs, tau_c is linear
    full = np.sqrt(np.diag(cov)) * np.array([0.5, 0.5, 0.5, 1.0, 0.5])
    assert np.array(b.relative_sd) == pytest.approx(full, rel=2e-3)
    assert b.names == ("Q", "N", "GM1.sigma", "GM1.tau_c", "K")


def test_within_is_the_log_normal_probability() -> None:
    b = fisher_bound("WN+RW", {"N": 0.002502, "K": 6.97e-5}, N_3H, RATE)
    s = b.sd("K")
    want = (
        math.erf(math.log(1.03) / s / math.sqrt(2)) / 2
        + math.erf(-math.log(0.97) / s / math.sqrt(2)) / 2
    )
    assert b.within("K", 0.03) == pytest.approx(want, rel=1e-9)
    assert b.to_dict()["parameters"][1]["name"] == "K"


def test_more_samples_tighter_bound() -> None:
    a = fisher_bound("QN+WN+GM+RW", ONE_GM, 10**6, 200.0)
    b = fisher_bound("QN+WN+GM+RW", ONE_GM, 4 * 10**6, 200.0)
    assert all(y < x for x, y in zip(a.relative_sd, b.relative_sd, strict=True))
    assert bound.EXACT < 4 * 10**6


@pytest.mark.parametrize(
    "model,values,n",
    [
        ("WN+DR", {"N": 1.0, "R": 1.0}, 1000),
        ("WN+RW", {"N": 1.0}, 1000),
        ("WN+RW", {"N": 1.0, "K": -1.0}, 1000),
        ("WN", {"N": 1.0}, 4),
        ("WN+XX", {"N": 1.0}, 1000),
    ],
)
def test_bad_input(model: str, values: dict, n: int) -> None:
    with pytest.raises(NoisevarError):
        fisher_bound(model, values, n, RATE)
    with pytest.raises(NoisevarError):
        fisher_bound("WN", {"N": 1.0}, 1000, RATE).within("K", 0.03)


def test_gmwm_k_is_unbiased_and_near_the_bound() -> None:
    # 40 seeded WN + RW records with the corner 40 Fourier frequencies up, as on
    # allan_variance_ros's accelerometer: the mean log error of K is within 2.5 standard
    # errors of 0 (weights from the data alone, the chi-square start, give -0.063, 2.8
    # standard errors low) and its spread within 1.3x the bound (measured 1.23x)
    n, rate, white = 2**18, 100.0, 1e-3
    walk = 40 * 2 * math.pi / n * white * rate
    x = np.column_stack(
        [
            simulate_inertial(n, rate, random_walk=white, rate_random_walk=walk, seed=3000 + i)
            for i in range(40)
        ]
    )
    fits = fit_imu_model(x, rate, models=["WN+RW"])
    err = np.log([f.value("K") / walk for f in fits])
    sd = fisher_bound("WN+RW", {"N": white, "K": walk}, n, rate).sd("K")
    assert abs(err.mean()) < 2.5 * err.std() / math.sqrt(err.size)
    assert err.std() < 1.3 * sd

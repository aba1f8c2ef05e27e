"""The search adds a power law only where it dominates some scale (docs/algorithms.md §E10,
issue 30): seeded records on which the search before this rule added one that did not."""

from __future__ import annotations

import numpy as np

from noisevar.noise_model.gmwm import fit_imu_model
from noisevar.noise_model.gmwm.fitting import as_rows, choose, identified, wavelet_variances
from noisevar.noise_model.simulate import simulate_inertial

#: allan_variance_ros's accelerometer (400 Hz, 3 h): noise density and bias random walk.
RATE, N_DENSITY, K_DENSITY = 400.0, 0.002502, 6.97e-5


def _ros_accelerometer(seed: int) -> np.ndarray:
    """The record of ``benchmarks/imu_k_bias.py``'s seed 2, accelerometer axis 2."""
    n = int(3 * 3600 * RATE)
    return simulate_inertial(n, RATE, random_walk=N_DENSITY, rate_random_walk=K_DENSITY, seed=seed)


def test_a_flicker_that_dominates_no_scale_is_not_added() -> None:
    y = _ros_accelerometer(2002)
    wv = wavelet_variances(as_rows(y, 0), robust=False)[0]
    # the model chosen before the rule: its flicker lies under the white noise and the
    # random walk at every scale; its random walk dominates the longest scales
    (sol, _) = choose(wv, ["WN+FL+RW"])
    assert not identified(sol, wv, "FL")
    assert identified(sol, wv, "RW")
    fit = fit_imu_model(y, RATE)
    assert fit.model == "WN+RW"  # was WN+FL+RW with K 33 % low
    assert abs(fit.value("K") / K_DENSITY - 1) < 0.3


def test_a_quantisation_under_the_white_noise_is_not_added() -> None:
    y = simulate_inertial(2**18, 200.0, random_walk=1e-3, rate_random_walk=3e-4, seed=13)
    assert fit_imu_model(y, 200.0).model == "WN+RW"  # was QN+WN+RW


def test_a_gm_in_the_random_walks_place_carries_the_random_walks_k() -> None:
    # benchmarks/imu_k_bias.py's seed 17, gyroscope axis 0 (white noise + random walk):
    # its longest scales dip, and HQ prefers a GM (tau_c ~ 6 min) by 0.4: K = 0 alone
    # before the note (issue 30, fifth round)
    n, nd, kd = int(3 * 3600 * RATE), 1.888e-4, 2.557e-6
    y = simulate_inertial(n, RATE, random_walk=nd, rate_random_walk=kd, seed=17010)
    fit = fit_imu_model(y, RATE, models=["WN+RW", "WN+GM"])
    assert fit.model == "WN+GM" and fit.value("K") == 0.0
    (note,) = [n for n in fit.notes if n.startswith("WN+RW is within")]
    rival = fit_imu_model(y, RATE, models=["WN+RW"]).parameter("K")
    assert f"K = {rival.value:.4g}" in note
    assert abs(rival.value / kd - 1) < 0.3


def test_a_plain_gm_carries_no_random_walk_note() -> None:
    y = simulate_inertial(2**17, 100.0, random_walk=1e-3, gauss_markov=((0.02, 5.0),), seed=3)
    fit = fit_imu_model(y, 100.0, models=["WN+RW", "WN+GM"])
    assert fit.model == "WN+GM"
    assert not [n for n in fit.notes if "is within" in n]

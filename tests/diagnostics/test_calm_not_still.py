"""Calm is not still (issue 26, real_audit12): a met mast's wind speed has no still
stretches, yet its calm ones were quoted as "the sensor noise measured in its still
stretches", 1.9-8.1x the bound two co-located anemometers give. Calm stretches whose noise
is correlated as the whole record's are the same signal at a lower level: their level is
said to be an upper bound; a sensor at rest between bursts of motion keeps its level."""

import numpy as np
from scipy.signal import lfilter

import noisevar as nv


def _wind(n: int, seed: int) -> np.ndarray:
    """A speed whose gusts (AR(1), 5 % of the speed) scale with it: quiet when calm."""
    rng = np.random.default_rng(seed)
    speed = np.abs(8 + 5 * np.sin(2 * np.pi * np.arange(n) * 7 / n)) + 0.5
    gust = lfilter([1.0], [1.0, -0.6], rng.normal(size=n))
    return speed + 0.05 * speed * gust + 0.01 * rng.normal(size=n)


def _imu(n: int, seed: int) -> np.ndarray:
    """Low-passed sensor noise at rest, with five bursts of motion of another correlation."""
    rng = np.random.default_rng(seed)
    z = 0.01 * lfilter([1.0], [1.0, -0.3], rng.normal(size=n))
    k = n // 10
    for a in range(k, n, 2 * k):
        z[a : a + k] += np.sin(np.arange(k) / 3.0) + 0.3 * lfilter(
            [1.0], [1.0, -0.9], rng.normal(size=k)
        )
    return z


def test_calm_stretches_are_an_upper_bound_and_still_ones_the_sensor_noise():
    for seed in (1, 2):
        wind = nv.estimate(_wind(20000, seed))
        assert wind.still is not None
        assert "sensor noise measured" not in wind.verdict
        assert "upper bound on the sensor's noise" in wind.verdict
        assert any("upper bound" in n for n in wind.still.notes)
        imu = nv.estimate(_imu(20000, seed))
        assert imu.still is not None
        assert "the sensor noise measured in its still stretches" in imu.verdict
        assert "upper bound" not in imu.verdict

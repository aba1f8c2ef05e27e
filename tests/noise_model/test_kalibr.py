"""Kalibr imu.yaml: values from the fits, the round trip, and bad files (§E4)."""

from __future__ import annotations

import builtins

import numpy as np
import pytest

import noisevar
from noisevar.noise_model import inertial_noise
from noisevar.noise_model.kalibr import (
    KalibrImu,
    kalibr_imu,
    parse_kalibr,
    read_kalibr,
    write_kalibr,
)
from noisevar.noise_model.simulate import simulate_inertial

RATE = 200.0


@pytest.fixture(scope="module")
def fits() -> tuple[tuple, tuple]:
    gyro = np.stack(
        [
            simulate_inertial(40_000, RATE, random_walk=n, rate_random_walk=1e-4, seed=i)
            for i, n in enumerate([1e-3, 2e-3, 1.5e-3])
        ]
    )
    accel = np.stack(
        [
            simulate_inertial(40_000, RATE, random_walk=2e-2, rate_random_walk=3e-3, seed=10 + i)
            for i in range(3)
        ]
    )
    return inertial_noise(gyro, RATE, axis=1), inertial_noise(accel, RATE, axis=1)


def test_values_are_the_worst_axis_times_the_inflation(fits) -> None:
    gyro, accel = fits
    imu = kalibr_imu(gyro, accel, inflation=10.0)
    # the largest N, raised to the largest white level sigma(tau0) sqrt(tau0) (issue 26)
    worst = max(max(g.random_walk, g.white_level) for g in gyro)
    assert imu.gyroscope_noise_density == pytest.approx(10 * worst)
    assert imu.gyroscope_noise_density == pytest.approx(10 * 2e-3, rel=0.05)
    assert imu.accelerometer_random_walk == pytest.approx(
        10 * max(a.rate_random_walk for a in accel)
    )
    assert imu.update_rate == RATE


def test_round_trip(tmp_path, fits) -> None:
    imu = kalibr_imu(*fits, inflation=2.5, rostopic="/sensors/imu")
    path = tmp_path / "imu.yaml"
    write_kalibr(imu, path)
    back = read_kalibr(path)
    assert back.rostopic == "/sensors/imu" and back.update_rate == RATE
    for key, value in imu.to_dict().items():
        if key != "rostopic":
            assert getattr(back, key) == pytest.approx(value, rel=1e-10)


def test_reads_kalibrs_own_example_without_pyyaml(monkeypatch) -> None:
    text = """#Accelerometers
accelerometer_noise_density: 1.86e-03   #Noise density (continuous-time)
accelerometer_random_walk:   4.33e-04   #Bias random walk

#Gyroscopes
gyroscope_noise_density:     1.87e-04   #Noise density (continuous-time)
gyroscope_random_walk:       2.66e-05   #Bias random walk

rostopic:                    /imu0      #the IMU ROS topic
update_rate:                 200.0      #Hz (for discretization of the values above)
"""
    with_yaml = parse_kalibr(text)
    real_import = builtins.__import__

    def no_yaml(name, *args, **kwargs):
        if name == "yaml":
            raise ImportError(name)
        return real_import(name, *args, **kwargs)

    monkeypatch.setattr(builtins, "__import__", no_yaml)
    without = parse_kalibr(text)
    expected = KalibrImu(1.86e-3, 4.33e-4, 1.87e-4, 2.66e-5, 200.0, "/imu0")
    assert with_yaml == without == expected


def test_bad_files_and_values(fits) -> None:
    with pytest.raises(noisevar.NoisevarError, match="missing"):
        parse_kalibr("update_rate: 100\n")
    with pytest.raises(noisevar.NoisevarError, match="not a number"):
        parse_kalibr(KalibrImu(1, 1, 1, 1, 100).to_yaml().replace("100", "fast"))
    with pytest.raises(noisevar.NoisevarError, match="inflation"):
        kalibr_imu(*fits, inflation=0.0)

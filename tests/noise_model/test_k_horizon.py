"""A bias random walk K from a record shorter than its horizon is not flown silently.

logcfg_audit: pymavlink's 0.9 s ArduPlane log wrote ``EK2_GBIAS_P_NSE`` 8.9e3x the
flight's, outside ArduPilot's documented range, with a warning only. An Allan variance at
tau needs 2 tau of record, so K at the 10 s horizon (``gmwm.model.HORIZON``) is measured
only when the fitted taus reach it (:func:`noisevar.noise_model.exports.model.k_rule`).
One rule on the consumer spec: a merged file (``Consumer.merged``) writes the line
commented out with the reason; a complete file keeps the value and its header says so.
"""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.noise_model import exports, inertial_noise
from noisevar.noise_model.kalibr import kalibr_imu

RATE = 100.0


def _fits(seconds: float) -> tuple:
    rng = np.random.default_rng(7)
    n = int(seconds * RATE)
    walk = np.cumsum(rng.normal(size=(3, n)), axis=1) * 1e-5
    gyro = inertial_noise(rng.normal(size=(3, n)) * 2e-3 + walk, RATE, unit="rad/s")
    accel = inertial_noise(rng.normal(size=(3, n)) * 2e-2 + 10 * walk, RATE, unit="m/s^2")
    return gyro, accel


def _model(seconds: float) -> exports.ImuModel:
    return exports.imu_model(*_fits(seconds))


def test_kalibr_file_of_the_cli_says_it_too() -> None:
    """``noisevar imu --kalibr`` writes ``kalibr_imu``'s file: the same rule, said."""
    imu = kalibr_imu(*_fits(4.0))
    said = [n for n in imu.notes if "random_walk NOT IDENTIFIED" in n]
    assert len(said) == 2 and "NOT IDENTIFIED" in imu.to_yaml()
    assert not any("NOT IDENTIFIED" in n for n in kalibr_imu(*_fits(30.0)).notes)


@pytest.fixture(scope="module")
def short() -> exports.ImuModel:
    return _model(4.0)  # longest octave tau 1.28 s, short of 10 s


def test_short_record_k_withheld_in_merged_files_kept_and_said_in_complete(short) -> None:
    assert "short of the 10 s horizon" in short.gyro.k_withheld and short.accel.k_withheld
    for f in exports.export(short, "all"):
        c = exports.consumer(f.consumer)
        back = c.parse(f.text)
        assert "gyroscope: K NOT IDENTIFIED" in f.text  # every file's header
        ks = [v for v in f.values if v.withheld]
        assert ks, f.consumer  # every consumer writes a K (or K^2 in its process noise)
        for v in ks:
            if c.merged:  # PX4, ArduPilot, VINS, ORB-SLAM3: the config keeps its own
                assert v.name not in back and "# WITHHELD (" in f.text, v.name
            else:  # Kalibr, OpenVINS, MATLAB, filterpy, robot_localization need every key
                assert back[v.name] == pytest.approx(v.value, rel=1e-9)
    merged = {k for k in exports.CONSUMERS if exports.consumer(k).merged}
    assert merged == {"px4", "ardupilot", "vins", "orbslam3"}


def test_record_reaching_the_horizon_keeps_k() -> None:
    long = _model(30.0)  # octave taus to 10.24 s
    assert long.gyro.k_withheld == "" and long.accel.k_withheld == ""
    (f,) = exports.export(long, "px4")
    assert "WITHHELD" not in f.text and "NOT IDENTIFIED" not in f.text
    assert "EKF2_GYR_B_NOISE" in exports.consumer("px4").parse(f.text)

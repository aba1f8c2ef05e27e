"""A flight log's own parameters set the EKF step its consumer file is written at.

ArduPilot's EKF predicts every ``max(1/SCHED_LOOP_RATE, EKF_TARGET_DT)``
(``NavEKF3_core::setup_core``); ArduPlane's 50 Hz loop makes that 20 ms, not EKF3's 12 ms
target, and ``AHRS_EKF_TYPE = 2`` flies EKF2, whose parameters are ``EK2_*``. On main the
ArduPilot file always held ``EK3_*`` at 83.3 Hz: on pymavlink's ArduPlane test log (EKF2,
50 Hz loop, ``benchmarks/logcfg_audit.py``) names no EKF on that vehicle reads, x1.29 too
high. PX4's ``EKF2_PREDICT_US``, when the ULog has it, is its step.
"""

from __future__ import annotations

import json
import math
from pathlib import Path

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.io.logs.params import log_parameters
from noisevar.noise_model import exports
from noisevar.noise_model.exports import ImuModel, SensorTerms

DATA = Path(__file__).resolve().parents[1] / "data"
MODEL = ImuModel(
    SensorTerms(2e-4, 3e-6, 0.0, "rad/s"), SensorTerms(3e-3, 4e-5, 0.0, "m/s^2"), 400.0
)


def test_the_parameters_of_real_logs():
    """pymavlink's ArduPlane 3.8 log (binary PARM) and pyulog's PX4 1.11 log (initial
    parameters), as their own tools read them."""
    ap = log_parameters(DATA / "ardupilot_pymavlink_test.BIN")
    assert ap["SCHED_LOOP_RATE"] == 50.0 and ap["AHRS_EKF_TYPE"] == 2.0
    assert ap["EK2_GYRO_P_NSE"] == pytest.approx(0.03)
    px4 = log_parameters(DATA / "px4_sample_log_small.ulg")
    assert px4["EKF2_GYR_NOISE"] == pytest.approx(0.015) and px4["IMU_INTEG_RATE"] == 200.0
    assert log_parameters(DATA / "ngimu_accel_y.csv") == {}


@pytest.mark.parametrize(
    ("params", "names", "rate"),
    [
        ({}, "EK3_", 1 / 0.012),  # no log: EKF3 at its target, said as assumed
        ({"SCHED_LOOP_RATE": 400.0, "AHRS_EKF_TYPE": 3.0}, "EK3_", 1 / 0.012),
        ({"SCHED_LOOP_RATE": 50.0, "AHRS_EKF_TYPE": 3.0}, "EK3_", 50.0),
        ({"SCHED_LOOP_RATE": 50.0, "AHRS_EKF_TYPE": 2.0}, "EK2_", 50.0),
        ({"SCHED_LOOP_RATE": 400.0, "AHRS_EKF_TYPE": 2.0}, "EK2_", 100.0),
    ],
)
def test_ardupilot_step_from_the_loop_rate_and_ekf(params, names, rate):
    (f,) = exports.export(MODEL, "ardupilot", params=params)
    got = exports.consumer("ardupilot").parse(f.text)
    assert got[names + "GYRO_P_NSE"] == pytest.approx(2e-4 * math.sqrt(rate), rel=1e-9)
    assert got[names + "ACC_P_NSE"] == pytest.approx(3e-3 * math.sqrt(rate), rel=1e-9)
    assert got[names + "GBIAS_P_NSE"] == pytest.approx(3e-6 * math.sqrt(rate), rel=1e-9)
    assert ("read from the flight log" in f.text) == bool(params)


@pytest.mark.parametrize(
    ("ekf", "name"),
    [(2.0, "ardupilot_ekf2.param"), (3.0, "ardupilot_ekf3.param"), (None, "ardupilot_ekf3.param")],
)
def test_ardupilot_file_is_named_after_the_ekf_it_holds(ekf, name, tmp_path):
    """logcfg_audit: pymavlink's ArduPlane log (EKF2) got ``ardupilot_ekf3.param`` holding
    ``EK2_*``; the name follows the EKF written, the same in a zip (the dashboard's)."""
    params = {} if ekf is None else {"AHRS_EKF_TYPE": ekf}
    (f,) = exports.export(MODEL, "ardupilot", params=params)
    assert f.filename == name and f"EK{int(ekf or 3)}_GYRO_P_NSE" in f.text
    (path,) = exports.write_exports([f], tmp_path)
    assert path.name == name


def test_ardupilot_out_of_range_is_warned():
    big = ImuModel(SensorTerms(2e-4, 0.1, 0.0, "rad/s"), MODEL.accel, 400.0)
    (f,) = exports.export(big, "ardupilot")
    assert "WARNING: EK3_GBIAS_P_NSE is outside the documented range" in f.text


def test_px4_step_from_ekf2_predict_us():
    (f,) = exports.export(MODEL, "px4", params={"EKF2_PREDICT_US": 8000.0})
    got = exports.consumer("px4").parse(f.text)
    assert got["EKF2_GYR_NOISE"] == pytest.approx(2e-4 * math.sqrt(125.0), rel=1e-9)
    assert "EKF2_PREDICT_US read from the flight log: 8000" in f.text


def test_px4_v1_11_step_from_its_firmware_release():
    """PX4 v1.11 has no EKF2_PREDICT_US: its ecl compiled the step in (FILTER_UPDATE_PERIOD_MS
    10 ms on PX4-ECL's Release_v1.11, 8 ms on Release_v1.10). pyulog's v1.11.2 log gives its
    release (``ver_sw_release``), and the file says where its step came from."""
    params = log_parameters(DATA / "px4_sample_log_small.ulg")
    assert "EKF2_PREDICT_US" not in params and params["ver_sw_release"] == 0x010B0200
    (f,) = exports.export(MODEL, "px4", params=params)
    assert "not a parameter of the flight's PX4 v1.11" in f.text and "Release_v1.11" in f.text
    got = exports.consumer("px4").parse(f.text)
    assert got["EKF2_GYR_NOISE"] == pytest.approx(2e-4 * math.sqrt(100.0), rel=1e-9)
    (f,) = exports.export(MODEL, "px4", params={"ver_sw_release": float(0x010A01FF)})
    got = exports.consumer("px4").parse(f.text)  # v1.10.1: 8 ms
    assert got["EKF2_GYR_NOISE"] == pytest.approx(2e-4 * math.sqrt(125.0), rel=1e-9)
    (f,) = exports.export(MODEL, "px4", params={"ver_sw_release": float(0x010E0000)})
    assert "EKF2_PREDICT_US assumed: 10000" in f.text  # a release not in the table: said


HEAD = [
    "FMT, 128, 89, FMT, BBnNZ, Type,Length,Name,Format,Columns",
    "FMT, 129, 31, PARM, QNf, TimeUS,Name,Value",
    "FMT, 133, 31, IMU, Qffffff, TimeUS,GyrX,GyrY,GyrZ,AccX,AccY,AccZ",
    "PARM, 1000, SCHED_LOOP_RATE, 50",
    "PARM, 1000, AHRS_EKF_TYPE, 2",
    "PARM, 1000, EK2_GYRO_P_NSE, 0.03",
]


def test_cli_writes_the_flights_ekf_at_its_loop_rate(tmp_path, capsys):
    """A Plane text log at 50 Hz flying EKF2: ``noisevar imu --export ardupilot`` writes
    EK2_* at 50 Hz, N sqrt(50) of the model it prints."""
    rng = np.random.default_rng(3)
    z = rng.normal(size=(3000, 6)) * np.array([2e-3] * 3 + [2e-2] * 3)
    lines = list(HEAD)
    for i, row in enumerate(z):
        lines.append(f"IMU, {2_000_000 + 20_000 * i}, " + ", ".join(f"{v:.7g}" for v in row))
    path = tmp_path / "plane.log"
    path.write_text("\n".join(lines) + "\n")
    argv = ["imu", str(path), "--topic", "IMU", "--gyro", "GyrX", "GyrY", "GyrZ"]
    argv += ["--accel", "AccX", "AccY", "AccZ", "--export", "ardupilot", "--out", str(tmp_path)]
    assert main([*argv, "--no-report", "--format", "json"]) == 0
    model = json.loads(capsys.readouterr().out)["model"]
    assert not (tmp_path / "ardupilot_ekf3.param").exists()  # named after the EKF it holds
    got = exports.consumer("ardupilot").parse((tmp_path / "ardupilot_ekf2.param").read_text())
    assert set(got) == {"EK2_GYRO_P_NSE", "EK2_ACC_P_NSE", "EK2_GBIAS_P_NSE", "EK2_ABIAS_P_NSE"}
    n = model["gyroscope"]["N"]
    assert got["EK2_GYRO_P_NSE"] == pytest.approx(n * math.sqrt(50.0), rel=1e-9)
    assert n == pytest.approx(2e-3 / math.sqrt(50.0), rel=0.1)  # the white level it was made of

"""``noisevar imu --export px4,ardupilot --gnss-pos/--gnss-vel``: the GNSS columns in metres
and metres a second (real_audit9: traffic's ADS-B records give latitude in degrees and ground
speed in knots; ``--gnss-pos latitude`` wrote EKF2_GPS_P_NOISE = 2e-5 "m" for a fix noise of
about 2 m, and a speed in knots was written as m/s)."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.estimators import estimate
from noisevar.noise_model import exports
from noisevar.noise_model.simulate import simulate_inertial

RATE = 5.0
BASE = ["--gyro", "gx", "--accel", "ax", "--gyro-unit", "rad/s", "--accel-unit", "m/s^2"]


@pytest.fixture(scope="module")
def flight(tmp_path_factory):
    """An IMU at 5 Hz beside an aircraft's ADS-B fields as traffic exports them."""
    rng = np.random.default_rng(9)
    n = 3000
    t = np.arange(n) / RATE
    cols = {
        "time": t,
        "gx": simulate_inertial(n, RATE, random_walk=2e-3, rate_random_walk=2e-5, seed=1),
        "ax": simulate_inertial(n, RATE, random_walk=2e-2, rate_random_walk=1e-4, seed=2),
        "latitude": 47.456 + 2e-6 * t + rng.normal(0, 2e-5, n),  # deg: about 2 m of noise
        "speed (kn)": 140 + 0.01 * t + rng.normal(0, 0.8, n),
        "north [ft]": 30 * t + rng.normal(0, 6.0, n),
    }
    path = tmp_path_factory.mktemp("flight") / "flight.csv"
    np.savetxt(path, np.column_stack(list(cols.values())), delimiter=",",
               header=",".join(cols), comments="")  # fmt: skip
    return path, cols


def _px4(tmp_path, path, *gnss: str) -> dict:
    out = tmp_path / "cfg"
    argv = ["imu", str(path), *BASE, "--export", "px4", "--out", str(out), "--no-report", *gnss]
    assert main(argv) == 0
    return exports.consumer("px4").parse((out / "px4_ekf2.params").read_text())


@pytest.mark.parametrize("column", ["latitude", "lat (deg)"])
def test_a_latitude_is_refused_as_a_gnss_position(capsys, flight, tmp_path, column) -> None:
    path, cols = flight
    if column != "latitude":
        path = tmp_path / "lat_deg.csv"
        np.savetxt(path, np.column_stack([cols["time"], cols["gx"], cols["ax"],
                   cols["latitude"]]), delimiter=",", header=f"time,gx,ax,{column}",
                   comments="")  # fmt: skip
    argv = ["imu", str(path), *BASE, "--export", "px4", "--out", str(tmp_path / "o"),
            "--no-report", "--gnss-pos", column]  # fmt: skip
    assert main(argv) == 2
    err = capsys.readouterr().err.strip()
    assert err.count("\n") == 0 and "degrees" in err and "metres" in err
    assert not (tmp_path / "o" / "px4_ekf2.params").exists()


def test_declared_units_are_converted_to_metres(flight, tmp_path) -> None:
    path, cols = flight
    px4 = _px4(tmp_path, path, "--gnss-pos", "north [ft]", "--gnss-vel", "speed (kn)")
    t = cols["time"]
    pos_ft = estimate(cols["north [ft]"], t=t).std
    vel_kn = estimate(cols["speed (kn)"], t=t).std
    assert px4["EKF2_GPS_P_NOISE"] == pytest.approx(0.3048 * pos_ft, rel=1e-6)
    assert px4["EKF2_GPS_V_NOISE"] == pytest.approx(1852 / 3600 * vel_kn, rel=1e-6)

"""An IMU is still when all its axes are: ``regimes="still"`` fits of a filter's IMU run on
one stretch where every gyroscope and accelerometer axis is still.

logcfg_audit: on autoflpy's ArduPlane SITL log each axis took its own longest still
stretch (the gyro's samples 11786-12687, AccX's 10-650), so the exported terms came from
different times, some of them when another axis moved. A single channel keeps its own.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.noise_model import inertial_noise
from noisevar.noise_model.inertial_axes import imu_still_stretch

RATE, N = 100.0, 6000
#: Still ranges: the gyro's longest is 3500-6000, the accelerometer's 0-2500; together
#: the longest is 0-2000.
GYRO_STILL, ACCEL_STILL = [(0, 2000), (3500, N)], [(0, 2500), (4500, N)]


def _axis(rng: np.random.Generator, still: list[tuple[int, int]], sigma: float) -> np.ndarray:
    i = np.arange(N)
    moving = np.ones(N, dtype=bool)
    for a, b in still:
        moving[a:b] = False
    motion = 40 * sigma * np.sin(2 * np.pi * i / 37.0) * moving
    return rng.normal(size=N) * sigma + motion


@pytest.fixture(scope="module")
def imu() -> np.ndarray:
    rng = np.random.default_rng(11)
    gyro = [_axis(rng, GYRO_STILL, 2e-3) for _ in range(3)]
    accel = [_axis(rng, ACCEL_STILL, 2e-2) for _ in range(3)]
    return np.stack(gyro + accel)


def test_one_stretch_where_every_axis_is_still(imu) -> None:
    s = imu_still_stretch(imu)
    assert s.axes == 6 and not s.one_regime
    assert 0 <= s.start <= 200 and 1800 <= s.stop <= 2000  # inside 0-2000, not 3500-6000
    assert "the IMU's longest stretch where all its 6 axes are still" in s.note
    fits = inertial_noise(imu[:3], RATE, unit="rad/s", regimes="still", stretch=s)
    assert all(s.note in f.notes for f in fits)
    # a single channel keeps its own longest still stretch
    (own,) = [n for n in inertial_noise(imu[0], RATE, regimes="still").notes if "still" in n]
    start = int(own.split("samples ")[1].split(" ")[0])
    assert start >= 3500


def test_no_common_still_stretch_is_refused_in_one_line() -> None:
    gyro = [_axis(np.random.default_rng(i), [(0, 1500), (4500, N)], 2e-3) for i in range(3)]
    accel = [_axis(np.random.default_rng(10 + i), [(1900, 3600)], 2e-2) for i in range(3)]
    with pytest.raises(NoisevarError, match="still on all the IMU's 6 axes together"):
        imu_still_stretch(np.stack(gyro + accel))


def test_cli_exports_fit_every_axis_on_the_imus_stretch(imu, tmp_path, capsys) -> None:
    names = ["gx", "gy", "gz", "ax", "ay", "az"]
    path = tmp_path / "imu.csv"
    np.savetxt(path, imu.T, delimiter=",", header=",".join(names), comments="")
    out = tmp_path / "cfg"
    argv = ["imu", str(path), "--rate", "100", "--gyro", *names[:3], "--accel", *names[3:]]
    argv += ["--export", "px4,kalibr", "--out", str(out), "--no-report", "--format", "json"]
    assert main([*argv, "--regimes", "still"]) == 0
    js = json.loads(capsys.readouterr().out)
    said = {n for c in names for n in js["columns"][c]["notes"] if n.startswith("regimes=")}
    assert len(said) == 1 and "all its 6 axes are still" in said.pop()
    for name in ("px4_ekf2.params", "imu.yaml"):  # every file's header says which samples
        assert "all its 6 axes are still" in (out / name).read_text()

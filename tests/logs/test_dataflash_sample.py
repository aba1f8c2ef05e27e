"""A real ArduPilot DataFlash log nobody here wrote (pymavlink's tests/test.BIN, LGPL-3.0,
tests/data/README.md): our reader against pymavlink's own message loop."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from noisevar.io import load_table
from noisevar.io.logs import dataflash

BIN = Path(__file__).resolve().parents[1] / "data" / "ardupilot_pymavlink_test.BIN"
AXES = ("GyrX", "GyrY", "GyrZ", "AccX", "AccY", "AccZ")


def _pymavlink(kind: str) -> tuple[np.ndarray, dict[str, np.ndarray]]:
    """TimeUS and the axes of every ``kind`` message, by pymavlink's own loop."""
    from pymavlink import mavutil

    log = mavutil.mavlink_connection(str(BIN))
    rows = []
    while (m := log.recv_match(type=kind)) is not None:
        rows.append((m.TimeUS, *(getattr(m, a) for a in AXES)))
    arr = np.asarray(rows, dtype=float)
    return arr[:, 0] / 1e6, {a: arr[:, i + 1] for i, a in enumerate(AXES)}


@pytest.mark.parametrize("kind", ["IMU", "IMU2"])
def test_imu_matches_pymavlinks_own_reading(kind):
    info = {t.name: t for t in dataflash.topics(BIN)}
    assert {"IMU", "IMU2", "GPS", "BARO"} <= info.keys()
    t_ref, ref = _pymavlink(kind)
    assert info[kind].count == t_ref.size > 40 and set(AXES) <= set(info[kind].fields)
    table = load_table(BIN, topic=kind)
    assert table.n_rows == t_ref.size
    np.testing.assert_allclose(np.asarray(table.time(), dtype=float), t_ref, rtol=0, atol=1e-9)
    for a in AXES:
        np.testing.assert_allclose(table.columns[a], ref[a], rtol=1e-7)
    assert 40 < 1 / table.sample_period < 50  # this log's IMU rate, about 45 Hz


def test_a_log_without_units_takes_ardupilots_definitions():
    """pymavlink's test.BIN logs no FMTU: it opened on ``AETR`` (control outputs), not its IMU,
    and its gyroscope had no unit to convert or to write an IMU config in."""
    from noisevar.io.logs import default_topic, list_topics

    topics = list_topics(BIN)
    assert default_topic(topics).name == "IMU"
    imu = load_table(BIN, topic="IMU")
    assert imu.units["GyrX"] == "rad/s" and imu.units["AccZ"] == "m/s**2"
    assert 9.5 < -np.median(imu.columns["AccZ"]) < 10.1  # gravity, in m/s²: the unit is right
    baro = load_table(BIN, topic="BARO")
    assert baro.units["Press"] == "Pa" and 9e4 < np.median(baro.columns["Press"]) < 1.1e5
    assert "AETR" not in {t.name for t in topics if t.units}  # only the messages it defines

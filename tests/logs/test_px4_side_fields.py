"""A PX4 log's bookkeeping fields are no signal (issue 26): ``sensor_combined``'s
``gyro_integral_dt`` (the integration interval in us, 4,839-4,889) was offered among the
Signal page's channels and estimated by ``--columns all`` as a sensor's noise."""

from __future__ import annotations

from pathlib import Path

from noisevar.cli import main
from noisevar.io import load_table

PX4 = Path(__file__).resolve().parents[1] / "data" / "px4_sample_log_small.ulg"


def test_intervals_and_flags_are_side_columns():
    t = load_table(PX4, topic="sensor_combined")
    assert t.signals == [f"{s}[{i}]" for s in ("gyro_rad", "accelerometer_m_s2") for i in range(3)]
    assert "integration interval" in t.side_columns["gyro_integral_dt"]
    assert "clipping" in t.side_columns["accelerometer_clipping"]
    imu = load_table(PX4, topic="vehicle_imu/0")
    assert {"delta_angle_dt", "gyro_device_id"} <= set(imu.side_columns)
    assert all(not c.endswith(("_dt", "_id")) for c in imu.signals)


def test_named_side_field_is_still_read():
    t = load_table(PX4, topic="sensor_combined")
    assert t.columns["gyro_integral_dt"].min() > 4800  # kept as written, for when it is named
    assert t.units["gyro_integral_dt"] == "us"


def test_columns_all_says_what_each_side_field_is(capsys):
    code = main(["estimate", str(PX4), "--topic", "sensor_combined", "--columns", "all"])
    out = capsys.readouterr().out
    assert code == 0
    row = next(line for line in out.splitlines() if "gyro_integral_dt" in line)
    assert "integration interval" in row and "not a measured signal" in row

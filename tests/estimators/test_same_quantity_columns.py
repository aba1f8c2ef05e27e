"""Which columns the Two sensors page opens on: sensors of one quantity, not a sensor's axes."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from noisevar.estimators import same_quantity_columns
from noisevar.io import load_table

ROOT = Path(__file__).resolve().parents[2]


def _signals(table) -> dict[str, np.ndarray]:
    names = table.signals or table.data_columns
    return {c: table.columns[c] for c in names if np.all(np.isfinite(table.columns[c]))}


def test_the_sample_sensors_are_picked() -> None:
    for name, want in [("three_sensors.csv", ["sensor_a", "sensor_b", "sensor_c"]),
                       ("two_sensors.csv", ["sensor_a", "sensor_b"])]:  # fmt: skip
        t = load_table(ROOT / "sample_data" / name)
        assert same_quantity_columns(_signals(t), dict(t.units)) == want, name


def test_a_sensors_axes_and_a_logs_fields_are_not() -> None:
    """The PX4 log's gyro and accelerometer axes (before: the first three columns, flagged
    "may not measure the same quantity" on opening); its sample intervals and an EKF's
    accelerations at rest are noise alone."""
    for topic in ("sensor_combined", "vehicle_local_position"):
        t = load_table(ROOT / "tests" / "data" / "px4_sample_log_small.ulg", topic=topic)
        assert same_quantity_columns(_signals(t), dict(t.units)) == [], topic
    t = load_table(ROOT / "sample_data" / "gps_circle.csv")
    assert same_quantity_columns(_signals(t), dict(t.units)) == []


def test_one_quantity_among_others_in_any_order_and_units() -> None:
    rng = np.random.default_rng(3)
    n = 5000
    s = np.cumsum(rng.normal(0, 0.3, n))
    cols = {
        "speed": np.gradient(s) + rng.normal(0, 0.05, n),
        "gps": s + rng.normal(0, 1.0, n),
        "temp": 20 + 0.001 * np.arange(n) + rng.normal(0, 0.1, n),
        "odometer": s + rng.normal(0, 0.5, n),
        "baro": s + rng.normal(0, 2.0, n),
    }
    assert same_quantity_columns(cols) == ["gps", "odometer", "baro"]
    assert same_quantity_columns(cols, most=2) == ["gps", "odometer"]  # the closest pair
    assert same_quantity_columns(cols, {"gps": "m", "odometer": "ft", "baro": "m"}) == [
        "gps", "baro",
    ]  # fmt: skip
    assert same_quantity_columns({"gps": cols["gps"]}) == []

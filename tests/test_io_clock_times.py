"""Phone apps' time columns (the exports teachers and students bring): a clock (Physics
Toolbox Sensor Suite: ``13:58:58:081`` on Android, milliseconds after a colon; ``58:58.081``
on iOS, a minute clock, ``;``-separated), across midnight and the hour, read as seconds;
AndroSensor's and SensorLog's time columns in their stated units."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.io import load_table


def _rows(start: float, period: float, n: int, fmt) -> list[str]:
    rng = np.random.default_rng(0)
    return [f"{fmt(start + i * period)}{rng.normal():.4f}" for i in range(n)]


def _hms_colon_ms(s: float) -> str:
    s = round(s * 1000) % 86_400_000
    return f"{s // 3_600_000:02d}:{s // 60_000 % 60:02d}:{s // 1000 % 60:02d}:{s % 1000:03d},"


def _ms_dot(s: float) -> str:
    s = round(s * 1000) % 3_600_000
    return f"{s // 60_000:02d}:{s // 1000 % 60:02d}.{s % 1000:03d};"


@pytest.mark.parametrize(
    ("header", "fmt", "start", "period"),
    [
        ("time,gFx", _hms_colon_ms, 13 * 3600 + 58 * 60, 0.005),  # Android
        ("time,gFx", _hms_colon_ms, 86_400 - 4.0, 0.005),  # across midnight
        ("time;gFx", _ms_dot, 3600 - 5.0, 0.01),  # iOS minute clock, across the hour
    ],
)
def test_clock_time_columns(tmp_path, header, fmt, start, period):
    path = tmp_path / "ptb.csv"
    path.write_text(header + "\n" + "\n".join(_rows(start, period, 2000, fmt)) + "\n")
    table = load_table(path)
    assert table.time_column == "time" and table.sample_period == pytest.approx(period)
    t = table.columns["time"]
    assert t[0] == 0 and np.all(np.diff(t) > 0)
    assert t[-1] == pytest.approx(1999 * period)


def test_hours_and_minutes_alone_are_not_a_clock(tmp_path):
    path = tmp_path / "hm.csv"
    path.write_text("time,x\n" + "".join(f"12:{i:02d},{i % 7}\n" for i in range(50)))
    with pytest.raises(NoisevarError, match="is not a number"):
        load_table(path)


def test_phone_app_time_columns(tmp_path):
    """AndroSensor's ``Time since start in ms`` and SensorLog's
    ``accelerometerTimestamp_sinceReboot(s)``: time columns in their stated units."""
    rng = np.random.default_rng(1)
    andro = tmp_path / "andro.csv"
    andro.write_text(
        "ACCELEROMETER X (m/s²);ACCELEROMETER Y (m/s²);Time since start in ms \n"
        + "".join(f"{rng.normal():.4f};{rng.normal():.4f};{i * 20}\n" for i in range(500))
    )
    table = load_table(andro)
    assert table.time_column == "Time since start in ms"
    assert table.sample_period == pytest.approx(0.02)
    assert table.first_signal == "ACCELEROMETER X (m/s²)"
    sl = tmp_path / "sensorlog.csv"
    sl.write_text(
        "loggingSample(N),accelerometerTimestamp_sinceReboot(s),accelerometerAccelerationX(G)\n"
        + "".join(f"{i},{1000 + i * 0.01:.3f},{rng.normal() * 0.01:.5f}\n" for i in range(500))
    )
    table = load_table(sl)
    assert table.time_column == "accelerometerTimestamp_sinceReboot(s)"
    assert table.sample_period == pytest.approx(0.01)
    assert table.first_signal == "accelerometerAccelerationX(G)"  # not the sample counter
    assert table.units["accelerometerAccelerationX(G)"] == "g"  # gravities, not gauss


def test_a_magnetometer_in_gauss_keeps_its_g():
    from noisevar.io.text import header_unit

    assert header_unit("mag_x (G)") == "G" and header_unit("accel_x (G)") == "g"


def test_a_date_column_and_a_clock_column_are_one_time(tmp_path):
    """NREL MIDC's logger CSV: ``DATE (MM/DD/YYYY),MST,...`` with ``1/1/2020,13:58``."""
    rng = np.random.default_rng(2)
    rows = [f"1/{d}/2020,{m // 60}:{m % 60:02d},{rng.normal():.3f}" for d in (1, 2)
            for m in range(1440)]  # fmt: skip
    path = tmp_path / "midc.csv"
    path.write_text("DATE (MM/DD/YYYY),MST,Global Horiz [W/m^2]\n" + "\n".join(rows) + "\n")
    table = load_table(path)
    assert table.sample_period == pytest.approx(60.0)
    t = table.columns[table.time_column]
    assert t[-1] == pytest.approx(2 * 86400 - 60) and np.all(np.diff(t) == 60)
    assert "MST" not in table.columns and any("joined into one time" in n for n in table.notes)

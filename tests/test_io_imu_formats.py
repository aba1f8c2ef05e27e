"""The IMU files VIO engineers have: EuRoC / TUM-VI (a ``#`` header) and Kalibr (epoch ns).

EuRoC's ``imu0/data.csv`` starts ``#timestamp [ns],w_RS_S_x [rad s^-1],...``: the header
was read as a comment, the time column became ``col0`` of integers beyond 2**53, and the
file was refused. Kalibr's ``timestamp`` column (nanoseconds since 1970, no unit in its
name) was read in seconds: its step 5e6 "is outside 1e-09 s to 1e+06 s", so ``noisevar
imu`` asked for ``--rate``; a ``time`` column in milliseconds since 1970 read 1000x slow.
"""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from noisevar.io import load_table
from noisevar.io.logs import list_topics

N, STEP_NS, T0 = 600, 5_000_000, 1_403_636_579_758_555_392  # 200 Hz, EuRoC's first stamp


def _write(path: Path, header: str, stamp) -> np.ndarray:
    rng = np.random.default_rng(0)
    g = rng.normal(0.0, 0.002, size=(N, 2))
    rows = [header] + [f"{stamp(i)},{g[i, 0]:.9f},{g[i, 1]:.9f}" for i in range(N)]
    path.write_text("\n".join(rows) + "\n")
    return g


def test_euroc_header_and_ns_stamps(tmp_path: Path) -> None:
    f = tmp_path / "data.csv"
    g = _write(f, "#timestamp [ns],w_RS_S_x [rad s^-1],w_RS_S_y [rad s^-1]",
               lambda i: T0 + i * STEP_NS)  # fmt: skip
    tab = load_table(f)
    assert list(tab.columns) == ["timestamp [ns]", "w_RS_S_x [rad s^-1]", "w_RS_S_y [rad s^-1]"]
    assert tab.time_column == "timestamp [ns]"
    assert tab.sample_period == pytest.approx(0.005, rel=1e-12)
    assert tab.units["w_RS_S_x [rad s^-1]"] == "rad s^-1"
    np.testing.assert_allclose(tab.columns["w_RS_S_y [rad s^-1]"], np.round(g[:, 1], 9))


@pytest.mark.parametrize(
    ("stamp", "unit"),
    [
        (lambda i: T0 + i * STEP_NS, "ns"),  # Kalibr: integers beyond 2**53
        (lambda i: f"{1.7e15 + i * 5000:.0f}", "us"),
        (lambda i: f"{1.7e12 + i * 5.0:.1f}", "ms"),
    ],
)
def test_epoch_stamps_read_in_their_unit(tmp_path: Path, stamp, unit: str) -> None:
    f = tmp_path / "imu.csv"
    _write(f, "timestamp,omega_x,omega_y", stamp)
    tab = load_table(f)
    assert tab.sample_period == pytest.approx(0.005, rel=1e-9)
    assert any(f"read in {unit} (its values are Unix times" in n for n in tab.notes)


@pytest.mark.parametrize(
    "stamp", [lambda i: f"{i * 0.005:.3f}", lambda i: f"{1.7e9 + i * 0.005:.3f}"]
)
def test_seconds_stay_seconds(tmp_path: Path, stamp) -> None:
    f = tmp_path / "imu.csv"
    _write(f, "timestamp,omega_x,omega_y", stamp)
    tab = load_table(f)
    assert tab.sample_period == pytest.approx(0.005, rel=1e-9)
    assert not any("Unix times" in n for n in tab.notes)


def test_commented_line_that_is_not_a_header(tmp_path: Path) -> None:
    f = tmp_path / "x.csv"
    f.write_text(
        "# recorded 2024-01-01, sensor A\n" + "\n".join(f"{i},{i * 0.5}" for i in range(50))
    )
    assert list(load_table(f).columns) == ["col0", "col1"]


def test_parquet_epoch_ns_without_unit_name(tmp_path: Path) -> None:
    import pandas as pd

    f = tmp_path / "imu.parquet"
    t = T0 + np.arange(N, dtype=np.int64) * STEP_NS
    pd.DataFrame({"timestamp": t, "gx": np.random.default_rng(1).normal(size=N)}).to_parquet(f)
    (info,) = list_topics(f)
    assert info.rate == pytest.approx(200.0, rel=1e-9)


def test_cli_imu_reads_a_kalibr_file(tmp_path: Path) -> None:
    f = tmp_path / "imu.csv"
    _write(f, "timestamp,omega_x,omega_y", lambda i: T0 + i * STEP_NS)
    out = subprocess.run(
        [sys.executable, "-m", "noisevar", "imu", str(f)], capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr
    assert "at 200 Hz" in out.stdout


def _rostopic(path: Path) -> None:
    """``rostopic echo -p /imu > imu.csv``: receive time, seq, stamp, frame, then the fields."""
    rng = np.random.default_rng(2)
    head = (
        "%time,field.header.seq,field.header.stamp,field.header.frame_id,"
        "field.orientation.x,field.orientation_covariance0,field.angular_velocity.x"
    )
    rows = [head]
    for i in range(N):
        stamp = T0 + i * STEP_NS
        rows.append(f"{stamp + 40_000 + int(rng.integers(0, 90_000))},{i},{stamp},imu_link,"
                    f"0,-1,{rng.normal(0.0, 0.01)!r}")  # fmt: skip
    path.write_text("\n".join(rows) + "\n")


def test_rostopic_echo_csv(tmp_path: Path) -> None:
    f = tmp_path / "imu.csv"
    _rostopic(f)
    tab = load_table(f)
    assert tab.time_column == "field.header.stamp"  # when the sensor sampled, not received
    assert tab.sample_period == pytest.approx(0.005, rel=1e-12)
    assert "field.header.frame_id" not in tab.columns
    assert any("holds text ('imu_link'), not numbers: left out" in n for n in tab.notes)
    assert tab.first_signal == "field.angular_velocity.x"
    from noisevar import NoisevarError, estimate

    with pytest.raises(NoisevarError, match="a counter or a clock"):
        estimate(tab.columns["field.header.seq"])
    out = subprocess.run(
        [sys.executable, "-m", "noisevar", "estimate", str(f)], capture_output=True, text=True
    )
    assert out.returncode == 0, out.stderr
    assert "column field.angular_velocity.x" in out.stdout.splitlines()[0]


def test_a_file_of_text_only_is_still_refused(tmp_path: Path) -> None:
    f = tmp_path / "t.csv"
    f.write_text("a,b\n" + "\n".join("x,y" for _ in range(20)))
    from noisevar import NoisevarError

    with pytest.raises(NoisevarError, match="is not a number"):
        load_table(f)


def test_microseconds_since_boot_are_said(tmp_path: Path) -> None:
    """PX4's ulog2csv: ``timestamp`` in microseconds since boot, which reads as 4000 s steps."""
    f = tmp_path / "log_sensor_gyro_0.csv"
    f.write_text("timestamp,x\n" + "\n".join(f"{12_345_678 + 4000 * i},{i % 7}" for i in range(50)))
    tab = load_table(f)
    assert any("PX4's ulog2csv writes microseconds since boot" in n for n in tab.notes)
    f.write_text(
        "timestamp_us,x\n" + "\n".join(f"{12_345_678 + 4000 * i},{i % 7}" for i in range(50))
    )
    tab = load_table(f)
    assert tab.sample_period == pytest.approx(0.004)
    assert not any("ulog2csv" in n for n in tab.notes)


def test_imu_and_allan_fit_the_signals_of_a_rostopic_csv(tmp_path: Path) -> None:
    """Every data column was fitted: the constant orientation aborted ``noisevar imu`` ("The
    record does not vary"), and ``noisevar allan`` took the receive clock ``%time``."""
    f = tmp_path / "imu.csv"
    _rostopic(f)
    run = [sys.executable, "-m", "noisevar"]
    imu = subprocess.run([*run, "imu", str(f)], capture_output=True, text=True)
    assert imu.returncode == 0, imu.stderr
    assert imu.stdout.count("samples at 200 Hz") == 1  # the one signal
    assert "file note: column 'field.header.frame_id' holds text" in imu.stdout
    allan = subprocess.run([*run, "allan", str(f)], capture_output=True, text=True)
    assert allan.returncode == 0, allan.stderr
    assert "of field.angular_velocity.x (" in allan.stdout


@pytest.mark.parametrize(
    ("head", "row", "period", "signal"),
    [
        # Sensor Logger (Android/iOS): ns since 1970 and the same clock in seconds
        ("time,seconds_elapsed,z,y,x", lambda i: f"{T0 + i * STEP_NS},{i * 0.005:.3f}", 0.005, "z"),
        # an Arduino's Serial.print(millis())
        ("millis,ax,ay,az", lambda i: f"{1000 + 10 * i}", 0.01, "ax"),
        ("micros,ax,ay,az", lambda i: f"{1000 + 2500 * i}", 0.0025, "ax"),
    ],
)
def test_phone_and_arduino_clocks(tmp_path: Path, head: str, row, period: float, signal: str):
    rng = np.random.default_rng(3)
    k = head.count(",") - row(0).count(",")
    lines = [head] + [
        row(i) + "".join(f",{float(v)!r}" for v in rng.normal(size=k)) for i in range(N)
    ]
    f = tmp_path / "log.csv"
    f.write_text("\n".join(lines) + "\n")
    tab = load_table(f)
    assert tab.sample_period == pytest.approx(period, rel=1e-9)
    assert tab.first_signal == signal  # not the second clock, not the clock


@pytest.mark.parametrize(
    ("stamp", "period"),
    [
        (lambda i: f"24-Nov-2023 13:{i // 60:02d}:{i % 60:02d}.000", 1.0),  # MATLAB
        (lambda i: f"11/24/2023 13:{i // 60:02d}:{i % 60:02d}", 1.0),  # Excel, US
        (lambda i: f"{1 + i // 2:02d}/03/2024 {12 * (i % 2):02d}:00", 43200.0),  # day first
    ],
)
def test_date_times_as_matlab_and_excel_write_them(tmp_path: Path, stamp, period: float):
    f = tmp_path / "log.csv"
    f.write_text("Timestamp,x\n" + "\n".join(f"{stamp(i)},{(i * 7919) % 101}" for i in range(50)))
    assert load_table(f).sample_period == pytest.approx(period)


def test_units_row_utf16_and_a_time_unit_in_it(tmp_path: Path) -> None:
    """A row of units under the header (data loggers, LabVIEW) and a UTF-16 file (Excel's
    "Unicode Text", Windows tools) were refused ("'s' is not a number"; "binary file")."""
    rows = "\n".join(f"{5 * i},{(i * 7919) % 101 / 10}" for i in range(200))
    f = tmp_path / "units.txt"
    f.write_text("time,ax\nms,m/s^2\n" + rows, encoding="utf-16")
    tab = load_table(f)
    assert tab.sample_period == pytest.approx(0.005)
    assert tab.units == {"ax": "m/s^2"}
    assert any("read in ms (the units row)" in n for n in tab.notes)


def test_euroc_file_to_a_filter_config_in_one_command(tmp_path: Path) -> None:
    """``noisevar imu data.csv --export ...`` asked for --gyro and --accel though the file
    declares which columns are rates (rad s^-1) and which accelerations (m s^-2)."""
    rng = np.random.default_rng(4)
    head = "#timestamp [ns]," + ",".join(
        [f"w_RS_S_{a} [rad s^-1]" for a in "xyz"] + [f"a_RS_S_{a} [m s^-2]" for a in "xyz"]
    )
    rows = [head] + [
        f"{T0 + i * STEP_NS}," + ",".join(f"{float(v)!r}" for v in rng.normal(0, 0.01, 6))
        for i in range(2000)
    ]
    f = tmp_path / "data.csv"
    f.write_text("\n".join(rows) + "\n")
    out = subprocess.run(
        [sys.executable, "-m", "noisevar", "imu", str(f), "--export", "kalibr", "--out",
         str(tmp_path / "cfg"), "--no-report"],
        capture_output=True, text=True,
    )  # fmt: skip
    assert out.returncode == 0, out.stderr
    assert "by the units the file declares" in out.stdout
    kalibr = next((tmp_path / "cfg").glob("*.yaml")).read_text()
    assert "gyroscope_noise_density" in kalibr and "update_rate:" in kalibr


def test_a_stamp_that_repeats_or_steps_back_keeps_the_rate(tmp_path: Path) -> None:
    """One duplicated or backward stamp (a mocap logger, a DataFlash line) threw the whole
    time axis away: no rate, so ``noisevar imu`` asked for --rate."""
    t = np.arange(600) * 0.005
    t[200] = t[199]  # repeats
    t[400] = t[398]  # steps back
    f = tmp_path / "imu.csv"
    f.write_text("time,gx\n" + "\n".join(f"{v:.3f},{(i * 7919) % 101}" for i, v in enumerate(t)))
    tab = load_table(f)
    assert tab.sample_period == pytest.approx(0.005)
    assert any("repeats or steps back at 2 of 599 steps (first at row 200)" in n for n in tab.notes)
    t[100:110] = t[99]  # many: the axis is not a clock
    f.write_text("time,gx\n" + "\n".join(f"{v:.3f},{(i * 7919) % 101}" for i, v in enumerate(t)))
    assert load_table(f).sample_period is None

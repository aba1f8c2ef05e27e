"""A time column whose name states its unit (``time_ns``, ``timestamp_us``, ``t [ms]``) is
read in that unit (real_audit3: a log exported with nanosecond stamps lost its rate, and a
``t [ms]`` column was taken as seconds, the rate 1000x too low, silently)."""

from __future__ import annotations

import json

import numpy as np
import pytest

import noisevar
from noisevar.cli import main
from noisevar.io import load_table


def _csv(name: str, scale: float, offset: int = 0) -> bytes:
    rng = np.random.default_rng(0)
    t = np.arange(400) * 0.01  # 100 Hz
    stamps = t.astype(str) if scale == 1.0 else (np.round(t / scale).astype(np.int64) + offset)
    z = rng.normal(size=t.size)
    rows = "\n".join(f"{s},{float(v)!r}" for s, v in zip(stamps, z, strict=True))
    return f"{name},value\n{rows}\n".encode()


@pytest.mark.parametrize(
    ("name", "scale", "offset"),
    [
        ("time_ns", 1e-9, 1_700_000_000_000_000_000),
        ("timestamp_us", 1e-6, 0),
        ("t [ms]", 1e-3, 0),
        ("TimeUS", 1e-6, 2_000_000),  # ArduPilot's field, as Mission Planner's CSV writes it
        ("Time_US_GPS_20190123_Flight2", 1e-6, 0),  # autoflpy's workbooks
    ],
)
def test_time_column_in_its_named_unit(name, scale, offset):
    tab = load_table(_csv(name, scale, offset), "a.csv")
    assert tab.time_column == name
    assert tab.sample_period == pytest.approx(0.01, rel=1e-9)
    assert any("its name" in n for n in tab.notes)


def test_allan_reads_the_rate_of_a_nanosecond_column(tmp_path, capsys):
    path = tmp_path / "ns.csv"
    path.write_bytes(_csv("time_ns", 1e-9, 1_700_000_000_000_000_000))
    code = main(["allan", str(path), "--column", "value", "--format", "json"])
    out, err = capsys.readouterr()
    assert code == 0, err
    assert json.loads(out)["rate"] == pytest.approx(100.0, rel=1e-9)


def test_seconds_are_unchanged():
    tab = load_table(_csv("time_s", 1.0), "b.csv")
    assert tab.sample_period == pytest.approx(0.01, rel=1e-9)
    assert not any("its name" in n for n in tab.notes)


def test_iso_times_with_a_zone_load_without_a_warning():
    """GPS tracks (GPX exports) stamp ``...Z`` or ``+02:00``: read in UTC, and numpy's
    timezone warning does not reach the user (main: a UserWarning on stderr)."""
    import warnings

    body = (
        b"time,ele\n2010-08-05T14:23:59Z,542.3\n2010-08-05T16:25:08+02:00,550.9\n"
        b"2010-08-05T14:26:08Z,551.2\n"
    )
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        tab = load_table(body, "track.csv")
    assert not caught
    np.testing.assert_array_equal(tab.time(), [0.0, 69.0, 129.0])


def test_npy_field_of_epoch_nanoseconds_is_the_time(tmp_path):
    """A structured ``.npy`` with ``time_ns`` int64 since the epoch (1.7e18, beyond 2**53):
    taken relative to its first value and read in ns (main refused it: 'subtract an
    offset first', the exception meant for time fields never matched a field's name)."""
    a = np.zeros(500, dtype=[("time_ns", "<i8"), ("gyro", "<f8")])
    a["time_ns"] = 1_700_000_000_000_000_000 + np.arange(500) * 2_500_000
    a["gyro"] = np.random.default_rng(0).normal(size=500)
    np.save(tmp_path / "s.npy", a)
    tab = load_table(tmp_path / "s.npy")
    assert tab.time_column == "time_ns"
    assert tab.sample_period == pytest.approx(0.0025, rel=1e-12)


@pytest.mark.parametrize("kind", ["parquet", "hdf5"])
@pytest.mark.parametrize(("name", "scale"), [("time_ns", 1e-9), ("timestamp_us", 1e-6)])
def test_log_tables_read_the_time_in_its_named_unit(tmp_path, kind, name, scale):
    """Parquet and HDF5 tables: ``time_ns`` was taken as seconds (the rate listed 4e-7 Hz
    for 400 Hz, the period refused) and ``timestamp_us`` was data."""
    from noisevar.io import log_topics

    n = 300
    stamps = np.arange(n, dtype=np.int64) * round(0.0025 / scale)
    if name == "time_ns":
        stamps += 1_700_000_000_000_000_000
    z = np.random.default_rng(0).normal(size=n)
    if kind == "parquet":
        import pyarrow as pa
        import pyarrow.parquet as pq

        path = tmp_path / "t.parquet"
        pq.write_table(pa.table({name: stamps, "gyro": z}), path)
    else:
        import h5py

        path = tmp_path / "t.h5"
        with h5py.File(path, "w") as f:
            f[f"imu/{name}"], f["imu/gyro"] = stamps, z
    (info,) = log_topics(path)
    assert info.rate == pytest.approx(400.0, rel=1e-9)
    tab = load_table(path, topic=info.name)
    assert tab.sample_period == pytest.approx(0.0025, rel=1e-9)
    assert list(tab.data_columns) == ["gyro"]


def test_date_times_with_empty_cells_are_the_time_column():
    """A GPS track whose first fixes have no time (gpxpy's korita-zbevnica.gpx): main refused
    the file with "'2010-10-03T09:36:30Z' is not a number"; now its time column has missing
    values, said, and the signal loads."""
    body = b"time,ele\n,733.6\n,735.5\n2010-10-03T09:36:30Z,728.3\n2010-10-03T09:36:31Z,729.0\n"
    tab = load_table(body, "track.csv")
    assert tab.time_column == "time" and tab.sample_period is None
    np.testing.assert_array_equal(tab.time()[2:], [0.0, 1.0])
    assert np.isnan(tab.time()[:2]).all()
    assert any("missing values" in n for n in tab.notes)


def test_a_run_per_column_pair_reads_its_units_and_one_clock(capsys, tmp_path):
    """PASCO Capstone's export: ``Time (s) Run #1, Position (m) Run #1, Time (s) Run #2, ...``:
    the units are read, and the second run's clock is no channel of ``--columns all``."""
    rng = np.random.default_rng(2)
    t = np.arange(400) * 0.05
    x = np.sin(t) + rng.normal(0, 0.002, t.size)
    rows = "\n".join(f"{a:.2f},{b:.4f},{a:.2f},{b + 0.1:.4f}" for a, b in zip(t, x, strict=True))
    path = tmp_path / "pasco.csv"
    path.write_text(
        f"Time (s) Run #1,Position (m) Run #1,Time (s) Run #2,Position (m) Run #2\n{rows}\n"
    )
    table = load_table(path)
    assert table.units["Position (m) Run #2"] == "m" and table.sample_period == pytest.approx(0.05)
    assert main(["estimate", str(path), "--columns", "all", "--format", "json"]) == 0
    got = json.loads(capsys.readouterr().out)
    rows = got if isinstance(got, list) else got["channels"]
    assert [r["column"] for r in rows] == ["Position (m) Run #1", "Position (m) Run #2"]
    assert {r["unit"] for r in rows} == {"m"}


def _runs(tmp_path, unit: str = "s", scale: float = 1.0):
    """PASCO-style runs: run 1 at 20 Hz (400 rows), run 2 at 50 Hz (250 rows, then blank)."""
    rng = np.random.default_rng(2)
    t1, t2 = np.arange(400) * 0.05, np.arange(250) * 0.02
    x1 = np.sin(t1) + rng.normal(0, 0.002, t1.size)
    x2 = np.cos(t2) + rng.normal(0, 0.004, t2.size)
    lines = [f"Time ({unit}) Run #1,Position (m) Run #1,Time ({unit}) Run #2,Position (m) Run #2"]
    for i in range(400):
        two = f"{t2[i] * scale:.6g},{x2[i]:.5f}" if i < 250 else ","
        lines.append(f"{t1[i] * scale:.6g},{x1[i]:.5f},{two}")
    path = tmp_path / "runs.csv"
    path.write_text("\n".join(lines) + "\n")
    alone = tmp_path / "run2.csv"
    alone.write_text(
        "\n".join([f"Time ({unit}),Position (m)"] + [f"{t2[i] * scale:.6g},{x2[i]:.5f}"
                                                      for i in range(250)]) + "\n"
    )  # fmt: skip
    return path, alone


@pytest.mark.parametrize(("unit", "scale"), [("s", 1.0), ("ms", 1e3)])
def test_each_run_reads_its_own_clock_and_rows(tmp_path, unit, scale):
    """PASCO Capstone's runs of other lengths and rates: run 2 is its 250 rows on its own
    clock, as the same run saved alone (before: run 1's clock, and its blank rows made it an
    error row of ``--columns all``; ``Time (ms) Run #1`` was read in seconds)."""
    from noisevar.io import channel_record

    path, alone = _runs(tmp_path, unit, scale)
    table, single = load_table(path), load_table(alone)
    z, t = channel_record(table, "Position (m) Run #2")
    z1, t1 = channel_record(single, "Position (m)")
    np.testing.assert_array_equal(z, z1)
    np.testing.assert_allclose(t, t1, rtol=1e-12)
    assert table.period_of("Position (m) Run #2") == pytest.approx(0.02, rel=1e-12)
    assert table.period_of("Position (m) Run #1") == pytest.approx(0.05, rel=1e-12)
    a = noisevar.estimate(z, t=t)
    assert a.variance == noisevar.estimate(z1, t=t1).variance


def test_runs_through_the_cli(capsys, tmp_path):
    path, alone = _runs(tmp_path)
    assert main(["estimate", str(path), "--columns", "all", "--format", "json"]) == 0
    got = json.loads(capsys.readouterr().out)
    rows = got if isinstance(got, list) else got["channels"]
    assert [r["n_total"] for r in rows] == [400, 250], rows
    assert main(["estimate", str(alone), "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["variance"] == rows[1]["variance"]
    assert main(["allan", str(path), "--column", "Position (m) Run #2", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["rate"] == 50.0
    assert main(["allan", str(path), "--format", "json"]) == 0  # the first run's by default
    assert json.loads(capsys.readouterr().out)["rate"] == 20.0
    out = tmp_path / "batch.csv"
    assert main(["batch", str(path), "--columns", "all", "--out", str(out), "--quiet"]) == 0
    import pandas as pd

    assert list(pd.read_csv(out)["sample_rate_hz"]) == [20.0, 50.0]


def test_runs_on_the_dashboard(tmp_path):
    from dashboard.state import make_signal

    path, _ = _runs(tmp_path)
    table = load_table(path)
    one = make_signal(table, None, table.sample_period, "upload", None)
    two = make_signal(table, "Position (m) Run #2", table.period_of("Position (m) Run #2"),
                      "upload", None)  # fmt: skip
    assert one.sample_period == pytest.approx(0.05) and two.sample_period == pytest.approx(0.02)
    assert two.z.size == 250 and two.times is not None and two.times.size == 250

"""noisevar.io: CSV/TSV/npy/NMEA loading, every failure one clear NoisevarError."""

from __future__ import annotations

import io
from pathlib import Path

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.io import (
    content_digest,
    geodetic_to_enu,
    load_table,
    pick_column,
    signal_summary,
    table_from_arrays,
)

ROOT = Path(__file__).resolve().parents[1]


def _nmea(body: str) -> str:
    c = 0
    for ch in body:
        c ^= ord(ch)
    return f"${body}*{c:02X}"


def _nmea_log(n: int = 20, lat0: float = 48.0, lon0: float = 11.0) -> list[str]:
    lines = []
    for k in range(n):
        lat, lon = lat0 + k * 1e-5, lon0 + k * 2e-5
        d = int(lat)
        la = f"{d:02d}{(lat - d) * 60:07.4f}"
        d = int(lon)
        lo = f"{d:03d}{(lon - d) * 60:07.4f}"
        hh = f"1200{k:02d}.00"
        lines.append(_nmea(f"GPGGA,{hh},{la},N,{lo},E,1,08,0.9,545.4,M,46.9,M,,"))
        lines.append(_nmea(f"GPRMC,{hh},A,{la},N,{lo},E,10.0,84.4,230394,003.1,W"))
        lines.append(_nmea("GPGSA,A,3,04,05,,09,12,,,24,,,,,2.5,1.3,2.1"))
    return lines


def test_csv_with_header_and_time_column():
    tab = load_table(b"t,x,y\n0,1,2\n0.5,2,3\n1.0,3,4\n", "a.csv")
    assert tab.kind == "csv"
    assert tab.time_column == "t"
    assert tab.sample_period == 0.5
    assert tab.data_columns == ["x", "y"]
    np.testing.assert_array_equal(pick_column(tab), [1, 2, 3])
    np.testing.assert_array_equal(pick_column(tab, "y"), [2, 3, 4])
    np.testing.assert_array_equal(pick_column(tab, 1), [2, 3, 4])


@pytest.mark.parametrize(
    ("times", "rate"),
    [
        (np.arange(2000) / 120, 120.0),  # full float digits
        (np.round(np.arange(2000) / 120, 6), 120.0),  # six decimals: 120.0048 is noise
        (np.arange(20) * 3600.0, 1 / 3600),  # a round period stays round
    ],
)
def test_rate_from_time_column_keeps_only_supported_digits(times, rate):
    body = "t,x\n" + "".join(f"{float(t)!r},{i % 7}\n" for i, t in enumerate(times))
    tab = load_table(body.encode(), "a.csv")
    assert 1.0 / tab.sample_period == rate  # not 120.00000000004799


def test_headerless_whitespace_and_tsv_and_comments():
    tab = load_table(b"# a comment\n1 2\n3 4\n\n5 6\n", "a.txt")
    assert tab.columns.keys() == {"col0", "col1"}
    assert tab.n_rows == 3
    tab = load_table(b"x\ty\n1\t2\n3\t4\n", "a.tsv")
    assert tab.kind == "tsv" and tab.n_rows == 2


def test_iso_time_column_and_non_uniform_note():
    tab = load_table(
        b"time,x\n2024-01-01T00:00:00,1\n2024-01-01T00:00:01,2\n2024-01-01T00:00:03,4\n", "t.csv"
    )
    assert tab.time_column == "time"
    np.testing.assert_allclose(tab.columns["time"], [0, 1, 3])
    assert any("not uniform" in n for n in tab.notes)


@pytest.mark.parametrize(
    ("content", "name", "fragment"),
    [
        (b"", "empty.csv", "empty"),
        (b"x,y\n", "hdr.csv", "no data rows"),
        (b"x,y\n1,2\n3,abc\n", "bad.csv", "line 3, column 'y': 'abc' is not a number"),
        (b"x,y\n1,2\n3,4,5\n", "ragged.csv", "line 3 has 3 fields"),
        (bytes(range(256)) * 4, "bin.csv", "binary"),
        (b"\x89PNG\r\n\x1a\n\x00\x00\x00", "picture.csv", "binary"),
        (b"not a numpy file", "x.npy", "not a valid .npy"),
        (b"x\nnan\n\n", "allnan.csv", "no numbers"),
    ],
)
def test_bad_files_raise_one_clear_error(content, name, fragment):
    with pytest.raises(NoisevarError, match=None) as info:
        load_table(content, name)
    assert fragment in str(info.value)
    assert "\n" not in str(info.value)


def test_nan_cells_are_refused_by_pick_column_unless_dropped():
    tab = load_table(b"x,y\n1,2\n3,\n4,nan\n", "n.csv")
    with pytest.raises(NoisevarError, match="2 empty or NaN values"):
        pick_column(tab, "y")
    np.testing.assert_array_equal(pick_column(tab, "y", drop_nonfinite=True), [2.0])
    with pytest.raises(NoisevarError, match="no column 'z'"):
        pick_column(tab, "z")
    with pytest.raises(NoisevarError, match="out of range"):
        pick_column(tab, 5)


def test_size_limit():
    with pytest.raises(NoisevarError, match="over the"):
        load_table(b"x\n" + b"1\n" * 1000, "big.csv", max_bytes=100)


def test_npy_shapes_and_pickle_refused():
    buf = io.BytesIO()
    np.save(buf, np.arange(10.0))
    tab = load_table(buf.getvalue(), "a.npy")
    assert tab.kind == "npy" and tab.data_columns == ["value"]
    buf = io.BytesIO()
    np.save(buf, np.ones((50, 3)))
    assert load_table(buf.getvalue(), "b.npy").data_columns == ["col0", "col1", "col2"]
    buf = io.BytesIO()
    np.save(buf, np.ones((2, 50)))  # rows of signals: transposed with a note
    tab = load_table(buf.getvalue(), "c.npy")
    assert tab.n_rows == 50 and tab.notes
    rec = np.zeros(5, dtype=[("time", float), ("speed", float)])
    rec["time"] = np.arange(5) * 0.1
    buf = io.BytesIO()
    np.save(buf, rec)
    tab = load_table(buf.getvalue(), "d.npy")
    assert tab.time_column == "time" and tab.sample_period == pytest.approx(0.1)
    buf = io.BytesIO()
    np.save(buf, np.array([{"a": 1}], dtype=object), allow_pickle=True)
    with pytest.raises(NoisevarError, match="refused for safety"):
        load_table(buf.getvalue(), "obj.npy")
    buf = io.BytesIO()
    np.save(buf, np.array(["a", "b"]))
    with pytest.raises(NoisevarError, match="not real numbers"):
        load_table(buf.getvalue(), "s.npy")


def test_nmea_positions_speed_course():
    text = "\n".join(_nmea_log(20)).encode()
    tab = load_table(text, "track.nmea")
    assert tab.kind == "nmea"
    assert tab.time_column == "time" and tab.sample_period == 1.0
    assert set(tab.data_columns) == {"east_m", "north_m", "up_m", "speed_mps", "course_deg"}
    # 2e-5 degrees of longitude at 48 N per second, 1e-5 of latitude
    east_step = np.diff(tab.columns["east_m"])
    north_step = np.diff(tab.columns["north_m"])
    np.testing.assert_allclose(
        east_step, 2e-5 * np.pi / 180 * 6378137 * np.cos(np.radians(48)), rtol=0.01
    )
    np.testing.assert_allclose(north_step, 1e-5 * np.pi / 180 * 6367000, rtol=0.01)
    np.testing.assert_allclose(tab.columns["speed_mps"], 10.0 * 1852 / 3600)
    # sniffed from content even with a .txt name
    assert load_table(text, "log.txt").kind == "nmea"


def test_nmea_checksum_error_names_the_line():
    lines = _nmea_log(10)
    lines[4] = lines[4][:-2] + ("00" if lines[4][-2:] != "00" else "11")
    with pytest.raises(NoisevarError, match="checksum error at line 5"):
        load_table("\n".join(lines).encode(), "bad.nmea")


def test_nmea_without_fixes():
    with pytest.raises(NoisevarError, match="no GGA or RMC"):
        load_table(_nmea("GPGSA,A,3,04,05,,09,12,,,24,,,,,2.5,1.3,2.1").encode(), "x.nmea")


def test_enu_of_first_point_is_origin():
    enu = geodetic_to_enu([40.0, 40.0], [116.0, 116.001], [50.0, 50.0])
    np.testing.assert_allclose(enu[0], 0.0)
    assert enu[1, 0] == pytest.approx(85.4, abs=0.5) and abs(enu[1, 1]) < 0.01


def test_sample_data_files_all_load():
    files = [
        p
        for p in (ROOT / "sample_data").glob("*")
        if p.suffix in (".csv", ".tsv", ".npy", ".nmea", ".txt")
    ]
    for p in files:
        tab = load_table(p)
        assert tab.n_rows > 100
        z = pick_column(tab)
        assert np.all(np.isfinite(z))


def test_summary_digest_and_arrays():
    s = signal_summary(np.array([1.0, 2.0, 3.0]), 0.5)
    assert s["n"] == 3 and s["duration_s"] == 1.0 and s["mean"] == 2.0
    assert content_digest(np.arange(3.0)) == content_digest(np.arange(3.0))
    assert content_digest(np.arange(3.0)) != content_digest(np.arange(1.0, 4.0))
    tab = table_from_arrays("g", {"a": [1, 2], "b": [3, 4]}, 0.1)
    assert tab.to_csv().splitlines()[0] == "a,b"
    with pytest.raises(NoisevarError, match="different lengths"):
        table_from_arrays("g", {"a": [1, 2], "b": [3]})
    with pytest.raises(NoisevarError, match="no such file"):
        load_table(ROOT / "does-not-exist.csv")


def test_one_million_row_csv_is_fast_enough():
    import time

    z = np.random.default_rng(0).normal(size=1_000_000)
    text = ("t,x\n" + "\n".join(f"{i * 0.01:.2f},{v:.5f}" for i, v in enumerate(z))).encode()
    t0 = time.perf_counter()
    tab = load_table(text, "big.csv")
    assert tab.n_rows == 1_000_000
    assert time.perf_counter() - t0 < 10.0


def test_loaded_columns_are_writable_for_every_method():
    tab = load_table(
        b"t,x\n" + b"".join(f"{i},{(i * 7919) % 13}\n".encode() for i in range(300)), "w.csv"
    )
    z = pick_column(tab, "x")
    assert z.flags.writeable
    import noisevar

    noisevar.estimate(z, method="wavelet-mad")


def test_a_one_column_file_whose_name_has_spaces(tmp_path):
    """``clock [ns]`` over one number per row: one column named so, with its unit (it was
    split into two columns at the space, the second all empty: refused)."""
    from noisevar.io import load_table

    path = tmp_path / "clock.csv"
    path.write_text("clock offset [ns]\n" + "\n".join(str(0.5 * i) for i in range(200)) + "\n")
    table = load_table(str(path), "clock.csv")
    assert table.data_columns == ["clock offset [ns]"] and table.units == {
        "clock offset [ns]": "ns"
    }
    path.write_text("a b\n1 2\n3 4\n")  # whitespace-separated columns stay columns
    assert load_table(str(path), "ws.txt").data_columns == ["a", "b"]

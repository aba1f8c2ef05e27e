"""Hostile files (issue 15, and issue 16's decimal comma): caps, formats, precision, escapes."""

from __future__ import annotations

import io
import time

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.io import drop_nonfinite_rows, echo, load_table, pick_column
from noisevar.io.text import MAX_COLUMNS, _unique_names


def _nmea(body: str) -> str:
    c = 0
    for ch in body:
        c ^= ord(ch)
    return f"${body}*{c:02X}"


def _gga(hms: str, lat: str) -> str:
    return _nmea(f"GPGGA,{hms},{lat},N,01131.000,E,1,08,0.9,545.4,M,46.9,M,,")


def _npy(arr: np.ndarray) -> bytes:
    buf = io.BytesIO()
    np.save(buf, arr)
    return buf.getvalue()


def test_a_file_over_the_cap_is_refused_before_reading(tmp_path):
    big = tmp_path / "big.csv"
    with big.open("wb") as fh:
        fh.truncate(3 << 30)  # sparse: nothing is written
    t0 = time.perf_counter()
    with pytest.raises(NoisevarError, match="over the"):
        load_table(big)
    assert time.perf_counter() - t0 < 5  # generous: the real target is measured in benchmarks


def test_bytes_over_the_cap_are_refused():
    with pytest.raises(NoisevarError, match="over the 0 MB limit"):
        load_table(b"x\n1\n2\n", "a.csv", max_bytes=3)


def test_npy_from_a_path_is_memory_mapped_and_equal(tmp_path):
    z = np.random.default_rng(0).normal(size=5000)
    p = tmp_path / "z.npy"
    np.save(p, z)
    tab = load_table(p)
    assert np.array_equal(pick_column(tab), z)


def test_a_text_table_on_disk_reads_like_its_bytes(tmp_path):
    text = "t,x\n" + "\n".join(f"{i * 0.1:.1f},{np.sin(i):.6f}" for i in range(3000))
    p = tmp_path / "a.csv"
    p.write_text(text)
    a, b = load_table(p), load_table(text.encode(), "a.csv")
    assert a.sample_period == b.sample_period == 0.1
    assert np.array_equal(a.columns["x"], b.columns["x"])


def test_too_many_columns_is_refused_fast():
    header = ",".join(f"c{i}" for i in range(200_000))
    t0 = time.perf_counter()
    with pytest.raises(NoisevarError, match="columns, over the limit"):
        load_table((header + "\n" + header.replace("c", "1") + "\n").encode(), "w.csv")
    assert time.perf_counter() - t0 < 10


def test_unique_names_is_linear_and_suffixes_repeats():
    assert _unique_names(["a", "a", "a_2", "", "a"]) == ["a", "a_2", "a_2_2", "col3", "a_3"]
    t0 = time.perf_counter()
    names = _unique_names(["x"] * 200_000)
    assert len(set(names)) == 200_000
    assert time.perf_counter() - t0 < 5


def test_unquoted_thousands_separators_keep_the_fraction():
    text = "price\n4,867.69\n4,901.10\n12,345.5\n" + "1,000.25\n" * 10
    tab = load_table(text.encode(), "p.csv")
    assert tab.columns["price"][:3].tolist() == [4867.69, 4901.10, 12345.5]


def test_thousands_in_a_comma_table_is_refused_with_a_hint():
    with pytest.raises(NoisevarError, match="thousands separators"):
        load_table(b"a,b\n1,2\n4,867.69,3\n", "p.csv")


def test_decimal_comma_with_semicolons_is_read():
    rows = "\n".join(f"{i};{np.cos(i):.5f}".replace(".", ",") for i in range(200))
    tab = load_table(("t;x\n" + rows).encode(), "eu.csv")
    assert tab.columns["x"][1] == pytest.approx(round(np.cos(1), 5))
    assert tab.sample_period == 1.0
    assert any("decimal comma" in n for n in tab.notes)


def test_decimal_comma_with_dot_thousands_is_read():
    tab = load_table(b"x;y\n1.234,5;1\n2.000,25;2\n3,5;3\n", "eu.csv")
    assert tab.columns["x"].tolist() == [1234.5, 2000.25, 3.5]


def test_plain_semicolon_table_with_decimal_points_is_unchanged():
    tab = load_table(b"a;b\n1.5;2\n2.5;3\n", "s.csv")
    assert tab.columns["a"].tolist() == [1.5, 2.5]


@pytest.mark.parametrize(
    "values",
    [
        [2**63 - 1 - 3 * i for i in range(50)],
        [2**64 - 1 - 3 * i for i in range(50)],
        [2**64 + 3 * i for i in range(50)],
        [-(2**63) + 3 * i for i in range(50)],
    ],
)
def test_integers_beyond_float_precision_are_refused(values):
    text = "x\n" + "\n".join(map(str, values))
    with pytest.raises(NoisevarError, match="precision lost"):
        load_table(text.encode(), "i.csv")


def test_nanosecond_time_column_is_taken_relative_exactly():
    text = "time,x\n" + "\n".join(
        f"{1_700_000_000_000_000_000 + 1000 * i},{i % 7}" for i in range(100)
    )
    tab = load_table(text.encode(), "t.csv")
    # nanoseconds since 1970 (its values say so): offsets from the first, in seconds
    np.testing.assert_allclose(tab.columns["time"][:3], [0.0, 1e-6, 2e-6], rtol=1e-12)
    assert tab.sample_period == pytest.approx(1e-6, rel=1e-12)


def test_time_step_outside_the_period_range_is_not_the_sample_period():
    text = "time,x\n" + "\n".join(
        f"{1_700_000_000_000 + 3_600_000 * i},{i % 7}" for i in range(100)
    )
    tab = load_table(text.encode(), "ms.csv")  # milliseconds since 1970: hourly
    assert tab.sample_period == pytest.approx(3600.0)
    text = "time,x\n" + "\n".join(f"{3_600_000 * i},{i % 7}" for i in range(100))
    tab = load_table(text.encode(), "ms.csv")  # the same from 0: no unit to read off it
    assert tab.sample_period is None
    assert any("another unit" in n for n in tab.notes)
    text = "time,x\n" + "\n".join(f"{i * 1e-12!r},{i % 7}" for i in range(100))
    assert load_table(text.encode(), "ps.csv").sample_period is None


def test_complex_fields_and_arrays_are_refused():
    s = np.zeros(100, dtype=[("t", "f8"), ("x", "c16")])
    with pytest.raises(NoisevarError, match="complex"):
        load_table(_npy(s), "c.npy")
    with pytest.raises(NoisevarError, match="complex"):
        load_table(_npy(np.zeros(100, complex)), "c.npy")
    with pytest.raises(NoisevarError, match="precision lost"):
        load_table(_npy(np.arange(100, dtype=np.int64) + 2**60), "i.npy")


def test_nmea_invalid_time_and_impossible_latitude_are_skipped_with_a_note():
    fixes = [_gga(f"1200{s:02d}.00", f"4807.{s:03d}") for s in range(10)]
    text = "\n".join(
        [*fixes[:3], _gga("999999.00", "4807.038"), _gga("120030.00", "9500.000"), *fixes[3:]]
    )
    tab = load_table(text.encode(), "x.nmea")
    assert tab.n_rows == 10
    notes = " ".join(tab.notes)
    assert "2 lines skipped" in notes and "invalid time" in notes


def test_control_characters_and_huge_fields_are_escaped_and_cut():
    with pytest.raises(NoisevarError) as info:
        load_table(b"x\n1\n\x1b[31mred" + b"9" * 5_000_000 + b"\n", "a.csv")
    msg = str(info.value)
    assert "\x1b" not in msg and "\\x1b" in msg and len(msg) < 400
    assert echo("a\x1b[0m") == "a\\x1b[0m"


def test_a_bad_column_name_is_escaped():
    tab = load_table(b"a\x1b[2J,b\n1,2\n3,4\n5,6\n", "a.csv")
    with pytest.raises(NoisevarError) as info:
        pick_column(tab, "\x1b[31m" + "z" * 10_000)
    assert "\x1b" not in str(info.value) and len(str(info.value)) < 400
    with pytest.raises(NoisevarError):
        pick_column(tab, "9" * 5000)


def test_drop_nonfinite_rows_keeps_rows_aligned():
    tab = load_table(b"t,x,y\n0,1,\n1,2,5\n2,nan,6\n3,4,7\n", "n.csv")
    out = drop_nonfinite_rows(tab)
    assert out.columns["t"].tolist() == [1.0, 3.0]
    assert out.columns["x"].tolist() == [2.0, 4.0]
    assert "dropped 2 rows" in out.notes[-1]
    assert MAX_COLUMNS >= 100


def test_a_header_shorter_than_every_row_is_said_so():
    """NREL MIDC's logger CSV in pvlib's tests (real_audit5): 20 names, 26 fields on every
    row (the logger added channels and kept its header). The error blamed thousands
    separators; it says the header is short."""
    rows = "".join(",".join(str(i + k) for k in range(6)) + "\n" for i in range(50))
    body = ("a,b,c,d\n" + rows).encode()
    with pytest.raises(NoisevarError, match=r"the header \(line 1\) names 4 columns but every "
                       r"row under it has 6 fields: name every column"):  # fmt: skip
        load_table(body, "short_header.csv")


def test_a_missing_value_code_is_noted():
    """NREL MIDC's logger writes -7999 for a missing value (real_audit5: a pyranometer's
    body temperature, 87 % of the day): read as numbers, R was 2.9e6 (deg C)² with a tight
    interval and no word about it. The loader notes such a value (many samples at one
    extreme, far outside every other value); a few-level signal is not one."""
    rng = np.random.default_rng(9)
    temp = 20 + np.cumsum(rng.normal(0, 0.05, 1000))
    temp[rng.random(1000) < 0.3] = -7999.0
    switch = np.where(rng.random(1000) < 0.5, 0.0, 1.0)  # two levels: no code
    cells = zip(temp, switch, rng.normal(size=1000), strict=True)
    body = "temp [deg C],switch,z\n" + "".join(f"{a:.3f},{b:.0f},{c:.4f}\n" for a, b, c in cells)
    notes = load_table(body.encode(), "logger.csv").notes
    coded = [n for n in notes if "missing-value code" in n]
    assert len(coded) == 1 and coded[0].startswith("column 'temp [deg C]': ")
    assert "are -7999" in coded[0]

"""Real-record audit 21's loader fixes (benchmarks/real_audit21.py): a column's missing-value
mark, and a headerless file that stacks several instruments' series."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest

from noisevar import NoisevarError
from noisevar.io import load_table


def test_a_repeated_mark_for_no_value_is_read_as_missing(tmp_path: Path) -> None:
    """radvel's ``164922_fixed.txt``: ``\\nodata`` in ``svalue`` until the second
    spectrograph's rows; the whole file was refused, even for another column."""
    rng = np.random.default_rng(21)
    t = np.cumsum(rng.uniform(0.5, 3.0, 200))
    v = rng.normal(0.0, 2.0, 200)
    s = [r"\nodata"] * 40 + [f"{x:.4f}" for x in rng.uniform(0.1, 0.2, 160)]
    path = tmp_path / "rv.txt"
    rows = (f"{a:.6f} {b:.6f} 1.1 k {c}" for a, b, c in zip(t, v, s, strict=True))
    path.write_text("time mnvel errvel tel svalue\n" + "\n".join(rows) + "\n")
    table = load_table(path)
    assert np.array_equal(table.columns["mnvel"], np.round(v, 6))
    assert np.isnan(table.columns["svalue"][:40]).all()
    assert np.isfinite(table.columns["svalue"][40:]).all()
    assert any("in 40 cells read as missing" in n for n in table.notes)
    for cells in (["oops"], ["oops", "oops2"], ["12:00", "12:00"]):  # no mark: refused
        rows = [f"{i},{i % 7}.5" for i in range(30)]
        for k, c in enumerate(cells):
            rows[3 + 5 * k] = f"{3 + 5 * k},{c}"
        path.write_text("n,x\n" + "\n".join(rows) + "\n")
        with pytest.raises(NoisevarError, match="is not a number"):
            load_table(path)


def test_a_headerless_file_of_stacked_instruments_is_refused(tmp_path: Path) -> None:
    """radvel's ``rvs_toi141.dat``: Julian dates, a velocity, its error, the spectrograph
    (FEROS, CORALIE, HARPS one after the other), no header; its dates were the signal."""
    rng = np.random.default_rng(141)
    lines = []
    for inst, n in (("FEROS", 120), ("CORALIE", 30), ("HARPS", 60)):
        t = 2458378.5 + np.cumsum(rng.exponential(0.7, n))
        lines += [f"{a:.7f} {b:.2f} 3.00 {inst}" for a, b in zip(t, rng.normal(0, 5, n),
                                                                  strict=True)]  # fmt: skip
    path = tmp_path / "rvs.dat"
    path.write_text("\n".join(lines) + "\n")
    with pytest.raises(NoisevarError, match=r"stacks 3 series, one per value of column 'col3'"):
        load_table(path)
    one = tmp_path / "feros.dat"
    one.write_text("\n".join(lines[:120]) + "\n")  # one spectrograph's rows: read
    assert load_table(one).first_signal == "col1"


def test_whitespace_columns_with_a_comma_inside_a_field_are_not_csv(tmp_path: Path) -> None:
    """ISMN's soil-moisture ``.stm`` files: a station line, then ``date time value flag
    flag`` rows whose flag is sometimes ``D02,D04``; read as CSV and refused."""
    rng = np.random.default_rng(4)
    v = 0.15 + np.cumsum(rng.normal(0, 1e-3, 300))
    flags = ["D02,D04" if 20 <= i < 40 else "G" for i in range(300)]
    rows = (f"2007/01/{1 + i // 24:02d} {i % 24:02d}:00   {x:.4f} {f} M "
            for i, (x, f) in enumerate(zip(v, flags, strict=True)))  # fmt: skip
    path = tmp_path / "SCAN_SCAN_AdamsRanch#1_sm.stm"
    head = "SCAN       SCAN   Adams_Ranch_#1    34.25000  -105.41700 1882.14    0.05    0.05 x \r"
    path.write_text(head + "\r".join(rows) + "\r")
    table = load_table(path)
    assert table.sample_period == pytest.approx(3600.0)
    assert np.allclose(table.columns[table.first_signal], np.round(v, 4))
    csv = tmp_path / "c.csv"  # a CSV whose rows end in a comma now and then stays a CSV
    csv.write_text("a, b\n" + "".join(f"{i}, {i % 5}{',' * (i % 3 == 0)}\n" for i in range(40)))
    assert load_table(csv).n_rows == 40


def test_a_slocum_gliders_binary_files_are_named(tmp_path: Path) -> None:
    """dbdreader's test data (an ocean glider's flight and science files, an ASCII header
    then binary) were refused as "a binary file" with no way out."""
    head = b"dbd_label: DBD(dinkum_binary_data)file\nencoding_ver: 5\n"
    for suffix in ("dbd", "EBD", "tcd"):
        path = tmp_path / f"amadeus-2014-204-05-000.{suffix}"
        path.write_bytes(head + bytes(range(256)) * 8)
        with pytest.raises(NoisevarError, match=r"Slocum glider.*dbdreader"):
            load_table(path)


def test_a_file_with_no_data_rows_says_what_to_give(tmp_path: Path) -> None:
    """ISMN's ``mal_formed_file.txt`` ("No good data here"): refused without a way out."""
    path = tmp_path / "mal_formed_file.txt"
    path.write_text("No good data here\n")
    with pytest.raises(NoisevarError, match="no data rows: give a table with one row of numbers"):
        load_table(path)


def test_a_word_in_a_column_of_numbers_says_what_to_do(tmp_path: Path) -> None:
    """ISMN's ``static_variables.csv`` (one row a soil or climate property, the Köppen class
    ``Cfa`` among the values) was refused with no way out."""
    path = tmp_path / "static_variables.csv"
    rows = [f"clay fraction;% weight;{d:.2f};{23 + d:.2f}" for d in np.linspace(0, 1, 12)]
    path.write_text("quantity_name;unit;depth;value\n" + "\n".join(rows)
                    + "\nclimate classification;;;Cfa\n")  # fmt: skip
    with pytest.raises(NoisevarError, match=r"'Cfa' is not a number .*give a table of samples"):
        load_table(path)

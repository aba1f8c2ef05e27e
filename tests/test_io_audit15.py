"""Files of the fifteenth real-record audit (benchmarks/real_audit15.py) as users have them:
Météo-France's daily climate files (tslearn's sdist) date their rows ``AAAAMMJJ``
(``20250101``), as KNMI's ``YYYYMMDD`` and ECA&D's ``DATE`` do. Read as a number, the date
was a measured column: the record had no time, and the department's file, its stations
stacked one after the other, was read as one series (R over the joins of 18 stations)."""

import numpy as np
import pandas as pd
import pytest

from noisevar.cli import main
from noisevar.io import load_table


def _daily(n: int, seed: int, start: str = "2024-12-20", name: str = "AAAAMMJJ") -> pd.DataFrame:
    """A station's daily rows: its id and name, its date as digits, a temperature on 0.1."""
    rng = np.random.default_rng(seed)
    days = pd.date_range(start, periods=n, freq="D")
    return pd.DataFrame({
        "NUM_POSTE": 35281001, "NOM_USUEL": "RENNES", name: days.strftime("%Y%m%d").astype(int),
        "TM": np.round(10.0 + np.cumsum(rng.normal(0.0, 0.3, n)) + rng.normal(0.0, 1.0, n), 1),
    })  # fmt: skip


@pytest.mark.parametrize("name", ["AAAAMMJJ", "YYYYMMDD", "DATE"])
def test_a_date_written_as_digits_is_the_time_column(tmp_path, name):
    path = tmp_path / "station.csv"
    _daily(400, 1, name=name).to_csv(path, sep=";", index=False)
    table = load_table(path)
    assert table.time_column == name  # the month's and the year's ends are one day too
    assert table.sample_period == pytest.approx(86400.0)
    assert name not in table.signals
    assert not any("not uniform" in n or "gap" in n for n in table.notes)
    # eight-digit counts in a column of no date name stay numbers
    counts = pd.DataFrame({"count": 20250101 + np.arange(100) * 37, "x": np.arange(100.0)})
    counts.to_csv(tmp_path / "counts.csv", index=False)
    assert load_table(tmp_path / "counts.csv").time_column is None


def test_stations_stacked_by_their_digit_dates_are_refused(tmp_path, capsys):
    a, b = _daily(300, 1), _daily(300, 2)
    b["NUM_POSTE"], b["NOM_USUEL"] = 35228001, "DINARD"
    path = tmp_path / "department.csv"
    pd.concat([a, b]).to_csv(path, sep=";", index=False)
    assert main(["estimate", str(path), "--column", "TM"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "stacks 2 series" in err and "NOM_USUEL" in err


def test_a_digit_date_that_is_no_day_is_said_in_one_line(tmp_path, capsys):
    df = _daily(100, 3)
    df.loc[50, "AAAAMMJJ"] = 20250132
    path = tmp_path / "station.csv"
    df.to_csv(path, sep=";", index=False)
    assert main(["estimate", str(path), "--column", "TM"]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "row 51" in err and "20250132" in err


def test_an_arff_file_is_refused_naming_it(tmp_path, capsys):
    """tslearn's UCR copies as ARFF (``@Relation``, an ``@attribute`` per value, one series
    a row after ``@data``) were refused as a Monash ``.tsf`` file."""
    rng = np.random.default_rng(5)
    head = ["%a comment", "@Relation Test", *(f"@attribute att{i} numeric" for i in range(20)),
            "@attribute target {1,-1}", "@data"]  # fmt: skip
    rows = [",".join(f"{v:.4f}" for v in rng.normal(size=20)) + ",1" for _ in range(30)]
    path = tmp_path / "Test_TEST.arff"
    path.write_text("\n".join([*head, *rows]) + "\n")
    assert main(["estimate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and "ARFF file" in err and ".tsf" not in err
    assert "column of a CSV file" in err


def test_a_series_a_line_is_said(tmp_path):
    """The UCR archive's text rows (a class, then one smooth series a line; tslearn's
    Lightning2 and GunPoint) were read down a column, one instant of every case, unsaid."""
    rng = np.random.default_rng(6)
    n, width = 40, 120
    phase = rng.uniform(0, 2 * np.pi, (n, 1))
    series = np.sin(np.linspace(0, 3, width) + phase) + rng.normal(0, 0.01, (n, width))
    rows = np.c_[rng.choice([-1.0, 1.0], n), series]
    path = tmp_path / "Cases_TEST.txt"
    np.savetxt(path, rows, fmt="%.7e")
    assert any("one series a line" in note for note in load_table(path).notes)
    # sensors side by side (few columns, many lines) step little along a line too: no note
    common = np.cumsum(rng.normal(0, 1, (500, 1)), axis=0)
    side = tmp_path / "sensors.txt"
    np.savetxt(side, common + rng.normal(0, 0.05, (500, 6)), fmt="%.5f")
    assert not any("one series a line" in note for note in load_table(side).notes)


def test_a_negative_digit_date_is_said_in_one_line() -> None:
    """'-20250101' in a DATE column raised an IndexError traceback (fuzzed: 3 of 300 files)."""
    from noisevar.errors import NoisevarError

    text = "DATE,TM\n20250101,-0.9\n-20250101,0.8\n20250103,-1.2\n20250104,-1.6\n"
    with pytest.raises(NoisevarError, match="data row 2 holds '-20250101'"):
        load_table(text.encode(), "f.csv")

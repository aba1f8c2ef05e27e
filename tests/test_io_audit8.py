"""Files of the eighth real-record audit (benchmarks/real_audit8.py) as users have them: a
date column named with its zone (Sheffield Solar's ``datetime_gmt``) was left out as text;
monthly dates (vega_datasets' stocks) were refused as the sample period ("is it in another
unit?") and hourly or daily dates said they might count microseconds; sktime's ``.ts`` files
were refused blaming thousands separators; a file stacking several series (the long format)
was answered as one record."""

import numpy as np
import pandas as pd
import pytest

from noisevar import NoisevarError
from noisevar.cli import main
from noisevar.io import load_table


def _dated(path, dates, seed: int = 8) -> np.ndarray:
    z = np.round(np.random.default_rng(seed).normal(size=len(dates)), 2)
    pd.DataFrame({"date": dates, "value": z}).to_csv(path, index=False)
    return z


def test_a_date_column_named_with_its_zone_is_the_time_column(tmp_path):
    path = tmp_path / "solar.csv"
    stamps = pd.date_range("2021-05-01", periods=289, freq="30min", tz="UTC")
    z = np.abs(np.round(np.random.default_rng(3).normal(size=289), 5))
    pd.DataFrame({"datetime_gmt": stamps.astype(str), "solar_gen": z}).to_csv(path, index=False)
    table = load_table(path)
    assert table.time_column == "datetime_gmt"
    assert table.sample_period == pytest.approx(1800.0)


@pytest.mark.parametrize("freq", ["MS", "QS", "YS"])
def test_calendar_dates_give_their_period(tmp_path, freq):
    """Months (28-31 days), quarters and years are one period each, not a unit mistake."""
    path = tmp_path / "monthly.csv"
    dates = pd.date_range("2000-01-01", periods=123, freq=freq)
    _dated(path, dates.strftime("%b %d %Y"))  # vega's stocks: "Jan 1 2000"
    table = load_table(path)
    steps = np.diff(dates.to_numpy()) / np.timedelta64(1, "s")
    assert table.sample_period == pytest.approx(np.mean(steps))
    text = " ".join(table.notes)
    assert "another unit" not in text and "not uniform" not in text
    assert "calendar" in text


@pytest.mark.parametrize("freq", ["h", "D"])
def test_date_times_are_not_said_to_count_microseconds(tmp_path, freq):
    path = tmp_path / "hourly.csv"
    _dated(path, pd.date_range("2010-01-01", periods=500, freq=freq).strftime("%Y/%m/%d %H:%M"))
    table = load_table(path)
    assert table.sample_period == {"h": 3600.0, "D": 86400.0}[freq]
    assert not any("microseconds" in n for n in table.notes)


def test_a_ts_file_is_refused_in_one_line_that_says_what_to_do(tmp_path, capsys):
    rng = np.random.default_rng(1)
    cases = [":".join(",".join(f"{v:.6f}" for v in rng.normal(size=100)) for _ in range(3))
             + f":{lab}" for lab in ("Standing", "Walking")]  # fmt: skip
    head = ["# a comment", "@problemName BasicMotions", "@univariate false", "@dimensions 3",
            "@classLabel true Standing Walking", "@data"]  # fmt: skip
    path = tmp_path / "BasicMotions_TRAIN.ts"
    path.write_text("\n".join([*head, *cases]) + "\n")
    assert main(["estimate", str(path)]) == 2
    err = capsys.readouterr().err.strip()
    assert "\n" not in err and ".ts file" in err and "CSV" in err
    assert "thousands" not in err


def test_a_file_stacking_several_series_is_refused(tmp_path):
    path = tmp_path / "stocks.csv"
    dates = pd.date_range("2000-01-01", periods=60, freq="MS").strftime("%b %d %Y").tolist()
    rng = np.random.default_rng(4)
    rows = [(s, d, round(p, 2)) for s, base in (("MSFT", 40), ("AMZN", 60), ("IBM", 100))
            for d, p in zip(dates, base + np.cumsum(rng.normal(size=60)), strict=True)]
    pd.DataFrame(rows, columns=["symbol", "date", "price"]).to_csv(path, index=False)
    with pytest.raises(NoisevarError, match=r"stacks 3 series.*'symbol'.*one series"):
        load_table(path)
    # one series with its label: read
    one = tmp_path / "msft.csv"
    pd.DataFrame(rows[:60], columns=["symbol", "date", "price"]).to_csv(one, index=False)
    assert load_table(one).columns["price"].size == 60


def _lines(path, a: np.ndarray) -> None:
    path.write_text("\n".join(" ".join(f"{v:6.1f}" for v in row) for row in a) + "\n")


def test_one_series_written_twelve_values_a_line_is_said(tmp_path):
    """pmdarima's sunspots.txt (R's print of a monthly series): col0 is every January."""
    rng = np.random.default_rng(11)
    t = np.arange(2400)
    z = 80 + 60 * np.sin(2 * np.pi * t / 132) + np.cumsum(rng.normal(size=t.size)) * 0.5
    path = tmp_path / "sunspots.txt"
    _lines(path, z.reshape(-1, 12))
    assert any("12 values a line" in n for n in load_table(path).notes)
    # channels side by side, and four sensors of one fast signal: no such note
    imu = np.column_stack([off + rng.normal(size=600) for off in (0, 0, 9.8, 0, 0, 0)])
    motion = 5 * np.sin(np.arange(600) / 3.0)
    same = np.column_stack([motion + 0.1 * rng.normal(size=600) for _ in range(4)])
    for name, a in (("imu.txt", imu), ("same.txt", same)):
        _lines(tmp_path / name, a)
        assert not any("values a line" in n for n in load_table(tmp_path / name).notes)

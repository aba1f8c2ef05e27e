"""Ingestion classes of the second real-record audit (benchmarks/real_audit2.py)."""

import json

import numpy as np
import pytest

import noisevar
from noisevar.cli import main
from noisevar.io import load_table


def test_a_datetime_column_of_date_times_is_the_time_column():
    """heartpy's PPG (``datetime,hr`` with ``2016-11-24 13:58:58.081000``) was refused:
    "'2016-11-24 ...' is not a number" (a column named ``datetime`` was not a time name)."""
    t0 = np.datetime64("2016-11-24T13:58:58.000")
    stamps = [str(t0 + np.timedelta64(10 * i, "ms")).replace("T", " ") for i in range(50)]
    text = "datetime,hr\n" + "".join(f"{s},{500 + i % 7}\n" for i, s in enumerate(stamps))
    t = load_table(text.encode(), "ppg.csv")
    assert t.time_column == "datetime"
    assert t.data_columns == ["hr"]
    assert t.sample_period == pytest.approx(0.01)


def test_a_date_column_of_numbers_is_read_as_dates_not_seconds():
    """statsmodels' co2 (``date,co2`` with ``19580329``): yyyymmdd numbers are not seconds
    (real_audit15: they are dates, one week apart, as Météo-France's ``AAAAMMJJ``)."""
    text = "date,co2\n19580329,316.1\n19580405,317.3\n19580412,317.6\n19580419,317.5\n"
    t = load_table(text.encode(), "co2.csv")
    assert t.time_column == "date"
    assert t.data_columns == ["co2"]
    assert t.sample_period == pytest.approx(7 * 86400.0)


def test_columns_all_on_a_one_column_file(tmp_path, capsys):
    """pywt's ECG, heartpy's PPG, statsmodels' co2 as one-column CSVs: ``estimate FILE
    --columns all`` exited 3 (internal error: 'VarianceEstimate' object is not iterable)."""
    z = np.random.default_rng(0).normal(size=300)
    path = tmp_path / "one.csv"
    path.write_text("ecg\n" + "\n".join(f"{v:.17g}" for v in z) + "\n")
    assert main(["estimate", str(path), "--columns", "all", "--format", "json"]) == 0
    (row,) = json.loads(capsys.readouterr().out)["channels"]
    assert row["variance"] == pytest.approx(noisevar.estimate(z).variance, rel=1e-9)

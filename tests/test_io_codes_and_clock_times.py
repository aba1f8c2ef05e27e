"""Columns that are no measured signal: quality codes and clock times written HHMM
(issue 26, real_audit15: Météo-France's daily files hold ``QRR`` (0, 1, 9) beside each field
and ``HTN``, the time of the day's minimum as HHMM). ``--columns all`` estimated them as
signals; it now leaves them out and says which, as the dashboard's channel picker
(``LoadedTable.signals``) does."""

import json

import numpy as np
import pandas as pd

from noisevar.batch.channels import table_channels
from noisevar.cli import main
from noisevar.io import load_table


def _station(tmp_path, n: int = 400, seed: int = 2):
    rng = np.random.default_rng(seed)
    hours, minutes = rng.integers(0, 24, n), rng.integers(0, 60, n)
    df = pd.DataFrame({
        "TN": np.round(8.0 + np.cumsum(rng.normal(0.0, 0.3, n)) + rng.normal(0.0, 1.0, n), 1),
        "QTN": rng.choice([0, 1, 9], n, p=[0.1, 0.8, 0.1]),  # a quality code
        "HTN": hours * 100 + minutes,  # 22:50 as 2250
        "NEAR": 530 + rng.integers(-15, 16, n),  # whole numbers within one hundred: a signal
    })  # fmt: skip
    path = tmp_path / "station.csv"
    df.to_csv(path, sep=";", index=False)
    return path


def test_codes_and_clock_times_are_no_signals(tmp_path):
    table = load_table(_station(tmp_path))
    assert table.signals == ["TN", "NEAR"]
    assert table_channels(table, "all") == ["TN", "NEAR"]
    assert table_channels(table, ["QTN"]) == ["QTN"]  # named, it is read


def test_columns_all_says_what_it_left_out(tmp_path, capsys):
    path = _station(tmp_path)
    assert main(["estimate", str(path), "--columns", "all", "--format", "json"]) == 0
    out, err = capsys.readouterr()
    rows = json.loads(out)["channels"]
    assert [c["column"] for c in rows if "error" not in c] == ["TN", "NEAR"], rows
    left = {c["column"]: c["error"] for c in rows if "error" in c}
    assert set(left) == {"QTN", "HTN"} and err == "", (left, err)
    assert "code" in left["QTN"] and "HHMM" in left["HTN"], left


def test_a_count_at_rest_on_neighbouring_values_stays_a_signal() -> None:
    """0, 1, 2 (a rain gauge's tips, a photon count at rest) are neighbours, as a sensor's
    noise under one step: a signal; 0 and 1 alone are a digital line, 0, 1, 9 a code."""
    import numpy as np

    from noisevar.io.column_kinds import not_measured

    rng = np.random.default_rng(0)
    assert not_measured(rng.integers(0, 3, 500).astype(float)) is None
    assert not_measured(rng.integers(0, 2, 500).astype(float)) is not None
    assert not_measured(rng.choice([0.0, 1.0, 9.0], 500)) is not None


def test_batch_gives_each_left_out_column_a_row(tmp_path, capsys):
    """``noisevar batch --columns all`` left codes and clock times out with no row, where
    ``noisevar estimate --columns all`` gave each a row saying why: one answer. The summary
    and the Fleet report count them apart from channels that failed."""
    from noisevar.batch._output import read_table
    from noisevar.batch.fleet import fleet_report

    paths = []
    for seed in range(3):
        (tmp_path / str(seed)).mkdir()
        paths.append(_station(tmp_path / str(seed), seed=seed))
    out = tmp_path / "fleet.csv"
    args = ["batch", *map(str, paths), "--columns", "all", "--out", str(out)]
    assert main(args) == 0
    err = capsys.readouterr().err
    assert "3 files, 12 rows, 0 with an error, 6 left out" in err, err
    frame = read_table(out)
    left = frame[frame["channel"].isin(["QTN", "HTN"])]
    assert len(left) == 6 and left["error"].str.startswith("left out by --columns all").all()
    assert left["std"].isna().all()
    report = fleet_report(frame)
    assert report.n_errors == 0 and any("6 columns left out" in n for n in report.notes)


def test_an_empty_batch_table_has_no_left_out_rows() -> None:
    """The left-out count reads the ``error`` column as booleans, also with no rows (an
    empty list read as floats failed the report's masks)."""
    from noisevar.batch.fleet import fleet_report

    for columns in (["file", "channel", "std", "error"], ["file", "channel", "std"]):
        empty = pd.DataFrame({c: [] for c in columns})
        assert fleet_report(empty).n_errors == 0

"""Stacked files whose series are labelled by numbers (a turbine, vehicle or station number),
and a picked series' clock (:mod:`noisevar.io.number_labels`).

Before: a file stacking series on an integer column was read as one record spliced across
the series (R over the joins) and ``--series 2`` was refused ("holds one series"); a picked
series' date-times stayed relative to the file's first row (iglu's Subject 2 at -8.8e6 s).
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar.cli import main
from noisevar.errors import StackedSeries
from noisevar.io import channel_record, load_table


def _csv(header: str, rows: list[str]) -> bytes:
    return ("\n".join([header, *rows]) + "\n").encode()


def _interleaved(n: int = 60, seed: int = 2) -> tuple[bytes, dict[int, np.ndarray]]:
    """Three turbines numbered 1-3, interleaved: each time stamp three times."""
    rng = np.random.default_rng(seed)
    values = {k: np.round(10 * k + rng.normal(size=n), 6) for k in (1, 2, 3)}
    rows = [f"{i * 600},{k},{float(values[k][i])!r}" for i in range(n) for k in (1, 2, 3)]
    return _csv("time,turbine,power", rows), values


def _blocks(n: int = 60, seed: int = 3) -> tuple[bytes, dict[int, np.ndarray]]:
    """Three vehicles numbered 7, 8, 9, one after the other, each time from 0."""
    rng = np.random.default_rng(seed)
    values = {k: np.round(k + rng.normal(size=n), 6) for k in (7, 8, 9)}
    rows = [f"{k},{i * 0.5},{float(values[k][i])!r}" for k in (7, 8, 9) for i in range(n)]
    return _csv("vehicle_id,t,speed", rows), values


@pytest.mark.parametrize("make, column", [(_interleaved, "turbine"), (_blocks, "vehicle_id")])
def test_a_numeric_label_column_is_refused_as_stacked(make, column):
    raw, values = make()
    with pytest.raises(StackedSeries) as err:
        load_table(raw, "fleet.csv")
    assert err.value.column == column and err.value.labels == tuple(str(k) for k in values)
    assert "\n" not in str(err.value) and f"--series '{next(iter(values))}'" in str(err.value)


@pytest.mark.parametrize("given", ["2", "2.0", "02", " 2 "])
def test_series_2_reads_the_rows_of_number_2_as_written(given):
    raw, values = _interleaved()
    table = load_table(raw, "scada.csv", series=given)
    z, t = channel_record(table, "power")
    assert np.array_equal(z, values[2]) and np.all(np.diff(t) == 600.0)
    assert "turbine" not in table.columns  # the label: constant, left out (noted)
    assert any("turbine = '2'" in n for n in table.notes), table.notes


def test_cli_series_on_a_numeric_label_file(tmp_path, capsys):
    raw, values = _blocks()
    p = tmp_path / "fleet.csv"
    p.write_bytes(raw)
    assert main(["estimate", str(p)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "vehicle_id" in err and "Traceback" not in err
    assert main(["estimate", str(p), "--series", "8", "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["n_total"] == values[8].size
    assert main(["estimate", str(p), "--series", "5"]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "no row has 'vehicle_id' = '5'" in err


def _coarse_clock(column: np.ndarray, n: int) -> list[str]:
    """10 rows a second, the time written in whole seconds (it repeats 9 times in 10)."""
    rng = np.random.default_rng(4)
    return [f"{i // 10},{int(column[i])},{rng.normal():.6f}" for i in range(n)]


def _false_positives() -> dict[str, bytes]:
    rng = np.random.default_rng(5)
    n = 2000
    ramp = np.arange(n)
    flag = (ramp // 137) % 3  # a status 0/1/2, the time rising
    adc = np.round(512 + 1.3 * rng.normal(size=n))  # a quantised sensor
    fixq = np.where(rng.random(n) < 0.9, 4, 5)  # a fix quality, 4 or 5
    return {
        "status, time rising": _csv(
            "t,mode,x", [f"{i * 0.1:.1f},{int(flag[i])},{rng.normal():.6f}" for i in range(n)]
        ),
        "status, coarse time": _csv("t,mode,x", _coarse_clock(flag, n)),
        "ADC count, coarse time": _csv("t,adc,x", _coarse_clock(adc, n)),
        "fix quality, coarse time": _csv("t,fix,x", _coarse_clock(fixq, n)),
        "sample counter 0-255, coarse time": _csv("t,counter,x", _coarse_clock(ramp % 256, n)),
        "digital line, the clock reset once where it changes": _csv(
            "t,line,x",
            [f"{(i % 1000) * 0.1:.1f},{(i // 50) % 2},{rng.normal():.6f}" for i in range(n)],
        ),
    }


@pytest.mark.parametrize("case", list(_false_positives()))
def test_flags_counts_and_counters_are_no_label(case):
    table = load_table(_false_positives()[case], "log.csv")
    assert table.n_rows == 2000


def test_a_picked_series_reads_its_times_from_its_own_first_row():
    rows = []
    for k, start in (("S1", "2020-01-01"), ("S2", "2020-03-15"), ("S3", "2020-02-01")):
        day = np.datetime64(f"{start}T00:00")
        rows += [f"{k},{day + np.timedelta64(5 * i, 'm')},{100 + i % 7}" for i in range(40)]
    raw = _csv("id,time,gl", rows)
    with pytest.raises(StackedSeries):
        load_table(raw, "cgm.csv")
    for label in ("S2", "S3"):
        picked = load_table(raw, "cgm.csv", series=label)
        cut = load_table(_csv("id,time,gl", [r for r in rows if r.startswith(f"{label},")]), "c")
        (_, ta), (_, tb) = channel_record(picked, "gl"), channel_record(cut, "gl")
        assert ta[0] == 0.0 and np.array_equal(ta, tb)

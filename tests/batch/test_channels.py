"""Channels: 2-D estimates against per-column ones; ``noisevar estimate --columns``."""

from __future__ import annotations

import csv
import io
import json

import numpy as np
import pytest

import noisevar as nv
from noisevar.cli import main

N = 4000
NAMES = ("ax", "ay", "az")
STDS = (0.5, 1.0, 2.0)


@pytest.fixture(scope="module")
def channels() -> np.ndarray:
    """Three random walks with noise of standard deviation 0.5, 1 and 2: shape (n, 3)."""
    rng = np.random.default_rng(7)
    walk = np.cumsum(rng.normal(0.0, 0.05, (N, 3)), axis=0)
    return walk + rng.normal(0.0, 1.0, (N, 3)) * np.array(STDS)


@pytest.fixture
def table(tmp_path, channels) -> str:
    path = tmp_path / "imu.csv"
    t = np.arange(N) * 0.01
    data = np.column_stack([t, channels])
    np.savetxt(path, data, delimiter=",", header="time," + ",".join(NAMES), comments="")
    return str(path)


@pytest.mark.parametrize("method", ["auto", "somd", "diff2", "mle-trend", "wavelet-mad"])
def test_two_d_estimates_equal_per_column_ones(channels, method):
    both = nv.estimate(channels, method=method, axis=0)
    assert isinstance(both, nv.VarianceEstimates) and both.shape == (3,)
    for j in range(3):
        one = nv.estimate(channels[:, j], method=method)
        assert both[j].variance == one.variance
        assert both[j].ci95 == one.ci95
        assert both[j].n_used == one.n_used
    frame = both.to_frame()
    assert list(frame["channel"]) == [0, 1, 2]
    np.testing.assert_array_equal(frame["variance"], both.variance)


def test_two_d_estimates_find_each_channels_noise(channels):
    std = nv.estimate(channels, axis=0).std
    np.testing.assert_allclose(std, STDS, rtol=0.1)


def _run(capsys, *argv):
    code = main([str(a) for a in argv])
    out, err = capsys.readouterr()
    assert code == 0, err
    return out


def test_cli_columns_all_json(capsys, table, channels):
    data = json.loads(_run(capsys, "estimate", table, "--columns", "all", "--format", "json"))
    assert data["file"] == table and data["method"] == "auto"
    assert [c["column"] for c in data["channels"]] == list(NAMES)
    for j, c in enumerate(data["channels"]):
        one = nv.estimate(channels[:, j])
        assert c["variance"] == pytest.approx(one.variance, rel=1e-12)
        assert [c["ci95_low"], c["ci95_high"]] == pytest.approx(list(one.ci95), rel=1e-12)


def test_cli_columns_list_csv(capsys, table, channels):
    argv = ["--columns", "az,ax", "--format", "csv", "--method", "rice"]
    out = _run(capsys, "estimate", table, *argv)
    rows = list(csv.DictReader(io.StringIO(out)))
    assert [r["channel"] for r in rows] == ["az", "ax"]
    for r, j in zip(rows, (2, 0), strict=True):
        one = nv.estimate(channels[:, j], method="rice")
        assert float(r["variance"]) == pytest.approx(one.variance, rel=1e-12)
        assert float(r["ci95_high"]) == pytest.approx(one.ci95[1], rel=1e-12)
        assert json.loads(r["params"])["method"] == "rice"


def test_cli_columns_table_has_one_row_per_channel(capsys, table, channels):
    out = _run(capsys, "estimate", table, "--columns", "all")
    lines = out.splitlines()
    for j, name in enumerate(NAMES):
        row = next(ln for ln in lines if ln.startswith(name + " "))
        assert float(row.split()[1]) == pytest.approx(nv.estimate(channels[:, j]).variance, 1e-5)


def test_cli_single_column_csv_and_config_column(capsys, tmp_path, table, channels):
    out = _run(capsys, "estimate", table, "--column", "ay", "--format", "csv")
    (row,) = list(csv.DictReader(io.StringIO(out)))
    assert row["channel"] == "ay"
    assert float(row["variance"]) == pytest.approx(nv.estimate(channels[:, 1]).variance, 1e-12)
    cfg = tmp_path / "cfg.json"
    cfg.write_text(json.dumps({"method": "diff2", "column": "az"}))
    data = json.loads(_run(capsys, "estimate", table, "--config", cfg, "--format", "json"))
    assert data["column"] == "az"
    assert data["variance"] == pytest.approx(nv.estimate(channels[:, 2], method="diff2").variance)
    cfg.write_text(json.dumps({"method": "diff2", "columns": ["ax", "ay"]}))
    many = json.loads(_run(capsys, "estimate", table, "--config", cfg, "--format", "json"))
    assert [c["column"] for c in many["channels"]] == ["ax", "ay"]


@pytest.mark.parametrize(
    ("argv", "message"),
    [
        (["--columns", "ax,nope"], "no column 'nope'"),
        (["--columns", "all", "--column", "ax"], "not both"),
        (["--columns", ","], "no column given"),
    ],
)
def test_cli_columns_errors_are_one_line(capsys, table, argv, message):
    code = main(["estimate", table, *argv])
    out, err = capsys.readouterr()
    assert code == 2 and not out
    assert message in err and len(err.strip().splitlines()) == 1

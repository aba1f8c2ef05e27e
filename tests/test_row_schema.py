"""One row schema for an estimate: to_frame(), the CLI's csv, the batch table and compare.

Every table of estimates is made of :meth:`VarianceEstimate.to_row`; the callers only add
what the row is of (``channel``, ``file``) and how it was made (batch: ``elapsed_s``, ...).
The methods' special needs are read from their specs, never from their names.
"""

from __future__ import annotations

import csv
import inspect
import io
import os
from dataclasses import replace

import numpy as np
import pandas as pd
import pytest

import noisevar as nv
from noisevar.batch import KEY_COLUMNS, RUN_COLUMNS, read_table
from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.estimators import DEFAULT_METHOD, METHODS, method_spec, register, unregister
from noisevar.estimators.compare import default_methods, single_signal_methods
from noisevar.estimators.results import FLAG_PREFIX, ROW_COLUMNS, row_columns
from noisevar.io.limits import MAX_BYTES

NAMES = ("ax", "ay")


@pytest.fixture(scope="module")
def record(tmp_path_factory):
    """A two-channel CSV file and its samples (one column per channel)."""
    rng = np.random.default_rng(11)
    n = 3000
    t = np.arange(n)
    z = np.column_stack([np.sin(t / 150) + rng.normal(0, 0.1, n), rng.standard_t(3, n)])
    path = tmp_path_factory.mktemp("schema") / "rec.csv"
    pd.DataFrame(z, columns=list(NAMES)).to_csv(path, index=False)
    return str(path), z


def _cli_csv(capsys, *argv: str) -> list[dict[str, str]]:
    assert main(list(argv)) == 0
    return list(csv.DictReader(io.StringIO(capsys.readouterr().out)))


def test_to_frame_cli_csv_and_batch_have_the_same_columns(record, capsys, tmp_path):
    path, z = record
    est = nv.estimate(z, axis=0)
    schema = list(est[0].to_row())
    assert schema == row_columns(schema)  # the row is in the schema's order
    assert set(ROW_COLUMNS) <= set(schema)
    assert [c for c in schema if c not in ROW_COLUMNS] == sorted(
        c for c in schema if c.startswith(FLAG_PREFIX)
    )

    frame = est.to_frame()
    cli = _cli_csv(capsys, "estimate", path, "--columns", "all", "--format", "csv")
    one = _cli_csv(capsys, "estimate", path, "--column", "ay", "--format", "csv")
    returned = nv.batch(path, out=tmp_path / "b.parquet", progress=False)
    nv.batch(path, out=tmp_path / "b.csv", progress=False)
    on_disk = [
        pd.read_parquet(tmp_path / "b.parquet"),
        read_table(tmp_path / "b.parquet"),
        read_table(tmp_path / "b.csv"),
        pd.read_csv(tmp_path / "b.csv"),
    ]

    assert list(frame.columns) == ["channel", *schema]
    assert list(cli[0]) == list(one[0]) == [*KEY_COLUMNS, *schema]
    for table in (returned, *on_disk):
        assert list(table.columns) == [*KEY_COLUMNS, *schema, *RUN_COLUMNS]

    # the estimate's columns are the same everywhere, and so are their values
    lead = len(KEY_COLUMNS)
    assert (
        list(frame.columns)[1:]
        == list(cli[0])[lead:]
        == list(returned.columns)[lead : -len(RUN_COLUMNS)]
    )
    for j, name in enumerate(NAMES):
        row = est[j].to_row()
        got = returned[returned["channel"] == name].iloc[0]
        for c in ("variance", "std", "ci95_low", "ci95_high", "dof"):
            assert got[c] == row[c] == frame[c].iat[j]
            assert float(cli[j][c]) == pytest.approx(row[c], rel=1e-15)
        assert got["n_used"] == row["n_used"] and got["n_total"] == row["n_total"] == len(z)
        assert got["params"] == row["params"] == cli[j]["params"]
        flags = [c for c in schema if c.startswith(FLAG_PREFIX)]
        assert [bool(got[c]) for c in flags] == [row[c] for c in flags]


def test_to_dict_nests_the_rows_fields(record):
    _, z = record
    est = nv.estimate(z[:, 0])
    row, d = est.to_row(), est.to_dict()
    scalars = [c for c in row if c not in ("other_still_levels", "verdict", "params", "notes")]
    scalars = [c for c in scalars if not c.startswith(FLAG_PREFIX)]
    assert list(d)[: len(scalars)] == scalars
    assert all(d[c] == row[c] for c in scalars)
    assert d["params"] == est.params and d["notes"] == est.notes
    assert d["diagnostics"]["verdict"] == row["verdict"]
    assert {FLAG_PREFIX + k: v for k, v in d["diagnostics"]["flags"].items()} == {
        c: row[c] for c in row if c.startswith(FLAG_PREFIX)
    }


def test_compare_rows_carry_the_schema(record):
    from noisevar.estimators.compare import compare_methods

    _, z = record
    comp = compare_methods(z[:, 0], ["rice", "somd"], true_variance=0.01)
    rows = comp.rows()
    schema = list(comp.results[0].estimate.to_row())
    assert list(rows[0])[:2] == ["method", "kind"]
    assert list(rows[0])[2 : 1 + len(schema)] == schema[1:]
    assert all(list(r) == list(rows[0]) for r in rows)
    assert comp.to_csv().splitlines()[0].split(",") == list(rows[0])


def test_an_older_batch_table_reads_with_todays_names(tmp_path):
    old = pd.DataFrame({"file": ["a.csv"], "channel": ["x"], "n": [10], "ci95_lo": [1.0]})
    old.to_csv(tmp_path / "old.csv", index=False)
    got = read_table(tmp_path / "old.csv")
    assert list(got.columns) == ["file", "channel", "n_total", "ci95_low"]
    assert str(got["n_total"].dtype) == "Int64"


# ---------------------------------------------- a method's needs come from its spec
@pytest.fixture
def plugin():
    """A registered copy of a peer, to give it capabilities by its spec alone."""
    names: list[str] = []

    def make(name: str, **changes: object):
        spec = register(replace(METHODS["rice"], name=name, **changes))
        names.append(name)
        return spec

    yield make
    for n in names:
        unregister(n)


def test_the_default_method_is_one_constant(record, capsys):
    path, _ = record
    assert DEFAULT_METHOD in METHODS
    assert inspect.signature(nv.batch).parameters["method"].default == DEFAULT_METHOD
    (row,) = _cli_csv(capsys, "estimate", path, "--format", "csv")
    assert row["method"] == DEFAULT_METHOD


def test_a_reference_method_is_refused_by_batch_and_the_columns_path(plugin, record):
    path, _ = record
    plugin("two-sensor", needs_reference=True)
    assert "two-sensor" not in single_signal_methods()
    with pytest.raises(NoisevarError, match="two-sensor needs a second sensor"):
        nv.batch(path, method="two-sensor", progress=False)
    # the CLI parser is built from the registry: the plug-in is a --method choice
    assert main(["estimate", path, "--columns", "all", "--method", "two-sensor"]) == 2
    assert main(["estimate", path, "--method", "two-sensor"]) == 2


def test_a_slow_method_is_left_out_of_long_comparisons(plugin):
    plugin("slow-peer", slow=True)
    assert "slow-peer" in default_methods(1000)
    assert "slow-peer" not in default_methods(10**6)
    assert "slow-peer" not in default_methods(1000, monte_carlo=True)


def _sparse_npy(path):
    path.write_bytes(b"\x93NUMPY")
    os.truncate(path, MAX_BYTES + 1)
    return str(path)


def test_precheck_asks_the_spec_whether_a_big_npy_may_stream(plugin, tmp_path):
    from noisevar.cli.estimate import precheck

    npy = _sparse_npy(tmp_path / "big.npy")
    assert method_spec(DEFAULT_METHOD).chunked is not None
    precheck([npy])  # the default method streams
    plugin("chunky", chunked=method_spec(DEFAULT_METHOD).chunked)
    precheck([npy, "--method", "chunky"])
    for method in ("rice", "no-such-method"):
        with pytest.raises(NoisevarError, match="over the 1,074 MB limit"):
            precheck([npy, f"--method={method}"])


def test_a_batch_table_with_text_for_a_number_is_refused_in_one_sentence(tmp_path):
    bad = tmp_path / "bad.csv"
    bad.write_text("file,channel,std,n_used\na.csv,x,loud,3\n")
    with pytest.raises(NoisevarError, match="cannot read the batch table bad.csv"):
        read_table(bad)


def test_a_row_without_a_still_r_says_why_and_its_cells_are_numbers_or_empty(tmp_path):
    rng = np.random.default_rng(26)
    white = rng.normal(0, 1, 4000)
    burst = white.copy()
    burst[:3000] *= 0.05  # a still start, then motion
    rows = [nv.estimate(white).to_row(), nv.estimate(burst).to_row()]
    assert rows[0]["still_variance"] is None
    assert "one still regime" in rows[0]["still_note"]
    assert rows[1]["still_variance"] is not None and rows[1]["still_note"] is None
    frame = nv.estimate(np.column_stack([white, burst]), axis=0).to_frame()
    for c in ("still_variance", "still_ci95_low", "still_ci95_high"):
        assert frame[c].dtype == "float64"  # NaN where absent, never the text "None"
    assert "None" not in frame.to_csv(index=False)

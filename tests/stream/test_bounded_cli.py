"""`noisevar estimate` streams a file over STREAM_BYTES without a flag, with the numbers of
the in-memory path (issue 29 item 6); a file the streamed path would read otherwise stays in
memory."""

from __future__ import annotations

import contextlib
import io
import json

import numpy as np
import pytest

import noisevar as nv
import noisevar.stream
from noisevar.cli import main

N = 120_000  # the chunked engine gives the one-pass numbers at any length (§F5.7)


def _run(*args: str) -> dict:
    buf = io.StringIO()
    with contextlib.redirect_stdout(buf):
        assert main(["estimate", *args, "--format", "json"]) == 0
    return json.loads(buf.getvalue())


@pytest.fixture
def record(tmp_path, monkeypatch):
    monkeypatch.setattr(noisevar.stream, "STREAM_BYTES", 1 << 18)  # lowered: files of ~1-2 MB
    rng = np.random.default_rng(6)
    z = np.sin(np.arange(N) / 3000) + 0.1 * rng.standard_normal(N)
    z[N // 2 :] += 1.5  # a jump
    return tmp_path, np.stack([z, 3 * z], axis=1)


def test_a_large_npy_is_streamed_with_the_in_memory_numbers(record):
    tmp, zz = record
    np.save(tmp / "big.npy", zz)
    np.save(tmp / "one.npy", zz[:, 0])
    for args, z in (
        (["big.npy"], zz[:, 0]),  # the first column, as in memory
        (["big.npy", "--column", "col1"], zz[:, 1]),
        (["big.npy", "--column", "1", "--method", "auto"], zz[:, 1]),
        (["one.npy"], zz[:, 0]),
    ):
        got = _run(str(tmp / args[0]), *args[1:])
        assert got["notes"][0].startswith("streamed in chunks")
        ref = nv.estimate(z)
        assert got["variance"] == pytest.approx(ref.variance, rel=1e-9)
        assert got["ci95_low"] == pytest.approx(ref.ci95[0], rel=1e-9)
        assert got["n_used"] == ref.n_used


def test_a_large_csv_is_streamed_unless_it_has_a_time_column(record):
    tmp, zz = record
    part = zz[:40_000]
    np.savetxt(tmp / "xy.csv", part, delimiter=",", header="x,y", comments="", fmt="%.17g")
    got = _run(str(tmp / "xy.csv"), "--column", "y")
    assert got["notes"][0].startswith("streamed in chunks")
    assert got["variance"] == pytest.approx(nv.estimate(part[:, 1]).variance, rel=1e-9)
    timed = np.column_stack([np.arange(part.shape[0]) * 0.01, part[:, 0]])
    np.savetxt(tmp / "tx.csv", timed, delimiter=",", header="t,x", comments="", fmt="%.17g")
    got = _run(str(tmp / "tx.csv"))  # gaps split the record in memory: not streamed
    assert not any(n.startswith("streamed") for n in got["notes"])
    assert got["variance"] == pytest.approx(nv.estimate(part[:, 0]).variance, rel=1e-9)


def test_a_method_without_a_chunked_path_or_several_columns_stay_in_memory(record):
    tmp, zz = record
    np.save(tmp / "big.npy", zz[:40_000])
    got = _run(str(tmp / "big.npy"), "--method", "rice")
    assert not any(n.startswith("streamed") for n in got["notes"])

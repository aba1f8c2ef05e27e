"""Batch on a real ``dask.distributed.LocalCluster``: worker processes on loopback."""

from __future__ import annotations

import numpy as np
import pandas as pd
import pytest
from distributed import Client, LocalCluster

import noisevar as nv
from noisevar.batch import read_table


@pytest.fixture(scope="module")
def client():
    cluster = LocalCluster(
        n_workers=2,
        threads_per_worker=1,
        processes=True,
        host="127.0.0.1",
        dashboard_address=None,
        silence_logs=40,
    )
    with cluster, Client(cluster) as c:
        yield c


@pytest.fixture
def fleet(tmp_path):
    rng = np.random.default_rng(3)
    for i in range(9):
        walk = np.cumsum(rng.normal(0.0, 0.05, (1200, 2)), axis=0)
        np.save(tmp_path / f"unit{i:02d}.npy", walk + rng.normal(0.0, 1.0 + i / 10, (1200, 2)))
    (tmp_path / "unit99.npy").write_bytes(b"\x93NUMPY garbage")
    return tmp_path


def test_the_cluster_gives_the_rows_of_one_process(client, fleet, tmp_path):
    assert len(client.nthreads()) == 2
    assert all(addr.startswith("tcp://127.0.0.1:") for addr in client.nthreads())
    out = tmp_path / "noise.parquet"
    local = nv.batch(fleet, progress=False)
    remote = nv.batch(fleet, client=client, out=out, progress=False)
    cols = [c for c in local.columns if c != "elapsed_s"]
    pd.testing.assert_frame_equal(local[cols], remote[cols], check_dtype=False)
    assert (
        remote["error"].notna().sum() == 1
        and "unit99" in remote.loc[remote["error"].notna(), "file"].iat[0]
    )
    assert len(read_table(out)) == 19
    ran_on = client.run(lambda: __import__("os").getpid())
    assert len(set(ran_on.values())) == 2  # two worker processes


def test_the_cluster_streams_and_resumes(client, fleet, tmp_path):
    out = tmp_path / "noise.csv"
    nv.batch(sorted(fleet.glob("unit0[0-4].npy")), client=client, out=out, progress=False)
    seen: list[tuple[int, int]] = []
    frame = nv.batch(fleet, client=client, out=out, progress=lambda d, t: seen.append((d, t)))
    assert seen[0] == (0, 5) and seen[-1] == (5, 5)
    assert [d for d, _ in seen] == sorted(d for d, _ in seen)  # one update per finished task
    assert frame["file"].nunique() == 10


def test_cli_scheduler_runs_on_the_cluster(client, fleet, tmp_path, capsys):
    from noisevar.cli import main

    out = tmp_path / "noise.parquet"
    address = client.scheduler.address
    assert main(["batch", str(fleet), "--scheduler", address, "--out", str(out), "--quiet"]) == 0
    assert "10 files, 19 rows, 1 with an error" in capsys.readouterr().err
    local = nv.batch(fleet, progress=False)
    cols = ["file", "channel", "variance", "ci95_low", "ci95_high", "error"]
    pd.testing.assert_frame_equal(read_table(out)[cols], local[cols], check_dtype=False)

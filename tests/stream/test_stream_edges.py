"""The streamed path's edges (issue 29 item 3): integers beyond 2**53 refused as in memory,
a FIFO refused instead of read forever, ``method=`` taken; the config loader's deep JSON."""

from __future__ import annotations

import json
import os
import sys

import numpy as np
import pytest

import noisevar
from noisevar.cli import main
from noisevar.config import parse_config
from noisevar.errors import NoisevarError
from noisevar.stream import estimate_file


@pytest.fixture
def big_ints() -> np.ndarray:
    return (2**60 + np.random.default_rng(2).integers(0, 1000, 3000)).astype(np.int64)


def test_integers_beyond_2_53_are_refused_by_every_streamed_reader(tmp_path, big_ints, capsys):
    np.save(tmp_path / "i.npy", big_ints)
    np.savetxt(tmp_path / "i.csv", big_ints, fmt="%d", header="x", comments="")
    big_ints.tofile(tmp_path / "i.bin")
    for name, extra in (("i.npy", {}), ("i.csv", {}), ("i.bin", {"dtype": "int64"})):
        with pytest.raises(NoisevarError, match=r"beyond 2\*\*53"):
            estimate_file(tmp_path / name, **extra)
    code = main(["estimate", str(tmp_path / "i.npy"), "--stream"])
    err = capsys.readouterr().err
    assert code == 2 and "beyond 2**53" in err and err.count("\n") == 1
    ok = (big_ints - 2**60).astype(np.int64)  # within 2**53: read, as in memory
    np.save(tmp_path / "ok.npy", ok)
    assert estimate_file(tmp_path / "ok.npy").variance == pytest.approx(
        noisevar.estimate(ok.astype(float)).variance, rel=1e-9
    )


@pytest.mark.skipif(not hasattr(os, "mkfifo"), reason="no FIFOs on this system")
def test_a_fifo_or_a_folder_is_refused_not_read_forever(tmp_path):
    fifo = tmp_path / "pipe.npy"
    os.mkfifo(fifo)
    for path in (fifo, tmp_path):
        with pytest.raises(NoisevarError, match="not a regular file"):
            estimate_file(path)


def test_estimate_file_takes_a_method(tmp_path):
    z = np.random.default_rng(1).normal(size=4000)
    np.save(tmp_path / "z.npy", z)
    got = estimate_file(tmp_path / "z.npy", method="auto")
    assert got.variance == pytest.approx(noisevar.estimate(z).variance, rel=1e-9)
    with pytest.raises(NoisevarError, match="cannot read a record in chunks"):
        estimate_file(tmp_path / "z.npy", method="rice")


def test_a_deeply_nested_config_is_one_error():
    deep = b"[" * 50_000 + b"]" * 50_000
    with pytest.raises(NoisevarError, match="nested too deeply"):
        parse_config(deep, "tuned.json")
    assert sys.getrecursionlimit() < 50_000  # the depth that broke the dashboard's loader


def test_the_dashboards_config_upload_words_a_deep_json_too():
    from dashboard.sections.estimator_tuning import _parse_with_column

    with pytest.raises(NoisevarError, match="nested too deeply"):
        _parse_with_column(b"[" * 50_000 + b"]" * 50_000, "tuned.json")


@pytest.mark.parametrize("column", [None, "0", "1", "gyro_z [rad/s]"])
def test_a_streamed_column_is_the_in_memory_one_with_its_name_and_unit(tmp_path, capsys, column):
    """--column counts data columns streamed or not (a time column is not one), and the
    streamed answer is printed under the channel's name, in its declared unit."""
    rng = np.random.default_rng(5)
    n = 3000
    table = np.c_[np.arange(n) * 0.01, rng.normal(size=n), 2 * rng.normal(size=n)]
    path = tmp_path / "imu.csv"
    np.savetxt(path, table, delimiter=",", header="time,accel_x [m/s^2],gyro_z [rad/s]",
               comments="", fmt="%.6f")  # fmt: skip
    pick = [] if column is None else ["--column", column]
    outs = []
    for extra in ([], ["--stream"]):
        assert main(["estimate", str(path), *pick, *extra, "--format", "json"]) == 0
        outs.append(json.loads(capsys.readouterr().out))
    memory, streamed = outs
    assert streamed["variance"] == pytest.approx(memory["variance"], rel=1e-6)
    for key in ("column", "unit"):
        assert streamed.get(key) == memory.get(key), key
    want = 1 if column in ("1", "gyro_z [rad/s]") else 0
    assert memory["column"] == ["accel_x [m/s^2]", "gyro_z [rad/s]"][want]

"""MATLAB ``.mat`` files (v4-v7.2) as logs: each numeric variable a topic, a time vector the
clock."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
import scipy.io as sio

import noisevar
from noisevar.cli import main
from noisevar.io import load_table, record_times
from noisevar.io.logs import list_topics


@pytest.fixture(scope="module")
def mat(tmp_path_factory) -> Path:
    rng = np.random.default_rng(0)
    f = tmp_path_factory.mktemp("mat") / "run.mat"
    t_ms = np.arange(2000) * 5.0  # 200 Hz, in ms
    gyro = rng.normal(0.0, 0.01, (2000, 3))
    sio.savemat(f, {"time_ms": t_ms, "gyro": gyro, "acc": 2 * gyro.T, "note": "run 1"},
                do_compression=True)  # fmt: skip
    return f


def test_topics_are_the_numeric_variables(mat: Path) -> None:
    tops = {t.name: t for t in list_topics(mat)}
    assert set(tops) == {"acc", "gyro"}  # the clock and the text are not topics
    assert tops["gyro"].fields == ("0", "1", "2") and tops["acc"].count == 2000
    assert tops["gyro"].rate == pytest.approx(200.0)


def test_a_column_reads_as_the_same_numbers_everywhere(mat: Path, capsys) -> None:
    tab = load_table(mat, topic="acc")  # stored 3 x 2000: read as 2000 samples of 3
    assert tab.sample_period == pytest.approx(0.005)
    z = sio.loadmat(mat)["acc"][1]
    np.testing.assert_array_equal(tab.columns["1"], z)
    want = noisevar.estimate(z, t=record_times(tab)).variance
    assert main(["estimate", str(mat), "--topic", "acc", "--column", "1", "--format", "json"]) == 0
    assert '"variance": ' + repr(want) in capsys.readouterr().out


def test_what_is_not_read_says_what_to_do(tmp_path: Path, capsys) -> None:
    s = tmp_path / "s.mat"
    sio.savemat(s, {"imu": {"gx": np.zeros(10)}})
    assert main(["topics", str(s)]) == 2
    assert "save(f, '-struct', 's')" in capsys.readouterr().err
    bad = tmp_path / "bad.mat"
    bad.write_bytes(np.random.default_rng(1).integers(0, 256, 3000, dtype=np.uint8).tobytes())
    assert main(["topics", str(bad)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "MATLAB file" in err

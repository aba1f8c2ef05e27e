"""``noisevar batch`` on big logs: the content hash streamed in bounded memory (any size),
logs read by path, ROS 2 bag directories expanded as one log each (issue 27 item 3)."""

from __future__ import annotations

import sys
import tracemalloc
from pathlib import Path

import numpy as np
import pytest

from noisevar.batch import batch, expand_paths
from noisevar.batch.digest import CHUNK, file_digest
from noisevar.io import content_digest

sys.path.insert(0, str(Path(__file__).resolve().parents[1] / "logs"))
from logfiles import imu_values, write_bag  # noqa: E402


def test_streamed_hash_equals_the_whole_file_hash(tmp_path):
    """The same hash as before (old journals resume), across chunk boundaries."""
    for n in (0, 1, CHUNK - 1, CHUNK, 2 * CHUNK + 7):
        p = tmp_path / f"f{n}.bin"
        p.write_bytes(np.random.default_rng(n).bytes(n))
        assert file_digest(p) == content_digest(p.read_bytes())


def test_hash_memory_is_bounded(tmp_path):
    """A 64 MiB (sparse) file hashed with a peak of a few chunks, not its size."""
    p = tmp_path / "big.bin"
    with open(p, "wb") as f:
        f.truncate(64 << 20)
    tracemalloc.start()
    try:
        file_digest(p)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert peak < 3 * CHUNK


def test_batch_reads_logs_by_path_and_expands_ros2_bags(tmp_path, monkeypatch):
    bags = tmp_path / "flights"
    one = write_bag(bags / "a", imu_values(400, seed=1), "mcap")
    two = write_bag(bags / "sub" / "b", imu_values(400, seed=2), "sqlite3")
    (bags / "notes.md").write_text("not data")
    assert expand_paths(bags) == sorted([str(one), str(two)])
    assert expand_paths([one]) == [str(one)]
    assert expand_paths(str(bags / "**" / "[ab]")) == sorted([str(one), str(two)])

    def whole(self):  # a file read whole into memory: the >1 GiB log's error row
        raise AssertionError(f"read whole: {self}")

    monkeypatch.setattr(Path, "read_bytes", whole)
    frame = batch([bags], topic="/imu", columns="angular_velocity.x", progress=False, jobs=1)
    assert frame["error"].isna().all(), frame["error"].tolist()
    assert sorted(frame["file"]) == sorted([str(one), str(two)])
    assert frame["hash"].tolist() == [file_digest(Path(f)) for f in frame["file"]]
    (Path(two) / "metadata.yaml").write_text((Path(two) / "metadata.yaml").read_text() + "\n")
    assert file_digest(two) != frame.set_index("file")["hash"][str(two)]  # a changed bag
    with pytest.raises(AssertionError, match="read whole"):
        Path(one).joinpath("metadata.yaml").read_bytes()


def test_a_folder_takes_recordings_not_tables_or_text_logs(tmp_path):
    for name in ("a.ulg", "b.bag", "c.bin", "d.csv", "out.parquet", "e.h5", "app.log"):
        (tmp_path / name).write_bytes(b"x")
    found = [Path(f).name for f in expand_paths(tmp_path)]
    assert found == ["a.ulg", "b.bag", "c.bin", "d.csv"]
    assert expand_paths([tmp_path / "out.parquet"]) == [str(tmp_path / "out.parquet")]

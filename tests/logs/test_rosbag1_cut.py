"""A ROS 1 bag without its index (a recorder's unclosed ``.bag.active``, a copy cut short) is
read from its whole chunks, with a note; one with no whole chunk is refused with one clear
error (noisevar.io.logs.rosbag1_cut)."""

from __future__ import annotations

import struct
from pathlib import Path

import numpy as np
import pytest
from logfiles import imu_values, write_ros1_chunked

from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io.logs import list_topics, load_log
from noisevar.io.logs.rosbag1_cut import unindexed

N = 3000


@pytest.fixture(scope="module", params=[None, "BZ2", "LZ4"])
def whole(request, tmp_path_factory) -> tuple[Path, np.ndarray]:
    z = imu_values(N, seed=3)
    return write_ros1_chunked(tmp_path_factory.mktemp("ros1") / "whole.bag", z, request.param), z


def _read(path: Path) -> tuple[np.ndarray, list[str]]:
    table = load_log(path, "/imu", ["angular_velocity.x"])
    return table.columns["angular_velocity.x"], table.notes


def test_copy_cut_short_reads_its_whole_chunks(whole, tmp_path):
    src, z = whole
    data = src.read_bytes()
    cut = tmp_path / "cut.bag"
    cut.write_bytes(data[: int(0.6 * len(data))])
    assert unindexed(cut) and not unindexed(src)
    got, notes = _read(cut)
    assert 0.4 * N < got.size < 0.6 * N and np.array_equal(got, z[: got.size, 0])
    assert any("no index" in n and "lost" in n for n in notes)
    full, notes = _read(src)
    assert np.array_equal(full, z[:, 0]) and not any("no index" in n for n in notes)


def test_unclosed_recording_reads_every_message(whole, tmp_path):
    """A recorder that never closed leaves index_pos = 0 (rosbag record's .bag.active)."""
    src, z = whole
    data = bytearray(src.read_bytes())
    at = data.find(b"index_pos=") + len(b"index_pos=")
    struct.pack_into("<Q", data, at, 0)
    active = tmp_path / "rec.bag.active"
    active.write_bytes(bytes(data))
    assert unindexed(active)
    got, _ = _read(active)
    assert np.array_equal(got, z[:, 0])
    assert next(t for t in list_topics(active) if t.name == "/imu").count == N


def test_no_whole_chunk_is_refused_in_one_line(whole, tmp_path, capsys):
    cut = tmp_path / "cut.bag"
    cut.write_bytes(whole[0].read_bytes()[:4200])  # the header and part of the first chunk
    with pytest.raises(NoisevarError, match="without its index and with no whole message"):
        list_topics(cut)
    code = main(["topics", str(cut)])
    _, err = capsys.readouterr()
    assert code == 2 and err.count("\n") == 1


def test_forged_chunk_size_stops_the_reading(whole, tmp_path):
    """A chunk declaring more than the limit is not inflated: the reading stops before it."""
    src, z = whole
    data = bytearray(src.read_bytes())
    second = data.find(b"compression=", data.find(b"compression=") + 1)
    size = data.find(b"size=", second - 40)  # the chunk header's fields: compression, size
    struct.pack_into("<I", data, size + len(b"size="), 2**32 - 1)
    cut = tmp_path / "forged.bag"
    cut.write_bytes(bytes(data[: int(0.7 * len(data))]))
    got, notes = _read(cut)
    assert 0 < got.size < N and np.array_equal(got, z[: got.size, 0])
    assert any("damaged" in n for n in notes)


def test_batch_rows_say_a_bag_was_cut(whole, tmp_path):
    """A fleet folder of bags: one cut short, one whole; the folder holding one .mcap among
    others is a folder of logs, not a recording directory."""
    from noisevar.batch._task import file_rows
    from noisevar.io.logs import is_ros2_dir

    src, _ = whole
    folder = tmp_path / "fleet"
    folder.mkdir()
    data = src.read_bytes()
    (folder / "cut.bag").write_bytes(data[: int(0.6 * len(data))])
    (folder / "whole.bag").write_bytes(data)
    (folder / "one.mcap").write_bytes(b"\x89MCAP0\r\n")
    assert not is_ros2_dir(folder)
    cut = file_rows(str(folder / "cut.bag"), ["angular_velocity.x"], "auto", {}, topic="/imu")
    fine = file_rows(str(folder / "whole.bag"), ["angular_velocity.x"], "auto", {}, topic="/imu")
    assert cut[0]["notes"].startswith("the ROS 1 bag has no index")
    assert "no index" not in (fine[0]["notes"] or "")

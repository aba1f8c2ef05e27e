"""An MCAP file cut short (a recording that never closed) is read up to its cut, with a note;
one with no whole message is refused with one clear error (noisevar.io.logs.mcap_cut)."""

from __future__ import annotations

import json
import struct
from pathlib import Path

import numpy as np
import pytest
from logfiles import imu_values, rechunked_mcap, write_bag

from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.io.logs import list_topics, load_log
from noisevar.io.logs.mcap_cut import cut_short

N = 3000


@pytest.fixture(scope="module")
def whole(tmp_path_factory) -> tuple[Path, np.ndarray]:
    d = tmp_path_factory.mktemp("mcap")
    z = imu_values(N)
    bag = write_bag(d / "b", z, "mcap")
    return rechunked_mcap(next(bag.glob("*.mcap")), d / "whole.mcap", "ZSTD"), z


def _cut(path: Path, frac: float, out: Path) -> Path:
    data = path.read_bytes()
    out.write_bytes(data[: int(len(data) * frac)])
    return out


@pytest.mark.parametrize("frac", [0.35, 0.7, 0.97])
def test_cut_file_reads_its_whole_chunks_with_a_note(whole, tmp_path, frac):
    src, z = whole
    cut = _cut(src, frac, tmp_path / "cut.mcap")
    assert cut_short(cut) and not cut_short(src)
    imu = next(t for t in list_topics(cut) if t.name == "/imu")
    assert 0 < imu.count < N
    table = load_log(cut, "/imu", ["angular_velocity.x"])
    got = table.columns["angular_velocity.x"]
    # the messages up to the cut, in order, each as recorded
    assert got.size == imu.count and np.array_equal(got, z[: got.size, 0])
    assert got.size > frac * N * 0.8  # only the last chunk (about 150 messages) is lost
    note = " ".join(table.notes)
    assert "cut short" in note and "lost" in note
    full = load_log(src, "/imu", ["angular_velocity.x"])
    assert not any("cut short" in n for n in full.notes)


def test_cut_file_through_the_cli(whole, tmp_path, capsys):
    cut = _cut(whole[0], 0.6, tmp_path / "cut.mcap")
    code = main(["estimate", str(cut), "--topic", "/imu", "--column", "angular_velocity.x"])
    out, err = capsys.readouterr()
    assert code == 0 and not err
    assert "cut short" in out and "variance" in out


def test_cut_before_any_message_is_refused(whole, tmp_path, capsys):
    cut = tmp_path / "cut.mcap"
    cut.write_bytes(whole[0].read_bytes()[:200])  # the header and part of the first chunk
    with pytest.raises(NoisevarError, match="cut short with no whole message"):
        list_topics(cut)
    code = main(["topics", str(cut)])
    out, err = capsys.readouterr()
    assert code == 2 and err.count("\n") == 1 and "copy the file again" in err


def test_topics_says_the_file_is_cut(whole, tmp_path, capsys):
    cut = _cut(whole[0], 0.5, tmp_path / "cut.mcap")
    assert main(["topics", str(cut)]) == 0
    out, _ = capsys.readouterr()
    assert "note      the MCAP file is cut short" in out
    assert main(["topics", str(cut), "--json"]) == 0
    data = json.loads(capsys.readouterr().out)
    assert any("cut short" in n for n in data["notes"])
    assert main(["topics", str(whole[0]), "--json"]) == 0
    assert json.loads(capsys.readouterr().out)["notes"] == []


def test_forged_chunk_size_stops_the_reading(whole, tmp_path):
    """A chunk whose declared size is over the limit is not decompressed: reading stops there."""
    data = bytearray(whole[0].read_bytes())
    assert data[8] == 0x01  # the header record after the magic: opcode, u64 length, body
    at = 8 + 9 + struct.unpack_from("<Q", data, 9)[0]
    assert data[at] == 0x06  # the first chunk: opcode, u64 length, start, end, size, ...
    struct.pack_into("<Q", data, at + 1 + 8 + 16, 1 << 62)
    cut = tmp_path / "forged.mcap"
    cut.write_bytes(bytes(data[: len(data) // 2]))
    with pytest.raises(NoisevarError, match="cut short"):
        list_topics(cut)


def test_recording_directory_that_never_closed(whole, tmp_path, capsys):
    """``ros2 bag record`` writes metadata.yaml on closing: a crashed recording's directory
    has its bag file alone (here cut short too); two files (a split recording) are asked."""
    rec = tmp_path / "rosbag2_2026_11_27"
    rec.mkdir()
    _cut(whole[0], 0.5, rec / "rosbag2_2026_11_27_0.mcap")
    table = load_log(rec, "/imu", ["angular_velocity.x"])
    assert table.columns["angular_velocity.x"].size > 0
    joined = " ".join(table.notes)
    assert "no metadata.yaml" in joined and "cut short" in joined
    _cut(whole[0], 0.9, rec / "rosbag2_2026_11_27_1.mcap")
    assert main(["topics", str(rec)]) == 2
    err = capsys.readouterr().err
    assert err.count("\n") == 1 and "give one file" in err

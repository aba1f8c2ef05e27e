"""``noisevar topics`` on a ROS bag: each topic's rate over its own span of record times
(from the bag's index), not the bag's (io/logs/rosbag_spans.py). ROS 1, ROS 2 sqlite3 and
MCAP bags, each with a topic that stops halfway and one that starts late."""

from __future__ import annotations

from pathlib import Path

import numpy as np
import pytest
from logfiles import RATE, write_bag

from noisevar.io.logs import rosbag
from noisevar.io.logs.rosbag_spans import topic_span

T0 = 1_700_000_000 * 10**9


def _bag(path: Path, kind: str, pad: int = 0) -> Path:
    """/full at 10 Hz for 20 s, /early at 10 Hz for its first 5 s, /late at 25 Hz from 15 s;
    ``pad`` bytes of a /blob string beside each /full message (several chunks: rosbags
    closes a chunk at 1 MiB; ROS 1 at 4 KiB here)."""
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    ros1 = kind == "ros1"
    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    flt, text = store.types["std_msgs/msg/Float64"], store.types["std_msgs/msg/String"]
    if ros1:
        w = Writer1(path)
        w.chunk_threshold = 4096
    else:
        plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
        w = Writer(path, version=9, storage_plugin=plugin)
    ser = store.serialize_ros1 if ros1 else store.serialize_cdr
    w.open()
    plan = {"/full": (0.0, 20.0, 10.0), "/early": (0.0, 5.0, 10.0), "/late": (15.0, 5.0, 25.0)}
    rows = []
    for name, (start, seconds, hz) in plan.items():
        conn = w.add_connection(name, flt.__msgtype__, typestore=store)
        n = int(seconds * hz)
        rows += [(T0 + round((start + i / hz) * 1e9), conn, i) for i in range(n)]
    blob = w.add_connection("/blob", text.__msgtype__, typestore=store) if pad else None
    for ns, conn, i in sorted(rows, key=lambda r: r[0]):
        w.write(conn, ns, ser(flt(data=float(i)), flt.__msgtype__))
        if blob is not None and conn.topic == "/full":
            w.write(blob, ns + 1, ser(text(data="x" * pad), text.__msgtype__))
    w.close()
    return path


@pytest.mark.parametrize("kind", ["ros1", "sqlite3", "mcap"])
def test_each_topic_rate_over_its_own_span(tmp_path, kind):
    suffix = ".bag" if kind == "ros1" else ""
    bag = _bag(tmp_path / f"b{suffix}", kind)
    rates = {t.name: t.rate for t in rosbag.topics(bag)}
    # the bag spans 20 s: over it /early would read 49 / 19.9 = 2.5 Hz, /late 124 / 19.9
    assert rates == pytest.approx({"/full": 10.0, "/early": 10.0, "/late": 25.0}, rel=1e-9)


def test_a_reader_without_an_index_falls_back_on_the_bag_span():
    class Conn:
        id, topic, msgtype, owner = 1, "/x", "std_msgs/msg/Float64", object()

    assert topic_span([Conn()]) is None and topic_span([]) is None


def test_mcap_chunks_are_read_by_their_index_only(tmp_path):
    """An MCAP bag of several chunks: the span is the index's, the same as the messages'."""
    from rosbags.highlevel import AnyReader

    bag = _bag(tmp_path / "b", "mcap", pad=20_000)  # about 4 MB: 4 chunks
    with AnyReader([bag]) as reader:
        (storage,) = reader.topics["/full"].connections[0].owner.storages
        assert len(storage.chunks) >= 3
        for name, info in reader.topics.items():
            stamps = [t for _, t, _ in reader.messages(connections=info.connections)]
            assert topic_span(info.connections) == (min(stamps), max(stamps)), name
            assert np.all(np.diff(stamps) > 0)


@pytest.mark.parametrize("kind", ["ros1", "sqlite3", "mcap"])
def test_the_committed_fixture_bags_give_each_topic_its_own_rate(tmp_path, kind):
    """write_bag: /imu at RATE, /level at every 4th sample (its last message 3 samples
    before the bag's end, so over the bag's span it read below RATE / 4)."""

    z = np.random.default_rng(0).normal(size=(203, 6))
    bag = write_bag(tmp_path / ("b.bag" if kind == "ros1" else "b"), z, kind)
    rates = {t.name: t.rate for t in rosbag.topics(bag)}
    assert rates == pytest.approx({"/imu": RATE, "/level": RATE / 4}, rel=1e-6)

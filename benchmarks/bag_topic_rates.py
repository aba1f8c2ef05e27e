"""``noisevar topics`` on ROS bags: each topic's rate over its own span, and what it costs.

Writes a ROS 1, a ROS 2 sqlite3 and a ROS 2 MCAP bag (temporary) of ``--messages``
Float64 messages on /full (1 kHz over the whole bag) plus /early (its first quarter) and
/late (its last quarter), then times ``rosbag.topics`` with each topic's own span (from
the bag's index, io/logs/rosbag_spans.py) and with the bag's span only (the code before),
and gives both rates. Results: ``results/bag_topic_rates.md``.

Usage: ``python benchmarks/bag_topic_rates.py [--messages 200000]``.
"""

from __future__ import annotations

import argparse
import os
import tempfile
import time
from pathlib import Path
from unittest import mock

from noisevar.io.logs import rosbag

RESULTS = Path(__file__).resolve().parent / "results"
OUT = RESULTS / "bag_topic_rates.md"
T0 = 1_700_000_000 * 10**9


def write(path: Path, kind: str, n: int) -> Path:
    from rosbags.rosbag1 import Writer as Writer1
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    ros1 = kind == "ros1"
    store = get_typestore(Stores.ROS1_NOETIC if ros1 else Stores.ROS2_HUMBLE)
    flt = store.types["std_msgs/msg/Float64"]
    plugin = StoragePlugin.MCAP if kind == "mcap" else StoragePlugin.SQLITE3
    w = Writer1(path) if ros1 else Writer(path, version=9, storage_plugin=plugin)
    ser = store.serialize_ros1 if ros1 else store.serialize_cdr
    w.open()
    full, early, late = (w.add_connection(t, flt.__msgtype__, typestore=store)
                         for t in ("/full", "/early", "/late"))  # fmt: skip
    data = ser(flt(data=1.0), flt.__msgtype__)
    for i in range(n):
        ns = T0 + i * 1_000_000
        w.write(full, ns, data)
        if i < n // 4 and i % 2 == 0:
            w.write(early, ns + 1, data)
        if i >= 3 * n // 4 and i % 5 == 0:
            w.write(late, ns + 2, data)
    w.close()
    return path


def timed(bag: Path, own: bool) -> tuple[dict, float, float]:
    patch = mock.patch.object(rosbag, "topic_span", return_value=None) if not own else None
    with patch or mock.patch.object(rosbag, "MAX_FIELDS", rosbag.MAX_FIELDS):
        wall, cpu = time.perf_counter(), time.process_time()
        rates = {t.name: t.rate for t in rosbag.topics(bag)}
        return rates, time.perf_counter() - wall, time.process_time() - cpu


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--messages", type=int, default=200_000)
    args = p.parse_args()
    lines = [
        "# Topic rates of ROS bags over their own spans",
        "",
        f"{args.messages} /full messages at 1 kHz; /early at 500 Hz over the first quarter, "
        f"/late at 200 Hz over the last. Load {os.getloadavg()[0]:.2f} at the start.",
        "",
        "| bag | size (MB) | rates, own span (Hz) | rates, bag span (Hz) "
        "| topics() own: wall / CPU s | bag span only: wall / CPU s |",
        "|---|---|---|---|---|---|",
    ]
    with tempfile.TemporaryDirectory() as tmp:
        for kind in ("ros1", "sqlite3", "mcap"):
            bag = write(Path(tmp) / (f"{kind}.bag" if kind == "ros1" else kind), kind,
                        args.messages)  # fmt: skip
            size = sum(f.stat().st_size for f in ([bag] if bag.is_file() else bag.iterdir()))
            timed(bag, True)  # warm the file cache for both
            own, w1, c1 = timed(bag, True)
            whole, w0, c0 = timed(bag, False)
            fmt = ", ".join
            lines.append(
                f"| {kind} | {size / 1e6:.1f} | {fmt(f'{k} {v:.2f}' for k, v in own.items())} "
                f"| {fmt(f'{k} {v:.2f}' for k, v in whole.items())} | {w1:.3f} / {c1:.3f} "
                f"| {w0:.3f} / {c0:.3f} |"
            )
    RESULTS.mkdir(exist_ok=True)
    OUT.write_text("\n".join(lines) + "\n")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

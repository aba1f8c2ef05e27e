"""Reading logs (issue 27, item 1): a ~1 GB ROS 2 mcap bag, listed and streamed.

    nice -n 10 python benchmarks/logs.py [--mb 1000] [--keep]

1. **The bag.** Written with ``rosbags`` (its own ROS 2 writer, mcap storage, no
   compression) into ``/tmp/noisevar-logs-bench``: ``/imu`` (``sensor_msgs/Imu``, 400 Hz,
   white rate noise, seeded), ``/camera/image_raw`` (``sensor_msgs/Image``, 640x480 mono8,
   30 Hz), ``/points`` (``sensor_msgs/PointCloud2``, 20,000 points x 16 bytes, 10 Hz) and
   ``/status`` (``std_msgs/Float64``, 10 Hz), interleaved in time order, until the file
   reaches ``--mb`` MB. Then read once so that every run reads it from the page cache.
2. **Runs**, each a fresh process under ``/usr/bin/time -v`` (wall time, peak resident
   memory of the whole process, interpreter and imports included): ``noisevar topics BAG``;
   the IMU topic streamed (``noisevar.io.logs.read_topic``, three gyro fields, chunks
   iterated and dropped); the IMU topic gathered (``load_table``, the ten default fields);
   ``noisevar imu BAG --topic /imu`` on the three gyro axes (log to noise terms).
   Throughput: MB of log per second of wall time.
3. **Worst case for MB/s:** a bag of ``/imu`` only (``--imu-mb`` MB), streamed as above:
   messages per second.
4. **Where the time goes**, in one process: the bag's message iteration alone (rosbags
   reading the chunks that hold ``/imu``), then the same plus rosbags' deserialiser on each
   message, then our whole read (fixed-layout fields taken from the bytes into arrays).

Writes ``benchmarks/results/logs.md``.
"""

from __future__ import annotations

import argparse
import os
import platform
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

RESULTS = ROOT / "benchmarks" / "results"
WORK = Path("/tmp/noisevar-logs-bench")
SEED = 20261126
RATE = 400.0
GYRO = ["angular_velocity.x", "angular_velocity.y", "angular_velocity.z"]


def write_bag(  # long: one writer loop, four topics
    path: Path, megabytes: float, imu_only: bool = False
) -> dict:
    """The benchmark bag (``imu_only``: the /imu topic alone); returns what it holds."""
    from rosbags.rosbag2 import StoragePlugin, Writer
    from rosbags.typesys import Stores, get_typestore

    store = get_typestore(Stores.ROS2_HUMBLE)
    ty = store.types
    imu_t, hdr_t, tm_t = (
        ty["sensor_msgs/msg/Imu"],
        ty["std_msgs/msg/Header"],
        ty["builtin_interfaces/msg/Time"],
    )
    vec_t, quat_t = ty["geometry_msgs/msg/Vector3"], ty["geometry_msgs/msg/Quaternion"]
    img_t, pc_t, pf_t = (
        ty["sensor_msgs/msg/Image"],
        ty["sensor_msgs/msg/PointCloud2"],
        ty["sensor_msgs/msg/PointField"],
    )
    f64_t = ty["std_msgs/msg/Float64"]
    rng = np.random.default_rng(SEED)
    image = rng.integers(0, 255, 640 * 480, dtype=np.uint8)
    cloud = rng.integers(0, 255, 20_000 * 16, dtype=np.uint8)
    fields = [pf_t(name=n, offset=4 * i, datatype=7, count=1) for i, n in enumerate("xyzi")]
    w = Writer(path, version=9, storage_plugin=StoragePlugin.MCAP)
    w.open()
    c_imu = w.add_connection("/imu", imu_t.__msgtype__, typestore=store)
    c_img = w.add_connection("/camera/image_raw", img_t.__msgtype__, typestore=store)
    c_pc = w.add_connection("/points", pc_t.__msgtype__, typestore=store)
    c_st = w.add_connection("/status", f64_t.__msgtype__, typestore=store)
    t0 = 1_700_000_000_000_000_000
    cov = np.zeros(9)
    written, k, counts = 0, 0, {"/imu": 0, "/camera/image_raw": 0, "/points": 0, "/status": 0}
    limit = megabytes * 1e6
    while written < limit:
        ns = t0 + int(round(k * 1e9 / RATE))
        stamp = tm_t(sec=ns // 10**9, nanosec=ns % 10**9)
        head = hdr_t(stamp=stamp, frame_id="imu_link")
        g, a = rng.normal(0, 0.01, 3), rng.normal(0, 0.05, 3)
        msg = imu_t(
            header=head,
            orientation=quat_t(x=0.0, y=0.0, z=0.0, w=1.0),
            orientation_covariance=cov,
            angular_velocity=vec_t(x=g[0], y=g[1], z=g[2]),
            angular_velocity_covariance=cov,
            linear_acceleration=vec_t(x=a[0], y=a[1], z=a[2] + 9.81),
            linear_acceleration_covariance=cov,
        )
        out = [(c_imu, store.serialize_cdr(msg, imu_t.__msgtype__), "/imu")]
        if k % 40 == 0 and not imu_only:  # 10 Hz
            cloud_msg = pc_t(
                header=hdr_t(stamp=stamp, frame_id="lidar"),
                height=1,
                width=20_000,
                fields=fields,
                is_bigendian=False,
                point_step=16,
                row_step=320_000,
                data=cloud,
                is_dense=True,
            )
            out.append((c_pc, store.serialize_cdr(cloud_msg, pc_t.__msgtype__), "/points"))
            value = f64_t(data=float(k))
            out.append((c_st, store.serialize_cdr(value, f64_t.__msgtype__), "/status"))
        if k % 13 == 0 and not imu_only:  # ~30 Hz
            img = img_t(
                header=hdr_t(stamp=stamp, frame_id="camera"),
                height=480,
                width=640,
                encoding="mono8",
                is_bigendian=0,
                step=640,
                data=image,
            )
            out.append((c_img, store.serialize_cdr(img, img_t.__msgtype__), "/camera/image_raw"))
        for conn, raw, topic in out:
            w.write(conn, ns, raw)
            written += len(raw)
            counts[topic] += 1
        k += 1
    w.close()
    return counts


def timed(cmd: list[str]) -> tuple[float, float, str]:
    """Wall seconds, peak RSS (MB) and stdout of ``cmd`` run under ``/usr/bin/time -v``."""
    start = time.perf_counter()
    proc = subprocess.run(
        ["/usr/bin/time", "-v", *cmd], capture_output=True, text=True, check=False
    )
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError(f"{cmd} failed: {proc.stderr[-2000:]}")
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr)[1])
    return wall, rss / 1024, proc.stdout


STREAM = """
import sys
from noisevar.io.logs import read_topic
n = 0
for chunk in read_topic(sys.argv[1], "/imu", {fields!r}):
    n += chunk.times.size
print(n)
"""
GATHER = """
import sys
from noisevar.io import load_table
print(load_table(sys.argv[1], topic="/imu").n_rows)
"""


def layers(bag: Path) -> list[tuple[str, float]]:
    """Seconds for: rosbags' message iteration of /imu; plus deserialising; our read."""
    from rosbags.highlevel import AnyReader

    from noisevar.io.logs import read_topic

    out = []
    with AnyReader([bag]) as r:
        conns = [c for c in r.connections if c.topic == "/imu"]
        t = time.perf_counter()
        for _ in r.messages(connections=conns):
            pass
        out.append(("rosbags: iterate the /imu messages (raw bytes)", time.perf_counter() - t))
        t = time.perf_counter()
        for c, _, raw in r.messages(connections=conns):
            r.deserialize(raw, c.msgtype)
        out.append(("rosbags: iterate and deserialise each message", time.perf_counter() - t))
    t = time.perf_counter()
    for _ in read_topic(bag, "/imu", GYRO):
        pass
    out.append(("noisevar: read_topic, three gyro fields", time.perf_counter() - t))
    return out


def main() -> None:  # long: the runs and the report, in order
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mb", type=float, default=1000.0, help="size of the bag (MB)")
    ap.add_argument("--imu-mb", type=float, default=100.0, help="size of the IMU-only bag (MB)")
    ap.add_argument("--keep", action="store_true", help="keep the bag in /tmp")
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    shutil.rmtree(WORK, ignore_errors=True)
    WORK.mkdir(parents=True)
    bag = WORK / "bag"
    t = time.perf_counter()
    counts = write_bag(bag, args.mb)
    t_write = time.perf_counter() - t
    mcap = next(bag.glob("*.mcap"))
    size = mcap.stat().st_size
    with mcap.open("rb") as fh:  # into the page cache
        while fh.read(1 << 24):
            pass
    py = sys.executable
    runs = [
        ("`noisevar topics BAG`", [py, "-m", "noisevar", "topics", str(bag)]),
        (
            "stream `/imu` (3 gyro fields, `read_topic`)",
            [py, "-c", STREAM.format(fields=GYRO), str(bag)],
        ),
        ("gather `/imu` (10 fields, `load_table`)", [py, "-c", GATHER, str(bag)]),
        (
            "`noisevar imu BAG --topic /imu --columns <3 gyro axes>`",
            [
                py,
                "-m",
                "noisevar",
                "imu",
                str(bag),
                "--topic",
                "/imu",
                "--columns",
                *GYRO,
                "--format",
                "json",
            ],
        ),
    ]
    rows = []
    for label, cmd in runs:
        wall, rss, _ = timed(cmd)
        rows.append((label, wall, size / 1e6 / wall, rss))
        print(f"{label}: {wall:.2f} s, {size / 1e6 / wall:.1f} MB/s, {rss:.0f} MB", flush=True)
    parts = layers(bag)
    if not args.keep:
        shutil.rmtree(bag, ignore_errors=True)
    only = WORK / "imu_only"
    only_counts = write_bag(only, args.imu_mb, imu_only=True)
    only_size = next(only.glob("*.mcap")).stat().st_size
    o_wall, o_rss, _ = timed([py, "-c", STREAM.format(fields=GYRO), str(only)])
    n_imu = only_counts["/imu"]
    parts_only = layers(only)
    rows.append(
        (
            f"IMU-only bag ({n_imu:,} messages, {only_size / 1e6:,.0f} MB): stream `/imu`",
            o_wall,
            only_size / 1e6 / o_wall,
            o_rss,
        )
    )
    print(f"imu-only: {o_wall:.2f} s, {only_size / 1e6 / o_wall:.1f} MB/s", flush=True)
    load = f"{load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end"
    lines = [
        "# Reading logs (issue 27, item 1)",
        "",
        f"Command: `nice -n 10 python benchmarks/logs.py --mb {args.mb:g}` on "
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
        f"1-minute load average {load} (other jobs share the machine).",
        "",
        f"Bag: ROS 2 mcap (rosbags writer, uncompressed), {size / 1e6:,.0f} MB, written in "
        f"{t_write:.0f} s: "
        + ", ".join(f"`{k}` {v:,}" for k, v in counts.items())
        + " messages (IMU at 400 Hz). Read from the page cache.",
        "",
        "| run | wall (s) | MB of log / s | peak RSS (MB) | target |",
        "|---|---|---|---|---|",
    ]
    for label, wall, mbs, rss in rows:
        ok = "yes" if mbs >= 50 and rss < 300 else "**no**"
        lines.append(f"| {label} | {wall:.2f} | {mbs:,.0f} | {rss:.0f} | {ok} |")
    lines += [
        "",
        "Target (issue 27): >= 50 MB/s of log and < 300 MB of memory, streamed.",
        "",
        "MB/s depends on what the bag holds: big messages (images, clouds) cost little per "
        "MB, small ones are paid per message. The last row is the worst case, a bag of IMU "
        f"messages only, streamed the same way: {n_imu / o_wall:,.0f} messages/s"
        + (
            "; under the 50 MB/s target, by the per-message cost (next table)."
            if only_size / 1e6 / o_wall < 50
            else "."
        ),
        "",
        "## Where the time goes (one process, reading `/imu`)",
        "",
        "| layer | 1 GB bag: s | MB/s | IMU-only bag: s | messages/s |",
        "|---|---|---|---|---|",
    ]
    lines += [
        f"| {name} | {sec:.2f} | {size / 1e6 / sec:,.0f} | {sec2:.2f} | {n_imu / sec2:,.0f} |"
        for (name, sec), (_, sec2) in zip(parts, parts_only, strict=True)
    ]
    (RESULTS / "logs.md").write_text("\n".join(lines) + "\n")
    print("\n".join(lines))
    if not args.keep:
        shutil.rmtree(WORK, ignore_errors=True)


if __name__ == "__main__":
    main()

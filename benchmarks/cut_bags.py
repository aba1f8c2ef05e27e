"""Real bags cut short, as a crash or a copy leaves them: what is read back, and its R.

    python benchmarks/cut_bags.py

Bags nobody here wrote (evo's ROS 1 bags and ROS 2 MCAP files, a model ship's MCAP from
blobjugglerpy; fetched by ``real_audit4.py``'s sources at run time) are cut at 30, 60 and
90 % of their bytes, and each is read as users read it (``load_log``). Per cut: the
messages kept of the topic, whether they are the whole bag's first ones value for value
(timestamps too), and ``auto``'s R of the field on the cut bag against R of the same
messages taken from the whole bag (they must be equal: the same samples). A recorder's
unclosed ROS 1 bag (``index_pos`` 0) is read whole. Writes ``results/cut_bags.md``.
"""

from __future__ import annotations

import struct
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
sys.path.insert(0, str(HERE))

from real_audit4 import path_of  # noqa: E402

import noisevar  # noqa: E402
from noisevar.errors import NoisevarError  # noqa: E402
from noisevar.io import channel_record  # noqa: E402
from noisevar.io.logs import load_log  # noqa: E402
from noisevar.io.table import LoadedTable  # noqa: E402

#: (record of real_audit4's SOURCES, topic, field)
CASES = (
    ("ros1_evo_slam", "groundtruth", "pose.position.x"),
    ("ros1_evo_fr2desk", "/fr2_desk_groundtruth", "pose.position.z"),
    ("ros2_mcap_turtlebot", "/odom", "twist.twist.linear.x"),
    ("ros2_mcap_voyager", "/voyager/measurement/imu", "angular_velocity.z"),
)
FRACTIONS = (0.3, 0.6, 0.9)


def _read(path: Path, topic: str, field: str) -> tuple[np.ndarray, np.ndarray, list[str]]:
    tab = load_log(path, topic, [field])
    return tab.columns["time"], tab.columns[field], list(tab.notes)


def _r(t: np.ndarray, z: np.ndarray, name: str) -> str:
    """R as every estimating path reads a channel (``channel_record``: its times)."""
    tab = LoadedTable(name, {"time": t, "x": z}, "rosbag", "time", None, [], {}, {})
    zz, times = channel_record(tab, "x")
    try:
        return f"{noisevar.estimate(zz, t=times).variance:.6g}"
    except NoisevarError as exc:
        return f"no R ({str(exc)[:40]})"


def _row(name: str, cut: str, whole: tuple, got: tuple | str) -> str:
    t_all, z_all, _ = whole
    if isinstance(got, str):
        return f"| {name} | {cut} | 0 of {z_all.size} | — | — | — | {got[:90]} |"
    t, z, notes = got
    k = z.size
    same = bool(np.array_equal(z, z_all[:k]) and np.array_equal(t, t_all[:k] - t_all[0] + t[0]))
    r_cut, r_whole = _r(t, z, name), _r(t_all[:k], z_all[:k], name)
    said = next((n for n in notes if "cut short" in n or "no index" in n), "")
    ok = "yes" if same and r_cut == r_whole else "**no**"
    return (
        f"| {name} | {cut} | {k:,} of {z_all.size:,} | {ok} | {r_cut} | {r_whole} | "
        f"{said[:110]}{'...' if len(said) > 110 else ''} |"
    )


def main() -> None:
    start = time.perf_counter()
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        for name, topic, field in CASES:
            src = path_of(name)
            src = next(src.glob("*.mcap")) if src.is_dir() else src
            whole = _read(src, topic, field)
            data = src.read_bytes()
            for frac in FRACTIONS:
                cut = Path(tmp) / f"{frac}-{src.name}"
                cut.write_bytes(data[: int(frac * len(data))])
                try:
                    got: tuple | str = _read(cut, topic, field)
                except NoisevarError as exc:
                    got = str(exc)
                rows.append(_row(f"{name} `{topic}` {field}", f"{frac:.0%}", whole, got))
            if src.suffix == ".bag":  # a recorder that never closed: index_pos 0
                raw = bytearray(data)
                at = raw.find(b"index_pos=") + len(b"index_pos=")
                struct.pack_into("<Q", raw, at, 0)
                active = Path(tmp) / f"{src.stem}.bag.active"
                active.write_bytes(bytes(raw))
                rows.append(_row(f"{name} `{topic}` {field}", "unclosed (.bag.active)", whole,
                                 _read(active, topic, field)))  # fmt: skip
    out = [
        "### Bags cut short (`python benchmarks/cut_bags.py`)",
        "",
        "Each real bag cut at a share of its bytes and read as users read it. *Kept*: the "
        "topic's messages read back; *first ones*: they are the whole bag's first messages, "
        "values and time steps alike; R on the cut bag and R of the same messages from the "
        "whole bag (equal when the same samples are read).",
        "",
        "| bag, topic, field | cut at | kept | first ones, same R | R (cut bag) | R (whole bag, "
        "same messages) | note |",
        "|---|---|---|---|---|---|---|",
        *rows,
        "",
        f"{time.perf_counter() - start:.1f} s wall.",
        "",
    ]
    text = "\n".join(out)
    (HERE / "results" / "cut_bags.md").write_text(text)
    print(text)


if __name__ == "__main__":
    main()

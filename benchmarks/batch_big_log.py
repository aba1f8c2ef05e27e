"""``noisevar batch`` on a log over 1 GiB (issue 27, item 3): hashed streamed, read by path.

    nice -n 10 python benchmarks/batch_big_log.py [--mb 1150] [--main /work/main]

1. **The bag.** ``benchmarks/logs.py``'s ROS 2 mcap bag (``/imu`` at 400 Hz among images,
   point clouds and a status topic; seeded), ``--mb`` MB: over the 1 GiB cap
   (``noisevar.io.limits.MAX_BYTES``) that a file read whole into memory meets. Read once
   into the page cache.
2. **Runs**, each a fresh process under ``/usr/bin/time -v`` (wall time, peak resident
   memory): ``noisevar batch BAGDIR --topic /imu --columns angular_velocity.x --out CSV``
   (the bag's directory, expanded to one log), then the same on the ``.mcap`` file; then,
   when ``--main`` names a checkout of the code before this change, the ``.mcap`` file by
   that code (its batch read the file whole and hashed the bytes).
3. **The hash alone**, in this process: :func:`noisevar.batch.digest.file_digest` of the
   ``.mcap`` (seconds, MB/s, the peak of Python's allocations by ``tracemalloc``).

Writes ``benchmarks/results/batch_big_log.md``.
"""

from __future__ import annotations

import argparse
import os
import platform
import shutil
import sys
import time
import tracemalloc
from pathlib import Path

import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from logs import timed, write_bag  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"
WORK = Path("/tmp/noisevar-batch-big-log")


def run_batch(source: Path, out: Path, cwd: Path) -> tuple[float, float, str]:
    """Wall s, peak MB and the rows' outcome of ``noisevar batch`` run from ``cwd``."""
    cmd = [sys.executable, "-m", "noisevar", "batch", str(source), "--topic", "/imu"]
    cmd += ["--columns", "angular_velocity.x", "--out", str(out), "--quiet", "--no-resume"]
    here = os.getcwd()
    os.chdir(cwd)  # python -m noisevar imports the package of the working directory
    try:
        wall, rss, _ = timed(cmd)
    finally:
        os.chdir(here)
    frame = pd.read_csv(out)
    errors = frame["error"].dropna()
    said = f"error: {str(errors.iat[0])[:90]}" if len(errors) else f"{len(frame)} row, no error"
    return wall, rss, said


def hash_alone(path: Path) -> tuple[float, float]:
    """Seconds and peak traced MB of the streamed hash."""
    from noisevar.batch.digest import file_digest

    tracemalloc.start()
    t = time.perf_counter()
    file_digest(path)
    wall = time.perf_counter() - t
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return wall, peak / 1e6


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mb", type=float, default=1150.0, help="size of the bag (MB)")
    ap.add_argument("--main", type=Path, help="a checkout of the code before this change")
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    shutil.rmtree(WORK, ignore_errors=True)
    WORK.mkdir(parents=True)
    bag = WORK / "bag"
    write_bag(bag, args.mb)
    mcap = next(bag.glob("*.mcap"))
    size = mcap.stat().st_size
    with mcap.open("rb") as fh:  # into the page cache
        while fh.read(1 << 24):
            pass
    runs = [("this branch, the bag's directory", bag, ROOT)]
    runs.append(("this branch, the .mcap file", mcap, ROOT))
    if args.main:
        runs.append((f"before (`{args.main}`), the .mcap file", mcap, args.main))
    rows = []
    for i, (label, source, cwd) in enumerate(runs):
        wall, rss, said = run_batch(source, WORK / f"out{i}.csv", cwd)
        rows.append(
            f"| {label} | {wall:.1f} s | {size / 1e6 / wall:.0f} MB/s | {rss:.0f} MB | {said} |"
        )
        print(rows[-1], flush=True)
    h_wall, h_peak = hash_alone(mcap)
    shutil.rmtree(WORK, ignore_errors=True)
    load = f"{load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end"
    lines = [
        "# noisevar batch on a log over 1 GiB (issue 27, item 3)",
        "",
        f"Command: `nice -n 10 python benchmarks/batch_big_log.py --mb {args.mb:g}"
        + (f" --main {args.main}`" if args.main else "`")
        + f" on {platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}; 1-minute load average {load} (other jobs share the "
        f"machine). The bag: {size / 1e6:,.0f} MB ROS 2 mcap, `/imu` at 400 Hz among images "
        "and point clouds (benchmarks/logs.py's writer).",
        "",
        "| run | wall | MB of log / s | peak memory | rows |",
        "|---|---|---|---|---|",
        *rows,
        "",
        f"The streamed hash alone (`file_digest`, 1 MiB chunks): {h_wall:.2f} s, "
        f"{size / 1e6 / h_wall:.0f} MB/s, peak of Python's allocations {h_peak:.1f} MB.",
        "",
    ]
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / "batch_big_log.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()

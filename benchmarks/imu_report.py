"""What report.html costs: ``noisevar imu --export all`` with and without it (issue 27 item 5).

    nice -n 10 python benchmarks/imu_report.py --main /tmp/nv-main [--runs 3]

The record of ``benchmarks/exports.py`` part (b) (allan_variance_ros's simulator
configuration: 11000 s at 400 Hz, 6 axes, seeded, one ``.npy``), then, alternating,
``noisevar imu FILE --rate 400 --accel col0..2 --gyro col3..5 --export all --out DIR`` by
this checkout (which also writes ``report.html``: each column's record answer and the
Allan fits) and by ``--main`` (a checkout from before, without the report), each a fresh
process under ``/usr/bin/time -v``. Reports the wall and CPU times (CPU: less swayed by
the shared machine's load), peak memory, the report's size and its verdicts.

Writes ``benchmarks/results/imu_report.md``.
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

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from exports import SIM_RATE, SIM_SECONDS, _simulate_file  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"
WORK = Path("/tmp/noisevar-imu-report-bench")


def timed(cmd: list[str]) -> tuple[float, float, float]:
    """Wall s, CPU s (user + system) and peak MB of ``cmd`` under ``/usr/bin/time -v``."""
    start = time.perf_counter()
    proc = subprocess.run(["/usr/bin/time", "-v", *cmd], capture_output=True, text=True)
    wall = time.perf_counter() - start
    if proc.returncode != 0:
        raise RuntimeError(f"{cmd} failed: {proc.stderr[-2000:]}")
    user = float(re.search(r"User time \(seconds\): ([\d.]+)", proc.stderr)[1])
    system = float(re.search(r"System time \(seconds\): ([\d.]+)", proc.stderr)[1])
    rss = int(re.search(r"Maximum resident set size \(kbytes\): (\d+)", proc.stderr)[1])
    return wall, user + system, rss / 1024


def run(cwd: Path, npy: Path, out: Path) -> tuple[float, float, float]:
    """Wall s, CPU s and peak MB of the export run by the checkout at ``cwd``."""
    cols = ["--accel", "col0", "col1", "col2", "--gyro", "col3", "col4", "col5"]
    cmd = [sys.executable, "-m", "noisevar", "imu", str(npy), "--rate", f"{SIM_RATE:g}", *cols]
    cmd += ["--export", "all", "--out", str(out), "--format", "json"]
    here = os.getcwd()
    os.chdir(cwd)  # python -m noisevar imports the package of the working directory
    try:
        return timed(cmd)
    finally:
        os.chdir(here)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--main", type=Path, required=True, help="a checkout without the report")
    ap.add_argument("--runs", type=int, default=3)
    args = ap.parse_args()
    load0 = os.getloadavg()[0]
    shutil.rmtree(WORK, ignore_errors=True)
    WORK.mkdir(parents=True)
    npy = WORK / "imu.npy"
    _simulate_file(npy)
    times: dict[str, list[tuple[float, float, float]]] = {
        "with report": [],
        "without (before)": [],
    }
    for i in range(args.runs):
        times["with report"].append(run(ROOT, npy, WORK / f"new{i}"))
        times["without (before)"].append(run(args.main, npy, WORK / f"old{i}"))
        print(i, {k: v[-1] for k, v in times.items()}, flush=True)
    report = (WORK / "new0" / "report.html").read_text(encoding="utf-8")
    verdicts = report.count("Verdict, ")
    rows = []
    for label, runs in times.items():
        walls, cpus = sorted(r[0] for r in runs), sorted(r[1] for r in runs)
        mid = len(runs) // 2
        rows.append(
            f"| {label} | {walls[mid]:.1f} s ({walls[0]:.1f}-{walls[-1]:.1f}) | "
            f"{cpus[mid]:.1f} s ({cpus[0]:.1f}-{cpus[-1]:.1f}) | {max(r[2] for r in runs):.0f} MB |"
        )
    shutil.rmtree(WORK, ignore_errors=True)
    load = f"{load0:.1f} at the start, {os.getloadavg()[0]:.1f} at the end"
    lines = [
        "# report.html: what it costs (issue 27, item 5)",
        "",
        f"Command: `nice -n 10 python benchmarks/imu_report.py --main {args.main} --runs "
        f"{args.runs}` on {platform.machine()}, {os.cpu_count()} cores, Python "
        f"{platform.python_version()}; 1-minute load average {load} (other jobs share the "
        f"machine). The record: {SIM_SECONDS:g} s at {SIM_RATE:g} Hz, 6 axes "
        "(benchmarks/exports.py part b).",
        "",
        "| `noisevar imu FILE --export all --out DIR` | wall, median (range) | CPU (user + "
        "system), median (range) | peak memory |",
        "|---|---|---|---|",
        *rows,
        "",
        f"report.html: {len(report) / 1e6:.1f} MB (plotly.js embedded once, 6 Allan figures), "
        f"{verdicts} verdicts (one per column).",
        "",
    ]
    RESULTS.mkdir(parents=True, exist_ok=True)
    (RESULTS / "imu_report.md").write_text("\n".join(lines))
    print("\n".join(lines))


if __name__ == "__main__":
    main()

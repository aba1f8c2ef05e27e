"""``noisevar imu --export all``: CPU per run, and how many estimates it makes (issue 26 item 5).

    python benchmarks/imu_export_cpu.py [--rounds 3] [--against DIR]

The record is ``exports.py`` part (b)'s: allan_variance_ros's simulator configuration,
11000 s at 400 Hz, 6 axes (a 211 MB ``.npy``, written once to a temporary directory). Each
run is a fresh process (``nice -n 10``) that times ``noisevar imu FILE --rate 400 --accel ...
--gyro ... --export all --out DIR --format json`` (process CPU time, every thread, and wall)
and counts the calls of :func:`noisevar.estimate` (the method-auto estimate of a whole
column: before pages26c, ``inertial_noise`` made one per axis for its regime warning and
the files' verdicts another). ``--against DIR`` alternates each round with the package
under ``DIR`` (``PYTHONPATH``; e.g. ``git archive`` of main) and checks that both give the
same fits (the JSON's ``columns``). Writes ``benchmarks/results/imu_export_cpu.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import statistics
import subprocess
import sys
import tempfile
from pathlib import Path

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent
OUT = HERE / "results" / "imu_export_cpu.md"

#: One run, in a fresh process: the CPU and wall seconds, the estimates made, the fits.
RUN = r"""
import contextlib, io, json, sys, tempfile, time
import noisevar.estimators
from noisevar.cli import main

calls = []
real = noisevar.estimators.estimate
def counted(*a, **k):
    calls.append(1)
    return real(*a, **k)
noisevar.estimators.estimate = counted
argv = ["imu", sys.argv[1], "--rate", "400", "--accel", "col0", "col1", "col2",
        "--gyro", "col3", "col4", "col5", "--export", "all", "--out", tempfile.mkdtemp(),
        "--format", "json"]
c0, t0 = time.process_time(), time.perf_counter()
with contextlib.redirect_stdout(io.StringIO()) as buf:
    assert main(argv) == 0
cpu, wall = time.process_time() - c0, time.perf_counter() - t0
cols = json.loads(buf.getvalue())["columns"]
print(json.dumps({"cpu": cpu, "wall": wall, "estimates": len(calls), "columns": cols,
                  "package": noisevar.__file__}))
"""


def _run(path: Path, package: Path) -> dict:
    env = dict(os.environ, PYTHONPATH=str(package))
    cmd = ["nice", "-n", "10", sys.executable, "-c", RUN, str(path)]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True, cwd="/")
    res = json.loads(out.stdout.strip().splitlines()[-1])
    res["load"] = os.getloadavg()[0]
    return res


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--against", help="a directory holding another noisevar package")
    args = ap.parse_args()
    sys.path.insert(0, str(HERE))
    from exports import _simulate_file

    packages = {"this checkout": ROOT}
    if args.against:
        packages["against"] = Path(args.against).resolve()
    runs: dict[str, list[dict]] = {k: [] for k in packages}
    with tempfile.TemporaryDirectory() as tmp:
        path = Path(tmp) / "sim_imu.npy"
        _simulate_file(path)
        for r in range(args.rounds):
            for name, pkg in packages.items():
                runs[name].append(_run(path, pkg))
                last = runs[name][-1]
                said = f"CPU {last['cpu']:.2f} s, wall {last['wall']:.1f} s"
                print(f"round {r} {name}: {said}, {last['estimates']} estimates", flush=True)
    lines = [
        "# `noisevar imu --export all`: CPU per run and estimates made "
        "(benchmarks/imu_export_cpu.py)",
        "",
        "allan_variance_ros's simulator record (exports.py part b: 11000 s at 400 Hz, 6 axes, "
        f"211 MB .npy); {args.rounds} rounds of fresh processes (`nice -n 10`), alternated.",
        "",
        "| code | CPU s per run (median; each) | wall s (median) | estimates per run "
        "| load (1 min) |",
        "|---|---|---|---|---|",
    ]
    for name, rs in runs.items():
        cpu = [x["cpu"] for x in rs]
        lines.append(
            f"| {name} ({Path(rs[0]['package']).parent.parent}) | {statistics.median(cpu):.2f} "
            f"({', '.join(f'{c:.2f}' for c in cpu)}) | "
            f"{statistics.median(x['wall'] for x in rs):.1f} | "
            f"{', '.join(sorted({str(x['estimates']) for x in rs}))} | "
            f"{min(x['load'] for x in rs):.1f}-{max(x['load'] for x in rs):.1f} |"
        )
    if args.against:
        same = all(
            a["columns"] == b["columns"]
            for a, b in zip(runs["this checkout"], runs["against"], strict=True)
        )
        lines += ["", f"The same fits (every column's JSON, both codes, every round): {same}."]
    text = "\n".join(lines) + "\n"
    print(text)
    OUT.write_text(text, encoding="utf-8")


if __name__ == "__main__":
    main()

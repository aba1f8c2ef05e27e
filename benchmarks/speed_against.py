"""``auto``'s wall and CPU time on speed.py's two records, alternated against another checkout.

    python benchmarks/speed_against.py --against DIR [--rounds 3] [--repeats 5]

Each round runs this checkout and the ``noisevar`` package under ``DIR`` (``PYTHONPATH``;
e.g. a ``git worktree`` of main) in fresh processes, one after the other. Per process:
the best wall time and the least CPU time (every thread) over ``repeats`` runs of
``auto`` on ``speed.py``'s ``auto (motion)`` record and on white noise (1e6 samples),
each over one third-order ``lfilter`` pass timed just before it. Reports the medians
over the rounds and the load average beside each round. Writes
``benchmarks/results/speed_against.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
RECORDS = ("auto (motion)", "auto (white)")


def _measure(repeats: int) -> dict[str, list[float]]:
    """``[wall, lfilter wall, CPU, lfilter CPU]`` per record (best / least of ``repeats``)."""
    from scipy import signal

    import noisevar

    sys.path.insert(0, str(HERE))
    from speed import motion_record

    n = 1_000_000
    rng = np.random.default_rng(0)
    data = {RECORDS[0]: motion_record(n), RECORDS[1]: rng.normal(size=n)}
    z = noisevar.generate("gps-circle", n=n, seed=3).measured
    b, a = signal.butter(3, 0.05)
    out = {}
    for name, x in data.items():
        noisevar.estimate(x, method="auto")  # warm caches
        best = [np.inf] * 4
        for _ in range(repeats):
            t0, c0 = time.perf_counter(), time.process_time()
            signal.lfilter(b, a, z)
            t1, c1 = time.perf_counter(), time.process_time()
            noisevar.estimate(x, method="auto")
            t2, c2 = time.perf_counter(), time.process_time()
            now = [t2 - t1, t1 - t0, c2 - c1, c1 - c0]
            best = [min(u, v) for u, v in zip(best, now, strict=True)]
        out[name] = best
    return out


def _child(path: str, repeats: int, nice: int) -> dict[str, list[float]]:
    env = dict(os.environ, PYTHONPATH=path)
    cmd = ["nice", "-n", str(nice), sys.executable, __file__, "--child", "--repeats", str(repeats)]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def main(argv: list[str] | None = None) -> int:
    """Run the comparison and print Markdown."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--against", help="a directory holding another noisevar package")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--nice", type=int, default=0)
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(_measure(args.repeats)))
        return 0
    if not args.against:
        ap.error("--against DIR is required")
    runs: dict[str, list] = {"this": [], "against": []}
    loads = []
    for _ in range(args.rounds):
        for who, path in (("this", str(HERE.parent)), ("against", args.against)):
            runs[who].append(_child(path, args.repeats, args.nice))
        loads.append(os.getloadavg()[0])
    lines = [
        "### `auto` wall and CPU time, alternated (`python benchmarks/speed_against.py`)",
        "",
        f"Medians over {args.rounds} rounds (fresh processes, best / least of "
        f"{args.repeats} runs each), 1e6 samples, {os.cpu_count()} cores; against "
        f"`{args.against}`; load average after each round: "
        + ", ".join(f"{x:.1f}" for x in loads)
        + ".",
        "",
        "| record | checkout | wall ms | x lfilter wall | CPU ms | x lfilter CPU |",
        "|---|---|---|---|---|---|",
    ]
    for rec in RECORDS:
        for who, rs in runs.items():
            wall, lw, cpu, lc = (float(np.median([r[rec][i] for r in rs])) for i in range(4))
            lines.append(
                f"| {rec} | {who} | {1000 * wall:.1f} | {wall / lw:.1f} | "
                f"{1000 * cpu:.1f} | {cpu / lc:.1f} |"
            )
    text = "\n".join(lines) + "\n"
    print(text)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "speed_against.md").write_text(text)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())

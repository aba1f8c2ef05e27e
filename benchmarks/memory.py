"""Bounded command-line memory by default (issue 29 item 6): a 1e8-sample ``.npy``, no flag.

    nice -n 10 python benchmarks/memory.py [--n 100000000] [--keep]

A ``--n``-sample float64 ``.npy`` (800 MB at 1e8: a slow sinusoid plus white noise of std
0.1, seeded; written in pieces by ``benchmarks/stream.py``'s writer into
``benchmarks/.cache``, deleted unless ``--keep``) is estimated twice, each in a child
process under ``/usr/bin/time -v``:

1. ``python -m noisevar estimate big.npy --format json``: no flag (the file is over
   :data:`noisevar.stream.STREAM_BYTES`, so it is streamed);
2. ``noisevar.estimate(np.load(big.npy))``: the whole record in memory.

Peak resident memory of each whole process (interpreter and imports included), wall time,
and the relative difference of the variance, its interval and ``n_used``.
Writes ``benchmarks/results/memory.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import re
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "benchmarks"))

from stream import CACHE, _warm, write_big  # noqa: E402

from noisevar.stream import STREAM_BYTES  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"
TARGET_MB = 256
IN_MEMORY = (
    "import json, sys, numpy as np, noisevar as nv\n"
    "r = nv.estimate(np.load(sys.argv[1]))\n"
    "print(json.dumps({'variance': r.variance, 'ci95_low': r.ci95[0], 'ci95_high': r.ci95[1],"
    " 'n_used': r.n_used, 'notes': r.notes}))\n"
)


def _timed(cmd: list[str]) -> tuple[dict, float, float]:
    """A child's JSON, wall seconds and peak RSS (MB, from ``/usr/bin/time -v``)."""
    t0 = time.perf_counter()
    out = subprocess.run(["/usr/bin/time", "-v", *cmd], capture_output=True, text=True, cwd=ROOT)
    wall = time.perf_counter() - t0
    if out.returncode:
        raise SystemExit(f"{' '.join(cmd)} failed: {out.stderr[-2000:]}")
    m = re.search(r"Maximum resident set size \(kbytes\): (\d+)", out.stderr)
    return json.loads(out.stdout), wall, int(m.group(1)) / 1024 if m else float("nan")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=100_000_000)
    ap.add_argument("--keep", action="store_true")
    args = ap.parse_args()
    CACHE.mkdir(exist_ok=True)
    path = CACHE / f"big_{args.n}.npy"
    if not (path.exists() and path.stat().st_size == 128 + 8 * args.n):
        write_big(args.n, path)
    _warm(path)
    load = os.getloadavg()[0]
    cli = [sys.executable, "-m", "noisevar", "estimate", str(path), "--format", "json"]
    streamed, s_wall, s_rss = _timed(cli)
    memory, m_wall, m_rss = _timed([sys.executable, "-c", IN_MEMORY, str(path)])
    if not args.keep:
        path.unlink()

    def rel(a: float, b: float) -> float:
        return abs(a / b - 1.0) if b else abs(a - b)

    diff = max(
        rel(streamed["variance"], memory["variance"]),
        *(rel(streamed[k], memory[k]) for k in ("ci95_low", "ci95_high")),
    )
    same_n = streamed["n_used"] == memory["n_used"]
    met = "met" if s_rss < TARGET_MB else "**NOT met**"
    lines = [
        "# Bounded command-line memory by default (issue 29, item 6)",
        "",
        f"Command: `nice -n 10 python benchmarks/memory.py --n {args.n}` on "
        f"{platform.machine()}, {os.cpu_count()} cores, Python {platform.python_version()}; "
        f"1-minute load average at start {load:.1f}.",
        "",
        f"File: {args.n:,} float64 samples, {path.name} ({(128 + 8 * args.n) / 1e6:,.0f} MB); "
        f"streamed without a flag above `noisevar.stream.STREAM_BYTES` = "
        f"{STREAM_BYTES / 2**20:.0f} MiB. Peak RSS of the whole child process "
        "(`/usr/bin/time -v`, interpreter and imports included).",
        "",
        "| run | peak RSS (MB) | wall (s) | variance | first note |",
        "|---|---|---|---|---|",
        f"| `noisevar estimate big.npy` (no flag) | {s_rss:,.0f} | {s_wall:.1f} | "
        f"{streamed['variance']:.10g} | {streamed['notes'][0]} |",
        f"| `noisevar.estimate(np.load(big.npy))` (in memory) | {m_rss:,.0f} | {m_wall:.1f} | "
        f"{memory['variance']:.10g} | {memory['notes'][0]} |",
        "",
        f"Target: peak RSS under {TARGET_MB} MB with no flag: {met} ({s_rss:,.0f} MB). "
        f"Largest relative difference of the variance and its interval against the in-memory "
        f"estimate: {diff:.1e}; n_used equal: {same_n}.",
        "",
    ]
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "memory.md").write_text("\n".join(lines), encoding="utf-8")
    print("\n".join(lines))


if __name__ == "__main__":
    main()

"""Hostile-input benchmark (issue 15): memory on a big CSV, refusal time of a huge file, fuzz.

Writes ``benchmarks/results/hostile.md``. The big files are built in a temporary folder
and deleted afterwards (never committed):

* peak RSS of ``noisevar estimate`` on a ~500 MB CSV (target < 2 GB), for this tree and,
  with ``--baseline PATH``, for another checkout (the code before the fix);
* time to refuse a 5 GB file (sparse, made with ``truncate``; target < 1 s);
* the CLI fuzz suite of ``tests/test_fuzz_cli.py``: cases, classes, failures.

Run: ``nice -n 10 python benchmarks/hostile.py [--mb 500] [--baseline /work/main]``.
"""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "benchmarks" / "results" / "hostile.md"


def write_csv(path: Path, megabytes: float, seed: int = 0) -> int:
    """A two-column CSV (``a,b``: random walks plus noise of std 1) of about ``megabytes``.

    Four distinct blocks of a million rows are formatted once and cycled (formatting is
    the slow part; the loader's memory does not depend on the values).
    """
    rng = np.random.default_rng(seed)
    blocks = []
    for _ in range(4):
        walk = np.cumsum(rng.normal(0, 0.01, (1_000_000, 2)), axis=0)
        z = walk + rng.normal(0, 1, walk.shape)
        blocks.append("\n".join(f"{a:.6f},{b:.6f}" for a, b in z) + "\n")
    rows = 0
    with path.open("w") as fh:
        fh.write("a,b\n")
        while fh.tell() < megabytes * 1e6:
            fh.write(blocks[(rows // 1_000_000) % 4])
            rows += 1_000_000
    return rows


def peak_rss(cmd: list[str], pythonpath: Path) -> tuple[float, float, int, str]:
    """Peak RSS (GB), wall time (s), exit status and last stdout/stderr line of ``cmd``."""
    env = {**os.environ, "PYTHONPATH": str(pythonpath)}
    wrapper = (
        "import resource, subprocess, sys, time; t0 = time.perf_counter(); "
        "r = subprocess.run(sys.argv[1:], capture_output=True, text=True); "
        "dt = time.perf_counter() - t0; "
        "rss = resource.getrusage(resource.RUSAGE_CHILDREN).ru_maxrss; "
        "last = ((r.stdout + r.stderr).strip().splitlines() or [''])[-1][:120]; "
        "print(rss, dt, r.returncode, last, sep='\\t')"
    )
    out = subprocess.run(
        [sys.executable, "-c", wrapper, *cmd], capture_output=True, text=True, env=env, cwd="/"
    ).stdout.strip()
    rss, dt, code, last = (out.split("\t") + ["", "", "", ""])[:4]
    return int(rss) / 1024**2, float(dt), int(code), last


def refuse_time(path: Path) -> tuple[float, str]:
    """Seconds ``noisevar estimate`` takes to refuse ``path``, and its message."""
    t0 = time.perf_counter()
    r = subprocess.run(
        [sys.executable, "-m", "noisevar", "estimate", str(path)],
        capture_output=True,
        text=True,
        env={**os.environ, "PYTHONPATH": str(ROOT)},
    )
    return time.perf_counter() - t0, r.stderr.strip()


def refuse_in_process(path: Path) -> float:
    """Seconds :func:`noisevar.io.load_table` takes to refuse ``path`` (no start-up cost)."""
    sys.path.insert(0, str(ROOT))
    from noisevar.errors import NoisevarError
    from noisevar.io import load_table

    t0 = time.perf_counter()
    try:
        load_table(path)
    except NoisevarError:
        pass
    return time.perf_counter() - t0


def fuzz_summary(tmp: Path) -> tuple[int, list[str], list[tuple[list[str], str]], float]:
    sys.path.insert(0, str(ROOT / "tests"))
    sys.path.insert(0, str(ROOT))
    import test_fuzz_cli as fz

    cases = list(fz._cases(tmp))
    t0 = time.perf_counter()
    fails = [(argv, why) for _, argv in cases if (why := fz.check_case(argv))]
    return len(cases), sorted({c for c, _ in cases}), fails, time.perf_counter() - t0


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mb", type=float, default=500.0, help="size of the big CSV (MB)")
    ap.add_argument("--baseline", type=Path, help="another checkout to measure too")
    ap.add_argument(
        "--method", nargs="+", default=["rice", "auto"], help="estimators for the big CSV"
    )
    args = ap.parse_args()
    lines = ["# Hostile input (issue 15)", ""]
    lines.append(f"Machine: {os.cpu_count()} cores shared with other jobs; `nice -n 10`.")
    lines.append("")
    with tempfile.TemporaryDirectory(prefix="noisevar-hostile-") as td:
        tmp = Path(td)
        big = tmp / "big.csv"
        t0 = time.perf_counter()
        rows = write_csv(big, args.mb)
        size = big.stat().st_size
        print(f"wrote {size / 1e6:.0f} MB, {rows:,} rows in {time.perf_counter() - t0:.0f} s")
        lines += [
            f"## Peak memory of `noisevar estimate` on a {size / 1e6:.0f} MB CSV",
            "",
            f"{rows:,} rows of `a,b` (first column estimated); peak RSS of the process "
            "(`ru_maxrss`). Target: under 2 GB.",
            "",
            "| code | method | peak RSS (GB) | wall (s) | exit | last line |",
            "|---|---|---:|---:|---:|---|",
        ]
        trees = [("this branch", ROOT)]
        if args.baseline:
            trees.append((f"baseline ({args.baseline})", args.baseline))
        for method in args.method:
            cmd = [sys.executable, "-m", "noisevar", "estimate", str(big), "--method", method]
            for label, tree in trees:
                gb, dt, code, last = peak_rss(cmd, tree)
                print(label, method, f"{gb:.2f} GB", f"{dt:.0f} s", code, last)
                lines.append(f"| {label} | {method} | {gb:.2f} | {dt:.0f} | {code} | {last} |")
        big.unlink()
        huge = tmp / "huge.csv"
        with huge.open("wb") as fh:
            fh.truncate(5 * 10**9)  # sparse: no disk used
        cli_s, msg = refuse_time(huge)
        api_s = refuse_in_process(huge)
        huge.unlink()
        print(f"5 GB refused: CLI {cli_s:.2f} s, load_table {api_s * 1e3:.2f} ms")
        lines += [
            "",
            "## A 5 GB file (sparse) is refused before it is read",
            "",
            "| path | time | target |",
            "|---|---:|---|",
            f"| `noisevar estimate` (process start included) | {cli_s:.2f} s | < 1 s |",
            f"| `load_table` in process | {api_s * 1e3:.2f} ms | |",
            "",
            f"Message: `{msg}`",
        ]
        n, classes, fails, fuzz_s = fuzz_summary(tmp)
    print(f"fuzz: {n} cases, {len(fails)} failures, {fuzz_s:.0f} s")
    lines += [
        "",
        "## CLI fuzz suite (`tests/test_fuzz_cli.py`)",
        "",
        f"{n} cases in {len(classes)} classes ({', '.join(classes)}), run in-process in "
        f"{fuzz_s:.0f} s: **{len(fails)} failures** (a failure is any exit other than 2 with "
        "one line or 0 with strict JSON and finite, non-negative variances).",
    ]
    for argv, why in fails[:10]:
        lines.append(f"- `{' '.join(argv)[:120]}`: {why[:200]}")
    OUT.write_text("\n".join(lines) + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()

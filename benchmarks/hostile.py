"""Hostile-input benchmark (issue 15): memory on a big CSV, refusal time of a huge file, fuzz,
and the cost of ``import noisevar`` (issue 17's memory budget).

Writes ``benchmarks/results/hostile.md``. The big files are built in a temporary folder
and deleted afterwards (never committed):

* ``memory``: peak RSS of ``noisevar estimate`` on a ~500 MB CSV (target < 2 GB), for this
  tree and, with ``--baseline PATH``, for another checkout (the code before the fix);
* ``refusal``: wall time of ``noisevar estimate`` (a new process, start-up included)
  refusing a 5 GB CSV and a 5 GB ``.npy`` (sparse, made with ``truncate``; target < 1 s),
  median of ``--runs`` runs;
* ``imports``: wall time and peak RSS of ``import noisevar`` and of the estimate path,
  each in a new process, median of ``--runs`` runs;
* ``fuzz``: the CLI fuzz suite of ``tests/test_fuzz_cli.py``: cases, classes, failures.

``--parts`` reruns some sections and keeps the others of the existing results file.
Run: ``nice -n 10 python benchmarks/hostile.py [--mb 500] [--baseline /work/main]
[--parts refusal imports]``.
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


#: Heavy modules reported as loaded (or not) after each import case.
HEAVY = (
    "numpy",
    "numba",
    "pandas",
    "pyarrow",
    "allantools",
    "statsmodels",
    "dask",
    "plotly",
    "scipy.stats",
    "scipy.signal",
)
#: (label, code run in a new process) for the ``imports`` section.
IMPORT_CASES = (
    ("interpreter alone (`python -c pass`)", "pass"),
    ("`import noisevar`", "import noisevar"),
    ("estimate path loaded (`from noisevar import estimate`)", "from noisevar import estimate"),
    (
        "`estimate` of 1e6 white samples, diagnostics on",
        "import numpy as np; from noisevar import estimate; "
        "estimate(np.random.default_rng(0).normal(size=10**6))",
    ),
    (
        "every public name loaded",
        "import noisevar; [getattr(noisevar, n) for n in noisevar.__all__]",
    ),
)
#: Section keys, in file order, and the heading each starts with.
SECTIONS = {
    "memory": "## Peak memory",
    "refusal": "## A 5 GB file",
    "imports": "## Import",
    "fuzz": "## CLI fuzz",
}


def machine_note() -> str:
    """When, and the machine's load (``uptime``) at the time."""
    up = subprocess.run(["uptime"], capture_output=True, text=True, check=False).stdout.strip()
    when = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
    return f"Measured {when}; `uptime`: `{up}`."


def repeat(cmd: list[str], tree: Path, runs: int) -> tuple[list[float], list[float], int, str]:
    """Wall times (s) and peak RSS (MB) of ``cmd`` run ``runs`` times, each a new process."""
    walls, rss, code, last = [], [], 0, ""
    for _ in range(runs):
        gb, dt, code, last = peak_rss(cmd, tree)
        walls.append(dt)
        rss.append(gb * 1024)
    return walls, rss, code, last


def _spread(values: list[float], fmt: str) -> str:
    return f"{np.median(values):{fmt}} ({min(values):{fmt}}-{max(values):{fmt}})"


def memory_section(tmp: Path, args: argparse.Namespace, trees: list) -> list[str]:
    """Peak RSS of ``noisevar estimate`` on a big CSV, per method and tree."""
    big = tmp / "big.csv"
    t0 = time.perf_counter()
    rows = write_csv(big, args.mb)
    size = big.stat().st_size
    print(f"wrote {size / 1e6:.0f} MB, {rows:,} rows in {time.perf_counter() - t0:.0f} s")
    lines = [
        f"{SECTIONS['memory']} of `noisevar estimate` on a {size / 1e6:.0f} MB CSV",
        "",
        machine_note(),
        "",
        f"{rows:,} rows of `a,b` (first column estimated); peak RSS of the process "
        "(`ru_maxrss`). Target: under 2 GB.",
        "",
        "| code | method | peak RSS (GB) | wall (s) | exit | last line |",
        "|---|---|---:|---:|---:|---|",
    ]
    for method in args.method:
        cmd = [sys.executable, "-m", "noisevar", "estimate", str(big), "--method", method]
        for label, tree in trees:
            gb, dt, code, last = peak_rss(cmd, tree)
            print(label, method, f"{gb:.2f} GB", f"{dt:.0f} s", code, last)
            lines.append(f"| {label} | {method} | {gb:.2f} | {dt:.0f} | {code} | {last} |")
    big.unlink()
    return lines


def refusal_section(tmp: Path, trees: list, runs: int) -> list[str]:
    """Wall time of ``noisevar estimate`` refusing a 5 GB CSV and ``.npy`` (sparse files)."""
    lines = [
        f"{SECTIONS['refusal']} (sparse) is refused before it is read",
        "",
        machine_note(),
        "",
        f"`noisevar estimate FILE` in a new process (interpreter start-up included), {runs} "
        "runs: median (min-max) wall time and peak RSS. Target: under 1 s. A `.npy` over "
        "the cap is streamed by method auto (issue 17), so it is timed with `--method rice`.",
        "",
        "| file | code | wall (s) | peak RSS (MB) | exit | in process, `load_table` |",
        "|---|---|---:|---:|---:|---:|",
    ]
    message = ""
    # a .npy over the cap is streamed by method auto (issue 17): refused for other methods
    for kind, head, flags in (
        ("csv", b"a,b\n1,2\n", []),
        ("npy", b"\x93NUMPY", ["--method", "rice"]),
    ):
        huge = tmp / f"huge.{kind}"
        huge.write_bytes(head)
        os.truncate(huge, 5 * 10**9)  # sparse: no disk used
        api_ms = refuse_in_process(huge) * 1e3
        cmd = [sys.executable, "-m", "noisevar", "estimate", str(huge), *flags]
        shown = " ".join([f"5 GB .{kind}", *flags])
        for label, tree in trees:
            walls, rss, code, last = repeat(cmd, tree, runs)
            message = message or last
            print(f"{shown} refused ({label}): {_spread(walls, '.3f')} s, exit {code}")
            lines.append(
                f"| {shown} | {label} | {_spread(walls, '.3f')} | {_spread(rss, '.0f')} "
                f"| {code} | {api_ms:.2f} ms |"
            )
        huge.unlink()
    return [*lines, "", f"Message: `{message}`"]


def imports_section(trees: list, runs: int) -> list[str]:
    """Wall time and peak RSS of ``import noisevar`` and of the estimate path."""
    lines = [
        f"{SECTIONS['imports']} cost: `import noisevar` and the estimate path",
        "",
        machine_note(),
        "",
        f"Each case in a new process, {runs} runs: median (min-max) wall time (start-up "
        "included) and peak RSS (`ru_maxrss`); the heavy modules loaded afterwards.",
        "",
        "| case | code | wall (s) | peak RSS (MB) | heavy modules loaded |",
        "|---|---|---:|---:|---|",
    ]
    report = f"; import sys; print(' '.join(m for m in {HEAVY!r} if m in sys.modules) or 'none')"
    for label, code in IMPORT_CASES:
        for tree_label, tree in trees:
            cmd = [sys.executable, "-c", code + report]
            walls, rss, status, last = repeat(cmd, tree, runs)
            loaded = last if status == 0 else f"exit {status}: {last}"
            print(f"{label} ({tree_label}): {_spread(walls, '.2f')} s, {_spread(rss, '.0f')} MB")
            lines.append(
                f"| {label} | {tree_label} | {_spread(walls, '.2f')} | {_spread(rss, '.0f')} "
                f"| {loaded} |"
            )
    return lines


def fuzz_section(tmp: Path) -> list[str]:
    """The CLI fuzz suite's cases, classes and failures."""
    n, classes, fails, fuzz_s = fuzz_summary(tmp)
    print(f"fuzz: {n} cases, {len(fails)} failures, {fuzz_s:.0f} s")
    lines = [
        f"{SECTIONS['fuzz']} suite (`tests/test_fuzz_cli.py`)",
        "",
        machine_note(),
        "",
        f"{n} cases in {len(classes)} classes ({', '.join(classes)}), run in-process in "
        f"{fuzz_s:.0f} s: **{len(fails)} failures** (a failure is any exit other than 2 with "
        "one line or 0 with strict JSON and finite, non-negative variances).",
    ]
    return lines + [f"- `{' '.join(argv)[:120]}`: {why[:200]}" for argv, why in fails[:10]]


def previous_sections() -> dict[str, str]:
    """The sections of the existing results file, by key (kept when not rerun)."""
    if not OUT.exists():
        return {}
    found: dict[str, str] = {}
    for chunk in OUT.read_text().split("\n## ")[1:]:
        text = "## " + chunk.strip()
        for key, heading in SECTIONS.items():
            if text.startswith(heading):
                found[key] = text
    return found


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--mb", type=float, default=500.0, help="size of the big CSV (MB)")
    ap.add_argument("--baseline", type=Path, help="another checkout to measure too")
    ap.add_argument(
        "--method", nargs="+", default=["rice", "auto"], help="estimators for the big CSV"
    )
    ap.add_argument("--parts", nargs="+", choices=list(SECTIONS), default=list(SECTIONS))
    ap.add_argument("--runs", type=int, default=5, help="runs per timed case (median)")
    args = ap.parse_args()
    trees = [("this branch", ROOT)]
    if args.baseline:
        trees.append((f"baseline ({args.baseline})", args.baseline))
    sections = previous_sections()
    with tempfile.TemporaryDirectory(prefix="noisevar-hostile-") as td:
        tmp = Path(td)
        made = {
            "memory": lambda: memory_section(tmp, args, trees),
            "refusal": lambda: refusal_section(tmp, trees, args.runs),
            "imports": lambda: imports_section(trees, args.runs),
            "fuzz": lambda: fuzz_section(tmp),
        }
        for key in args.parts:
            sections[key] = "\n".join(made[key]())
    lines = ["# Hostile input (issue 15)", ""]
    lines.append(f"Machine: {os.cpu_count()} cores shared with other jobs; `nice -n 10`.")
    lines += [part for key in SECTIONS if key in sections for part in ("", sections[key])]
    OUT.write_text("\n".join(lines).replace("\n\n\n", "\n\n") + "\n")
    print(f"wrote {OUT}")


if __name__ == "__main__":
    main()

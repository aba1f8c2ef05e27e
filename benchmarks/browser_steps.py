"""Browser CPU-s per step of the load path, this tree against another commit (issue 29).

One Chromium (Playwright) drives ``--reps`` sessions one after another on a fresh
``noisevar dashboard`` (after one warm-up session), along ``benchmarks/load.py``'s path:
open the Signal page, upload a 20,000-sample CSV, Estimator, two Γ_amp steps, Compare to
its last row, Noise model. For each step it records the CPU-s of its own Chromium (not
other jobs' browsers) and of the server (``benchmarks/cpu_split.py``'s sampler), from the
step's action to 0.5 s after the page settled. The same is run on ``--base`` (``git
archive`` into a temporary folder, served from there with the same interpreter and this
tree's driver), alternating ``--rounds`` times, so both see the same machine. CPU-s is far
less sensitive to other jobs than wall time; the median over every session of a tree is
reported. Run from the repository root::

    python benchmarks/browser_steps.py [--base main] [--reps 3] [--rounds 2]

Writes ``benchmarks/results/browser_steps.md``.
"""

from __future__ import annotations

import argparse
import asyncio
import json
import os
import platform
import statistics
import subprocess
import sys
import tarfile
import tempfile
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
OUT = ROOT / "benchmarks" / "results" / "browser_steps.md"
STEPS = ("open", "upload", "estimator", "slider1", "slider2", "compare", "noise model")


async def one_session(page, base: str, r: int, sampler, rows: dict) -> None:
    """One session's steps; appends [browser CPU-s, server CPU-s] to ``rows[step]``."""
    import browser_profile as bp
    import load

    actions = {
        "open": lambda: bp.opened(page, base),
        "upload": lambda: bp.upload(page, load.record_csv(123 + r)),
        "estimator": lambda: load.go_to(page, "Estimator", '[data-testid="stMetricValue"]'),
        "slider1": lambda: bp.slide(page),
        "slider2": lambda: bp.slide(page),
        "compare": lambda: load.open_compare(page),
        "noise model": lambda: load.go_to(page, "Noise model"),
    }
    for step in STEPS:
        c0 = sampler.snapshot()
        await actions[step]()
        await asyncio.sleep(0.5)
        c1 = sampler.snapshot()
        rows[step].append([c1["browser"] - c0["browser"], c1["server"] - c0["server"]])


async def sessions(reps: int) -> dict[str, list[list[float]]]:
    """``reps`` sessions on a fresh server of the tree in the current directory (the
    driver is this file's tree): step -> [browser CPU-s, server CPU-s] per session."""
    import load
    from cpu_split import CpuSampler
    from playwright.async_api import async_playwright

    proc, base = load.start_server({})
    sampler = CpuSampler(proc.pid, os.getpid(), own_browser=True).start()
    rows: dict[str, list[list[float]]] = {k: [] for k in STEPS}
    try:
        async with async_playwright() as pw:
            browser = await pw.chromium.launch(executable_path=load.CHROMIUM, args=load.CHROME_ARGS)
            await load.wave(browser, base, 1, False, 10_000)  # warm the server
            for r in range(reps):
                ctx = await browser.new_context(viewport={"width": 1400, "height": 900})
                page = await ctx.new_page()
                await one_session(page, base, r, sampler, rows)
                await ctx.close()
            await browser.close()
    finally:
        sampler.stop()
        os.killpg(proc.pid, 15)
        proc.wait(timeout=60)
    return rows


def run_tree(tree: Path, reps: int) -> dict[str, list[list[float]]]:
    """:func:`sessions` in a child process whose working directory is ``tree``."""
    out = subprocess.run(
        [sys.executable, str(Path(__file__).resolve()), "--child", str(reps)],
        cwd=tree,
        capture_output=True,
        text=True,
        check=True,
    ).stdout
    return json.loads(out.strip().splitlines()[-1])


def med(values: list[list[float]], i: int) -> float:
    return statistics.median(v[i] for v in values)


def report(args, trees: dict[str, dict[str, list[list[float]]]], loads: list[float]) -> str:
    head = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    ).stdout.strip()
    lines = [
        "# Browser CPU-s per step, this tree against another commit "
        "(`benchmarks/browser_steps.py`)",
        "",
        f"{platform.node()}: {os.cpu_count()} cores, one headless Chromium and the dashboard on "
        f"the same cores; this tree at {head} (with its uncommitted changes) against "
        f"`{args.base}`, alternated {args.rounds} times, {args.reps} sessions each; "
        f"1-minute load average {min(loads):.1f}-{max(loads):.1f} (other jobs share the "
        "machine: CPU-s moves with them far less than wall time).",
        "",
        f"Command: `python benchmarks/browser_steps.py --base {args.base} --reps {args.reps} "
        f"--rounds {args.rounds}`",
        "",
        "Median over every session (browser CPU-s: the benchmark's own Chromium, from the "
        "action to 0.5 s after the page settled; server CPU-s beside it):",
        "",
        f"| step | browser CPU-s, {args.base} | browser CPU-s, this tree | change | "
        f"server CPU-s, {args.base} | server CPU-s, this tree |",
        "|---|---|---|---|---|---|",
    ]
    base, this = trees["base"], trees["this"]
    for step in STEPS:
        b, t = med(base[step], 0), med(this[step], 0)
        lines.append(
            f"| {step} | {b:.2f} | {t:.2f} | {t - b:+.2f} | {med(base[step], 1):.2f} | "
            f"{med(this[step], 1):.2f} |"
        )
    tb = sum(med(base[s], 0) for s in STEPS)
    tt = sum(med(this[s], 0) for s in STEPS)
    lines += [
        f"| sum of the medians | {tb:.2f} | {tt:.2f} | {tt - tb:+.2f} ({(tt / tb - 1):+.0%}) | | |",
        "",
        "Every session's browser CPU-s by step (base | this tree):",
        "",
    ]
    for step in STEPS:
        b = " ".join(f"{v[0]:.2f}" for v in base[step])
        t = " ".join(f"{v[0]:.2f}" for v in this[step])
        lines.append(f"- {step}: {b} | {t}")
    return "\n".join(lines) + "\n"


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--base", default="main", help="the commit to compare with")
    p.add_argument("--reps", type=int, default=3, help="sessions per tree and round")
    p.add_argument("--rounds", type=int, default=2, help="alternations of the two trees")
    p.add_argument("--out", type=Path, default=OUT)
    p.add_argument("--child", type=int, help=argparse.SUPPRESS)
    args = p.parse_args()
    if args.child is not None:
        print(json.dumps(asyncio.run(sessions(args.child))))
        return
    trees: dict[str, dict[str, list[list[float]]]] = {
        "base": {k: [] for k in STEPS},
        "this": {k: [] for k in STEPS},
    }
    loads = [os.getloadavg()[0]]
    with tempfile.TemporaryDirectory(prefix="noisevar-base-") as tmp:
        archive = subprocess.run(
            ["git", "-C", str(ROOT), "archive", args.base], capture_output=True, check=True
        ).stdout
        tar = Path(tmp) / "base.tar"
        tar.write_bytes(archive)
        with tarfile.open(tar) as t:
            t.extractall(tmp, filter="data")
        for r in range(args.rounds):
            for name, tree in (("base", Path(tmp)), ("this", ROOT)):
                t0 = time.perf_counter()
                got = run_tree(tree, args.reps)
                for step in STEPS:
                    trees[name][step] += got[step]
                loads.append(os.getloadavg()[0])
                print(f"round {r + 1} {name}: {time.perf_counter() - t0:.0f} s", flush=True)
    args.out.write_text(report(args, trees, loads))
    print(args.out.read_text())


if __name__ == "__main__":
    main()

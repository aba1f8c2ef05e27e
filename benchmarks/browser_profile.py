"""What the browser spends its CPU on: one session of the load benchmark, step by step (issue 29).

Drives the path of ``benchmarks/load.py`` (open the Signal page, upload a 20,000-sample
CSV, Estimator, three Γ_amp steps, Compare to its last row, Noise model) in one headless
Chromium context on a fresh ``noisevar dashboard``, after one warm-up session. For each
step it records the browser's CPU-s (``benchmarks/cpu_split.py``'s sampler: every
Chromium process), Chrome's own counters for the page (CDP ``Performance.getMetrics``:
tasks, scripts, layout, style; wall time on the page's main thread) and a sampled
JavaScript profile (CDP ``Profiler``, 0.5 ms) summed by the file of the function that ran:
Streamlit's bundle is split by component (``PlotlyChart.*.js``, ``DataFrame.*.js``,
``StreamlitSyntaxHighlighter.*.js``...), so a file names the kind of element that cost
the time (``--js``: the profiler costs CPU itself). ``(program)`` is the browser's own
native work outside JavaScript, ``(idle)`` the main thread waiting. Then the page waits
``--idle`` seconds untouched: what a settled page costs. Run from the repository root::

    python benchmarks/browser_profile.py [--idle 5] [--js]

Writes ``benchmarks/results/browser_profile.md``.
"""

from __future__ import annotations

import argparse
import asyncio
import collections
import os
import platform
import subprocess
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "benchmarks"))

import load  # noqa: E402  (benchmarks/load.py: the session's path and its settle rules)
from cpu_split import CpuSampler  # noqa: E402

OUT = ROOT / "benchmarks" / "results" / "browser_profile.md"
COUNTERS = ("TaskDuration", "ScriptDuration", "LayoutDuration", "RecalcStyleDuration")


def by_file(profile: dict, top: int = 5) -> str:
    """A CDP profile's self time by script file (s), the ``top`` largest, idle left out."""
    nodes = {n["id"]: n["callFrame"] for n in profile["nodes"]}
    spent: collections.Counter = collections.Counter()
    for node, dt in zip(profile["samples"], profile["timeDeltas"], strict=False):
        frame = nodes[node]
        name = frame["url"].rsplit("/", 1)[-1] or frame["functionName"] or "(native)"
        spent[name.split(".")[0] if frame["url"] else name] += dt / 1e6
    spent.pop("(idle)", None)
    return "; ".join(f"{k} {v:.2f}" for k, v in spent.most_common(top))


class Recorder:
    """Per-step rows: browser CPU-s, Chrome's counters, the JS profile by file."""

    def __init__(self, cdp, sampler: CpuSampler, js: bool) -> None:
        self.cdp, self.sampler, self.js, self.rows = cdp, sampler, js, []

    async def counters(self) -> dict[str, float]:
        m = await self.cdp.send("Performance.getMetrics")
        return {x["name"]: x["value"] for x in m["metrics"]}

    async def step(self, label: str, action) -> None:
        c0, m0, t0 = self.sampler.snapshot(), await self.counters(), time.perf_counter()
        if self.js:
            await self.cdp.send("Profiler.start")
        await action
        files = by_file((await self.cdp.send("Profiler.stop"))["profile"]) if self.js else "-"
        c1, m1, t1 = self.sampler.snapshot(), await self.counters(), time.perf_counter()
        cells = " | ".join(f"{m1[k] - m0[k]:.2f}" for k in COUNTERS)
        self.rows.append(
            f"| {label} | {t1 - t0:.1f} | {c1['browser'] - c0['browser']:.2f} | "
            f"{c1['server'] - c0['server']:.2f} | {cells} | {files} |"
        )
        print(self.rows[-1], flush=True)


async def upload(page, data: bytes) -> None:
    t0 = await load.now(page)
    await page.locator('[data-testid="stFileUploaderDropzoneInput"]').set_input_files(
        files=[{"name": "rec.csv", "mimeType": "text/csv", "buffer": data}]
    )
    await page.locator('[data-testid="stSidebar"]').get_by_text("rec.csv").first.wait_for()
    await load.settled(page, t0)


async def slide(page) -> None:
    thumb = page.locator('[data-testid="stSlider"]', has_text="Γ_amp").get_by_role("slider")
    await thumb.focus()
    await page.evaluate(load.MARK_JS)
    t0 = await load.now(page)
    await thumb.press("ArrowRight")
    await load.settled(page, t0, redrawn=True)


async def opened(page, base: str) -> None:
    await page.goto(f"{base}Signal")
    await page.locator("h1").first.wait_for()
    await page.evaluate(load.OBSERVER_JS, load.PEERS_TEXT)
    await load.settled(page, await load.now(page))


async def run(idle: float, js: bool) -> list[str]:
    from playwright.async_api import async_playwright

    proc, base = load.start_server({})
    sampler = CpuSampler(proc.pid, os.getpid()).start()
    try:
        async with async_playwright() as pw:
            browser = await pw.chromium.launch(executable_path=load.CHROMIUM, args=load.CHROME_ARGS)
            await load.wave(browser, base, 1, False, 10_000)  # warm the server
            ctx = await browser.new_context(viewport={"width": 1400, "height": 900})
            page = await ctx.new_page()
            cdp = await ctx.new_cdp_session(page)
            await cdp.send("Performance.enable")
            await cdp.send("Profiler.enable")
            await cdp.send("Profiler.setSamplingInterval", {"interval": 500})
            rec = Recorder(cdp, sampler, js)
            steps = [
                ("open", lambda: opened(page, base)),
                ("upload", lambda: upload(page, load.record_csv(123))),
                (
                    "estimator",
                    lambda: load.go_to(page, "Estimator", '[data-testid="stMetricValue"]'),
                ),
                ("slider1", lambda: slide(page)),
                ("slider2", lambda: slide(page)),
                ("slider3", lambda: slide(page)),
                ("compare (to its last row)", lambda: load.open_compare(page)),
                ("noise model", lambda: load.go_to(page, "Noise model")),
            ]
            for label, action in steps:
                await rec.step(label, action())
                if label in ("estimator", "compare (to its last row)", "noise model"):
                    await rec.step(f"  then {idle:.0f} s untouched", asyncio.sleep(idle))
            await ctx.close()
            await browser.close()
    finally:
        sampler.stop()
        os.killpg(proc.pid, 15)
        proc.wait(timeout=60)
    return rec.rows


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--idle", type=float, default=5.0, help="seconds a settled page waits")
    p.add_argument(
        "--js",
        action="store_true",
        help="add the sampled JavaScript profile by file (the profiler costs CPU itself)",
    )
    p.add_argument("--out", type=Path, default=OUT)
    args = p.parse_args()
    load_before = os.getloadavg()[0]
    rows = asyncio.run(run(args.idle, args.js))
    commit = subprocess.run(
        ["git", "-C", str(ROOT), "rev-parse", "--short", "HEAD"], capture_output=True, text=True
    ).stdout.strip()
    text = [
        "# What the browser spends its CPU on (`benchmarks/browser_profile.py`)",
        "",
        f"{platform.node()}: {os.cpu_count()} cores, one headless Chromium (Playwright) and "
        f"the dashboard on the same cores; commit {commit}; 1-minute load average "
        f"{load_before:.1f} before, {os.getloadavg()[0]:.1f} after (other jobs share the "
        "machine: wall times and Chrome's counters, which are main-thread wall time, grow "
        "with them; the sampler's CPU-s less so).",
        "",
        f"Command: `python benchmarks/browser_profile.py --idle {args.idle:g}"
        f"{' --js' if args.js else ''}`",
        "",
        "With `--js` the profiler samples every 0.5 ms and costs CPU itself (a page left "
        "untouched then shows a few tenths of a CPU-s of '(program)'): read its CPU-s from a "
        "run without it, its files for where the time goes.",
        "",
        "| step | wall s | browser CPU-s | server CPU-s | tasks s | scripts s | layout s | "
        "style s | JavaScript self time by file (s; (program) = native work) |",
        "|---|---|---|---|---|---|---|---|---|",
        *rows,
        "",
    ]
    args.out.write_text("\n".join(text))
    print(args.out.read_text())


if __name__ == "__main__":
    main()

"""The dashboard as a user meets it: time in a real browser (issue 16).

Starts ``streamlit run app.py`` on a free port, drives Debian's Chromium
through Playwright (flags: ``--headless --no-sandbox --disable-gpu
--disable-background-networking --disable-component-update --disable-sync
--no-first-run``) and measures, on the Estimator page:

1. **control change to page settled**: ten keyboard steps of the Γ_amp
   slider (each a new value: nothing comes from a cache), each timed from the
   key press to the last change of the page (a ``MutationObserver`` stamps
   every DOM change; settled = a figure drawn again, no script running and no
   change for 0.4 s);
   median and worst, on 6,000 and 241,000 samples (targets 0.5 s and 1 s),
   with the browser's busy time (long tasks) and the websocket bytes per change;
2. **2,000,000 samples**: the page opened on a 2e6-sample record, timed from
   navigation to settled with the metrics shown, five times (each in a new tab,
   on a new seed: nothing cached; the median against the target, 5 s), then one
   control change; the browser's JS heap (``Performance.getMetrics``
   ``JSHeapUsedSize`` through the DevTools protocol; target < 500 MB), and
   the points and shapes of every drawn figure, read from the page's Plotly
   objects (budget 10,000 points, 2,000 shapes).

Run from the repository root (a few minutes)::

    python benchmarks/dashboard_browser.py [--changes 10] [--opens 5] [--app-dir DIR --label L]

Prints a Markdown report and writes ``benchmarks/results/dashboard_browser.md``. With
``--app-dir`` the app of another checkout is measured (e.g. the code before a change,
``git archive main | tar -x -C DIR``), so that both are timed back to back under the same
load; ``--label`` then names its report ``dashboard_browser-L.md``.
"""

from __future__ import annotations

import argparse
import os
import platform
import socket
import statistics
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: The checkout whose app is served (``--app-dir``; this one by default).
APP_DIR = ROOT
CHROMIUM = os.environ.get("NOISEVAR_CHROMIUM", "/usr/bin/chromium")
CHROME_ARGS = [
    "--headless",
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
VIEWPORT = {"width": 1400, "height": 900}
#: Seconds without a DOM change (and no script running) before the page counts as settled.
QUIET_S = 0.4
#: (label, samples, target seconds) of the control-change measurements.
SIZES = [("6,000 samples", 6_000, 0.5), ("241,000 samples", 241_000, 1.0)]
BIG_N = 2_000_000
BIG_TARGET_S = 5.0
#: A websocket frame larger than this carries a figure (the others: text, widgets, metrics).
FIGURE_FRAME_BYTES = 5000
HEAP_TARGET_MB = 500.0

OBSERVER_JS = """() => {
  window.__nvLast = performance.now();
  window.__nvBusy = [];
  new PerformanceObserver(l => { for (const e of l.getEntries())
    window.__nvBusy.push([e.startTime, e.duration]); }).observe({type: 'longtask'});
  new MutationObserver(() => { window.__nvLast = performance.now(); })
    .observe(document.body, {subtree: true, childList: true, characterData: true,
                             attributes: true});
}"""
MARK_JS = """() => document.querySelectorAll('.js-plotly-plot')
  .forEach(el => { el.__nvOld = 1; })"""
FRESH_JS = """() => Array.from(document.querySelectorAll('.js-plotly-plot'))
  .some(el => !el.__nvOld)"""
FIGURES_JS = """() => Array.from(document.querySelectorAll('.js-plotly-plot')).map(el => ({
  points: (el._fullData || []).reduce((s, t) => s + (t._length || 0), 0),
  shapes: ((el.layout || {}).shapes || []).length,
}))"""


def recipe(n: int, seed: int = 0) -> str:
    """A generated fast-slow record of ``n`` samples (rebuilt from the link)."""
    return f"gen:fast-slow;n={n};seed={seed};noise_std=5.0"


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def start_server() -> tuple[subprocess.Popen, str]:
    """``streamlit run app.py`` on a free port; returns the process and its base URL."""
    port = _free_port()
    log_path = Path(tempfile.gettempdir()) / "noisevar-dashboard-browser-server.log"
    log = open(log_path, "w")  # noqa: SIM115 - the server's output, for a failed start
    proc = subprocess.Popen(
        [sys.executable, "-m", "streamlit", "run", "app.py", "--server.headless", "true",
         "--server.address", "127.0.0.1", "--server.port", str(port),
         "--server.fileWatcherType", "none"],
        cwd=APP_DIR,
        env={**os.environ, "STREAMLIT_BROWSER_GATHER_USAGE_STATS": "false"},
        stdout=log,
        stderr=subprocess.STDOUT,
    )  # fmt: skip
    base = f"http://127.0.0.1:{port}"
    deadline = time.time() + 120
    while time.time() < deadline:
        try:
            with urllib.request.urlopen(f"{base}/_stcore/health", timeout=2) as r:
                if r.status == 200:
                    return proc, base
        except OSError:
            time.sleep(0.5)
    proc.terminate()
    raise SystemExit("streamlit did not become healthy")


def mark_figures(page) -> None:
    """Tag the drawn Plotly figures: a figure drawn again afterwards is a new, untagged node."""
    page.evaluate(MARK_JS)


def settled_at(page, since: float, timeout: float = 300.0, redrawn: bool = False) -> float:
    """Seconds from ``since`` (``performance.now()`` ms) to the page's last change.

    With ``redrawn``, the page counts as settled only after a figure was drawn again
    (:func:`mark_figures` tags the old ones): a slow server may not have answered yet
    when the page has been quiet for :data:`QUIET_S`.
    """
    deadline = time.time() + timeout
    while time.time() < deadline:
        busy = page.locator('[data-testid="stStatusWidget"]').count() > 0
        quiet = page.evaluate("() => performance.now() - window.__nvLast")
        fresh = not redrawn or page.evaluate(FRESH_JS)
        if fresh and not busy and quiet > QUIET_S * 1000:
            return (page.evaluate("() => window.__nvLast") - since) / 1000.0
        time.sleep(0.05)
    raise RuntimeError("the page did not settle")


def open_estimator(page, base: str, n: int, seed: int = 0) -> float:
    """Open the Estimator on ``n`` samples; seconds from navigation to settled with metrics."""
    t0 = time.perf_counter()
    page.goto(f"{base}/Estimator?sig={recipe(n, seed)}")
    page.wait_for_selector('[data-testid="stMetricValue"]', timeout=600_000)
    page.evaluate(OBSERVER_JS)
    shown = time.perf_counter() - t0
    # anything still drawing after the metrics appeared counts too
    extra = settled_at(page, page.evaluate("() => performance.now()"))
    return shown + max(extra, 0.0)


BUSY_JS = """since => window.__nvBusy.filter(e => e[0] >= since)
  .reduce((s, e) => s + e[1], 0) / 1000"""


def control_changes(
    page, changes: int, split: list | None = None, frames: list[tuple[float, int]] | None = None
) -> list[float]:
    """Seconds to settle after each of ``changes`` keyboard steps of the Γ_amp slider.

    ``split``, when given, receives per change ``(busy, kB)``: the browser's busy time
    (its long tasks, s) and the kB the server sent (``frames``: :func:`watch_frames`).
    """
    thumb = page.locator('[data-testid="stSlider"]', has_text="Γ_amp").get_by_role("slider")
    out = []
    for _ in range(changes):
        thumb.focus()
        mark_figures(page)
        since = page.evaluate("() => performance.now()")
        before = _sent(frames)
        thumb.press("ArrowRight")  # 0.5 -> 0.55 -> ... -> 1.0: a new value each time
        # the window-tests figure draws the thresholds: a new value always redraws it
        out.append(settled_at(page, since, redrawn=True))
        if split is not None:
            busy = page.evaluate(BUSY_JS, since)
            split.append((busy, (_sent(frames) - before) / 1e3))
    return out


def watch_frames(page) -> list[tuple[float, int]]:
    """``(perf_counter, bytes)`` of each websocket frame the page receives (call before opening)."""
    got: list[tuple[float, int]] = []
    page.on(
        "websocket",
        lambda ws: ws.on("framereceived", lambda pl: got.append((time.perf_counter(), len(pl)))),
    )
    return got


def _sent(frames: list[tuple[float, int]] | None) -> int:
    """Bytes received so far in ``frames`` (:func:`watch_frames`)."""
    return sum(size for _, size in frames or [])


def frame_times(frames: list[tuple[float, int]], t0: float) -> tuple[float, float]:
    """Seconds from ``t0`` to the server's first message and to the last figure it sent."""
    first = frames[0][0] - t0 if frames else float("nan")
    figures = [t for t, size in frames if size > FIGURE_FRAME_BYTES]
    return first, (max(figures) - t0 if figures else float("nan"))


def heap_mb(page) -> float:
    """The page's used JS heap (DevTools ``Performance.getMetrics``), in MB."""
    cdp = page.context.new_cdp_session(page)
    cdp.send("Performance.enable")
    metrics = {m["name"]: m["value"] for m in cdp.send("Performance.getMetrics")["metrics"]}
    return metrics["JSHeapUsedSize"] / 1e6


def run(changes: int, opens: int) -> dict:
    """Every measurement (see the module docstring)."""
    from playwright.sync_api import sync_playwright

    proc, base = start_server()
    out: dict = {"sizes": [], "load": [os.getloadavg()[0]]}
    try:
        with sync_playwright() as p:
            browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROME_ARGS, headless=True)
            for label, n, target in SIZES:
                page = browser.new_page(viewport=VIEWPORT)
                frames = watch_frames(page)
                opened = open_estimator(page, base, n)
                split: list = []
                times = control_changes(page, changes, split, frames)
                out["sizes"].append((label, target, opened, times, split))
                print(f"{label}: opened {opened:.2f} s; changes {times}", flush=True)
                page.close()
            out["big_opens"] = []
            for seed in range(opens):  # a new record each time: nothing comes from a cache
                page = browser.new_page(viewport=VIEWPORT)
                frames = watch_frames(page)
                t0 = time.perf_counter()
                opened = open_estimator(page, base, BIG_N, seed)
                out["big_opens"].append((opened, *frame_times(frames, t0)))
                print(f"2e6 seed {seed}: {out['big_opens'][-1]}", flush=True)
                if seed < opens - 1:
                    page.close()
            out["big_open"] = statistics.median(o[0] for o in out["big_opens"])
            out["big_change"] = control_changes(page, 1)[0]
            out["big_heap"] = heap_mb(page)
            out["big_figures"] = page.evaluate(FIGURES_JS)
            print(f"2e6: {out['big_open']:.2f} s, heap {out['big_heap']:.0f} MB", flush=True)
            browser.close()
        out["load"].append(os.getloadavg()[0])
    finally:
        proc.terminate()
        proc.wait(timeout=30)
    return out


def report(res: dict, changes: int) -> str:
    """The Markdown report."""
    lines = [
        "# Dashboard in a real browser (issue 16)",
        "",
        f"Headless Chromium ({CHROMIUM}) through Playwright, {VIEWPORT['width']}x"
        f"{VIEWPORT['height']}, Estimator page, `streamlit run app.py` on the same machine "
        f"({platform.machine()}, {os.cpu_count()} cores, shared with other jobs). A change is a "
        "keyboard step of the Γ_amp slider (a new value each time); settled = the page's last "
        "DOM change, once a figure was drawn again (the window-tests figure shows the "
        f"threshold), with no script running and no change for {QUIET_S} s after it. Browser "
        "busy = the tab's long tasks (> 50 ms: parsing the server's messages, React, plotly's "
        "redraws) during a change; sent = the websocket bytes the server sent for it.",
        "",
        f"| record | page opened (s) | control change to settled, median / worst of {changes}"
        " (s) | target (s) | met | browser busy per change, median (s) | sent per change (kB) |",
        "|---|---|---|---|---|---|---|",
    ]
    for label, target, opened, times, split in res["sizes"]:
        med = statistics.median(times)
        busy = statistics.median(b for b, _ in split)
        sent = statistics.median(k for _, k in split)
        lines.append(
            f"| {label} | {opened:.2f} | {med:.2f} / {max(times):.2f} | <= {target:g} | "
            f"{'yes' if med <= target else 'no'} | {busy:.2f} | {sent:.0f} |"
        )
    figs = res["big_figures"]
    most_points = max((f["points"] for f in figs), default=0)
    most_shapes = max((f["shapes"] for f in figs), default=0)
    opens = res["big_opens"]
    lines += [
        "",
        f"**{BIG_N:,} samples**: the page opened and settled in {res['big_open']:.2f} s, the "
        f"median of {len(opens)} opens, each in a new tab on a new record (target <= "
        f"{BIG_TARGET_S:g} s: {'met' if res['big_open'] <= BIG_TARGET_S else 'not met'}; "
        f"worst {max(o[0] for o in opens):.2f} s); one control change then settled in "
        f"{res['big_change']:.2f} s; JS heap "
        f"{res['big_heap']:.0f} MB (target < {HEAP_TARGET_MB:g} MB: "
        f"{'met' if res['big_heap'] < HEAP_TARGET_MB else 'not met'}); {len(figs)} figures drawn, "
        f"the largest with {most_points:,} points and {most_shapes:,} shapes (budget 10,000 and "
        "2,000).",
        "",
        "| open | server's first message (s) | last figure sent (s) | settled (s) |",
        "|---|---|---|---|",
        *(f"| {i + 1} | {o[1]:.2f} | {o[2]:.2f} | {o[0]:.2f} |" for i, o in enumerate(opens)),
        "",
        "The first message comes once the tab has loaded Streamlit's JavaScript and connected. "
        "The page's first element asks for plotly.js (dashboard.widgets.page_head), so the tab "
        "evaluates it while the server computes; from the last figure sent to settled, the "
        "browser draws the figures and what came with them.",
        "",
        f"Load average (1 min) at the start and the end: {res['load'][0]:.1f} and "
        f"{res['load'][-1]:.1f} on {os.cpu_count()} cores: the browser, the server and other "
        "jobs shared the CPU, so these times are upper bounds for a quiet machine. "
        '"Page opened" includes loading the app\'s JavaScript (Streamlit and plotly.js) into a '
        "new tab, which dominates it at every record size.",
        "",
        "Command: `nice -n 10 python benchmarks/dashboard_browser.py`.",
        "",
    ]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--changes", type=int, default=10)
    ap.add_argument("--opens", type=int, default=5, help="2e6-sample opens (median judged)")
    ap.add_argument("--app-dir", type=Path, default=ROOT, help="checkout whose app is served")
    ap.add_argument("--label", default="", help="report name suffix (with --app-dir)")
    args = ap.parse_args()
    global APP_DIR  # noqa: PLW0603 - the one setting start_server reads
    APP_DIR = args.app_dir.resolve()
    res = run(args.changes, args.opens)
    text = report(res, args.changes)
    if APP_DIR != ROOT:
        text += f"\nApp served from `{APP_DIR}` ({args.label or 'another checkout'}).\n"
    print(text)
    name = f"dashboard_browser-{args.label}.md" if args.label else "dashboard_browser.md"
    (ROOT / "benchmarks" / "results" / name).write_text(text)


if __name__ == "__main__":
    main()

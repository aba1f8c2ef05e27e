"""A class at once: N concurrent browser sessions on one dashboard server (issue 29).

Starts ``noisevar dashboard`` on a free port and drives one headless Chromium (Debian's,
through Playwright: ``--no-sandbox --disable-gpu --disable-background-networking
--disable-component-update --disable-sync --no-first-run``) with one browser context per
session. Each session, all at once:

1. uploads a CSV record on the Signal page (20,000 samples; its own seed, or one shared
   record for every session);
2. opens the Estimator (sidebar link) and makes three keyboard steps of the Γ_amp slider;
3. opens Compare, then Noise model.

Compare draws the fast methods' rows at once and each maximum-likelihood peer's row when
it arrives from the worker pool (a status line names the peers still computing). Its
interaction ends at its first view (:func:`first_view`: the table, its figure and the
record's diagnostics drawn, 0.4 s without a change outside that status line); the time to
its last row is reported beside it ("compare, last row", and the worst interaction with
Compare counted to its last row), not hidden.

An interaction's latency runs from the action to the page's last DOM change (settled: no
script running, a figure drawn or redrawn after the action, then 0.4 s without change). A
figure redrawn in place (Streamlit updates the same element, e.g. the Signal page's figure
becoming the Estimator's) counts as redrawn: a mutation inside any ``.js-plotly-plot``
after the action; only new elements counted before, and sessions whose figure was updated
in place never settled. The
waves are N = 1, 4, 8, 16 on distinct records, then 16 on one shared record. The
server's memory (resident set of the server, its worker pool and fork server) is read
before each wave and after its contexts close (sessions are dropped
``server.disconnectedSessionTTL`` = 30 s after their tab closes; the default is 120 s;
with 5 s, sessions whose websocket reconnected late on an overloaded machine lost their
state and never completed).

``--proxy`` adds a run of 30 sessions through the README's proxy recipe (Debian's nginx,
two app processes, one worker each: ``deploy/local.py``); ``--big`` opens 50 distinct
2e6-sample records one after another (the Estimator page, a new tab each) and reads the
server's memory after each against its budget. Run from the repository root::

    python benchmarks/load.py [--waves 1 4 8 16] [--shared 16] [--proxy 30] [--big 50]

Writes ``benchmarks/results/load.md``.
"""

from __future__ import annotations

import argparse
import asyncio
import collections
import io
import os
import platform
import shutil
import statistics
import subprocess
import sys
import time
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))
sys.path.insert(0, str(ROOT / "deploy"))
sys.path.insert(0, str(ROOT / "benchmarks"))

import local  # noqa: E402  (deploy/local.py)
from cpu_split import PERIOD_S, CpuSampler  # noqa: E402  (benchmarks/cpu_split.py)

import noisevar  # noqa: E402

CHROMIUM = os.environ.get("NOISEVAR_CHROMIUM", "/usr/bin/chromium")
CHROME_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
SAMPLES = 20_000
BIG_N = 2_000_000
QUIET_S = 0.4
#: Longest pause between two looks at a page (s): 0.1 s at first, growing while it waits.
#: The latency is read from the page's own clock, so a later look does not lengthen it
#: (unless the page changes again after 0.4 s of quiet); looking every 0.1 s throughout
#: cost the browser and Playwright's driver CPU in proportion to the waits.
POLL_MAX_S = 0.3
SESSION_TTL_S = 30
#: A session's steps, in order (a failed session names the one it failed at).
STEPS = ("open", "upload", "estimator", "slider1", "slider2", "slider3", "compare", "noise model")
OUT = ROOT / "benchmarks" / "results" / "load.md"  # --out changes it
#: The server's script-run trace (``--trace``: ``NOISEVAR_TRACE``, dashboard/trace.py).
TRACE = Path("/tmp") / "noisevar-load-trace.jsonl"

#: The Compare page's line while its slow peers compute (dashboard/sections/compare.py).
PEERS_TEXT = "of the peers still computing"
OBSERVER_JS = """(peers) => {
  if (window.__nvObserved) return; window.__nvObserved = true;
  window.__nvLast = performance.now();
  window.__nvView = window.__nvLast;
  window.__nvPlot = 0;
  new MutationObserver((records) => {
    const t = performance.now();
    window.__nvLast = t;
    for (const r of records) {
      const el = r.target.nodeType === 1 ? r.target : r.target.parentElement;
      if (!el) continue;
      if (el.closest('.js-plotly-plot')) window.__nvPlot = t;
      // the view: every change but the status widget's and the peers' status line
      if (!el.closest('[data-testid="stStatusWidget"]')
          && !(el.closest('[data-testid="stCaptionContainer"]') || {innerText: ''})
               .innerText.includes(peers)) window.__nvView = t;
    }
  }).observe(document.body, {subtree: true, childList: true, characterData: true,
                             attributes: true});
}"""
MARK_JS = "() => document.querySelectorAll('.js-plotly-plot').forEach(el => { el.__nvOld = 1; })"
VIEW_JS = """([since, peers]) => ({
  quiet: performance.now() - window.__nvView, last: window.__nvView,
  busy: document.querySelectorAll('[data-testid="stStatusWidget"]').length > 0,
  peers: Array.from(document.querySelectorAll('[data-testid="stCaptionContainer"]'))
    .some(el => el.innerText.includes(peers)),
  fresh: window.__nvPlot > since
    || Array.from(document.querySelectorAll('.js-plotly-plot')).some(el => !el.__nvOld),
  errors: document.querySelectorAll('[data-testid="stException"]').length,
})"""
STATE_JS = """(since) => ({
  quiet: performance.now() - window.__nvLast, last: window.__nvLast,
  busy: document.querySelectorAll('[data-testid="stStatusWidget"]').length > 0,
  fresh: window.__nvPlot > since
    || Array.from(document.querySelectorAll('.js-plotly-plot')).some(el => !el.__nvOld),
  errors: document.querySelectorAll('[data-testid="stException"]').length,
})"""


def record_csv(seed: int, n: int = SAMPLES) -> bytes:
    """A fast-slow record with a time column, as CSV bytes."""
    z = noisevar.generate("fast-slow", n=n, seed=seed).measured
    buf = io.StringIO()
    np.savetxt(buf, np.column_stack([np.arange(n) * 0.01, z]), delimiter=",", fmt="%.9g")
    return b"t,z\n" + buf.getvalue().encode()


def tree_rss_mb(pid: int) -> float:
    """Resident memory of ``pid`` and all its descendants (MB)."""
    children: dict[int, list[int]] = {}
    for stat in Path("/proc").glob("[0-9]*/stat"):
        try:
            fields = stat.read_text().rsplit(")", 1)[1].split()
        except OSError:
            continue
        children.setdefault(int(fields[1]), []).append(int(stat.parent.name))
    total, todo = 0, [pid]
    while todo:
        p = todo.pop()
        todo += children.get(p, [])
        try:
            for line in Path(f"/proc/{p}/status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    total += int(line.split()[1])
        except OSError:
            pass
    return total / 1024


async def settled(page, since: float, redrawn: bool = False, timeout: float = 900.0) -> float:
    """Seconds from ``since`` (page clock, ms) to the page's last change once it settled."""
    deadline = time.monotonic() + timeout
    polls = 0
    while time.monotonic() < deadline:
        s = await page.evaluate(STATE_JS, since)
        if s["errors"]:
            raise RuntimeError("an exception box on the page")
        if (s["fresh"] or not redrawn) and not s["busy"] and s["quiet"] > QUIET_S * 1000:
            return (s["last"] - since) / 1000.0
        polls += 1
        await asyncio.sleep(min(POLL_MAX_S, 0.1 + 0.02 * polls))
    raise TimeoutError("the page did not settle")


async def first_view(page, since: float, timeout: float = 900.0) -> float:
    """Seconds from ``since`` to the Compare page's first view: the table of every fast
    method, its figure and the record's diagnostics drawn, while a status line names the
    peers still computing (their rows arrive later, :func:`settled` times the last one);
    the same as :func:`settled` when no peer is left to compute."""
    deadline = time.monotonic() + timeout
    polls = 0
    while time.monotonic() < deadline:
        s = await page.evaluate(VIEW_JS, [since, PEERS_TEXT])
        if s["errors"]:
            raise RuntimeError("an exception box on the page")
        if s["fresh"] and (s["peers"] or not s["busy"]) and s["quiet"] > QUIET_S * 1000:
            return (s["last"] - since) / 1000.0
        polls += 1
        await asyncio.sleep(min(POLL_MAX_S, 0.1 + 0.02 * polls))
    raise TimeoutError("the page's first view did not settle")


async def now(page) -> float:
    return await page.evaluate("() => performance.now()")


async def go_to(page, title: str, ready: str | None = None) -> float:
    """Open a page through the sidebar; seconds to settled with a figure drawn (and the
    ``ready`` element shown: a page waiting for a worker can be quiet for a while)."""
    await page.evaluate(MARK_JS)
    t0 = await now(page)
    nav = page.locator('[data-testid="stSidebarNav"]')
    await nav.get_by_text(title, exact=True).first.click()
    await page.locator("h1", has_text=title).first.wait_for(timeout=900_000)
    if ready:
        await page.locator(ready).first.wait_for(timeout=900_000)
    return await settled(page, t0, redrawn=True)


async def open_compare(page) -> tuple[float, float]:
    """Open Compare: seconds to its first view (:func:`first_view`) and to its last row."""
    await page.evaluate(MARK_JS)
    t0 = await now(page)
    nav = page.locator('[data-testid="stSidebarNav"]')
    await nav.get_by_text("Compare", exact=True).first.click()
    await page.locator("h1", has_text="Compare").first.wait_for(timeout=900_000)
    view = await first_view(page, t0)
    return view, max(view, await settled(page, t0, redrawn=True))


async def page_state(page) -> str:
    """What a failed session's page shows: its status widget and the start of its text."""
    try:
        status = await page.evaluate(
            "() => Array.from(document.querySelectorAll('[data-testid=\"stStatusWidget\"]'))"
            ".map(e => e.innerText).join(' ')"
        )
        text = await page.evaluate(
            "() => (document.querySelector('[data-testid=\"stMain\"]') || document.body).innerText"
        )
    except Exception as exc:  # noqa: BLE001 - the page itself may be gone
        return f" (page unreadable: {type(exc).__name__})"
    words = " ".join(str(text).split())
    return f" (status: {' '.join(str(status).split())[:40] or 'none'}; page: {words[:120]})"


class StepLog(dict):
    """A session's latencies by step; with a sampler, also the CPU totals at each step's end
    (``cpu``: step -> totals by class)."""

    def __init__(self, sampler: CpuSampler | None = None) -> None:
        super().__init__()
        self.sampler = sampler
        self.cpu: dict[str, dict[str, float]] = {}
        if sampler is not None:
            self.cpu["start"] = sampler.snapshot()

    def __setitem__(self, key: str, value: object) -> None:
        super().__setitem__(key, value)
        if self.sampler is not None and key in STEPS:
            self.cpu[key] = self.sampler.snapshot()


async def session(
    browser, base: str, data: bytes, name: str, sampler: CpuSampler | None = None
) -> dict:
    """One student's path; returns the latency of each interaction (s)."""
    out = StepLog(sampler)
    ctx = await browser.new_context(viewport={"width": 1400, "height": 900})
    page = await ctx.new_page()
    page.set_default_timeout(900_000)  # a loaded machine: every step completes or times out
    try:
        t0 = time.perf_counter()
        await page.goto(f"{base}Signal", timeout=900_000)
        await page.locator("h1").first.wait_for(timeout=900_000)
        await page.evaluate(OBSERVER_JS, PEERS_TEXT)
        await settled(page, await now(page))
        out["open"] = time.perf_counter() - t0
        t0 = await now(page)
        await page.locator('[data-testid="stFileUploaderDropzoneInput"]').set_input_files(
            files=[{"name": name, "mimeType": "text/csv", "buffer": data}]
        )
        await (
            page.locator('[data-testid="stSidebar"]')
            .get_by_text(name)
            .first.wait_for(timeout=900_000)
        )
        out["upload"] = await settled(page, t0)
        out["estimator"] = await go_to(page, "Estimator", '[data-testid="stMetricValue"]')
        thumb = page.locator('[data-testid="stSlider"]', has_text="Γ_amp").get_by_role("slider")
        for i in range(3):
            await thumb.focus()
            await page.evaluate(MARK_JS)
            t0 = await now(page)
            await thumb.press("ArrowRight")
            out[f"slider{i + 1}"] = await settled(page, t0, redrawn=True)
        out["compare"], out["compare rows"] = await open_compare(page)
        out["noise model"] = await go_to(page, "Noise model")
        out["ok"] = 1.0
    except Exception as exc:  # noqa: BLE001 - a failed session is counted, not fatal
        out["ok"] = 0.0
        step = next((k for k in STEPS if k not in out), "?")
        text = f"at {step}: {type(exc).__name__}: {exc}".splitlines()[0][:120]
        out["error"] = text + await page_state(page)  # type: ignore[assignment]
    finally:
        await ctx.close()
    return out


async def wave(
    browser, base: str, n: int, shared: bool, seed0: int, sampler: CpuSampler | None = None
) -> list[dict]:
    datas = [record_csv(seed0 if shared else seed0 + i) for i in range(n)]
    names = [f"rec{seed0 if shared else seed0 + i}.csv" for i in range(n)]
    runs = (session(browser, base, d, nm, sampler) for d, nm in zip(datas, names, strict=True))
    return list(await asyncio.gather(*runs))


def summary(results: list[dict]) -> dict:
    keys = [k for k in STEPS[1:] if results and k in results[0]]
    lat = [r[k] for r in results if r.get("ok") for k in keys]
    rows = [r.get("compare rows", r.get("compare", 0.0)) for r in results if r.get("ok")]
    changes = [r[k] for r in results if r.get("ok") for k in ("slider1", "slider2", "slider3")]
    return {
        "done": sum(1 for r in results if r.get("ok")),
        "n": len(results),
        "median": statistics.median(lat) if lat else float("nan"),
        "worst": max(lat) if lat else float("nan"),
        "change": statistics.median(changes) if changes else float("nan"),
        # the worst interaction when Compare counts until its last row
        "worst rows": max([*lat, *rows]) if lat else float("nan"),
        "rows": (statistics.median(rows), max(rows)) if rows else (float("nan"),) * 2,
        "errors": [r["error"] for r in results if not r.get("ok")],
        "steps": {
            k: (statistics.median(v), max(v))
            for k in keys
            if (v := [r[k] for r in results if r.get("ok")])
        },
    }


def start_server(env: dict[str, str]) -> tuple[subprocess.Popen, str]:
    port = local.free_port()
    log = open(Path("/tmp") / "noisevar-load-server.log", "wb")  # noqa: SIM115
    proc = subprocess.Popen(
        [sys.executable, "-m", "noisevar", "dashboard", "--port", str(port)],
        env={**os.environ, **env},
        stdout=log,
        stderr=subprocess.STDOUT,
        start_new_session=True,
    )
    local.wait_listening(port)
    return proc, f"http://127.0.0.1:{port}/"


async def settle_memory(pid: int) -> float:
    await asyncio.sleep(SESSION_TTL_S + 8)
    return tree_rss_mb(pid)


def one_session_cpu(cpu: dict[str, dict[str, float]]) -> list[str]:
    """Rows of a single session's CPU-s by step (server, browser)."""
    rows, prev = [], cpu["start"]
    for step in STEPS:
        now = cpu.get(step)
        if now is None:
            continue
        rows.append(
            f"| {step} | {now['server'] - prev['server']:.2f} | "
            f"{now['browser'] - prev['browser']:.2f} |"
        )
        prev = now
    return rows


def trace_rows(label: str, t0: float, t1: float) -> list[str]:
    """The server's script runs that started in ``[t0, t1]`` (unix time), from the trace:
    one summary row, then the five longest runs."""
    import json

    if not TRACE.exists():
        return []
    runs, guard, pauses = [], [], []
    for line in TRACE.read_text().splitlines():
        r = json.loads(line)
        if "guard" in r and t0 <= r["guard"] <= t1:
            guard.append(r["seconds"])
        elif "gc" in r and t0 <= r["gc"] <= t1:
            pauses.append(r["seconds"])
        elif "start" in r and t0 <= r["start"] <= t1:
            r["wall"] = r["end"] - r["start"]
            r["wait"] = max(0.0, r["wall"] - r["cpu"] - r["pool"])
            runs.append(r)
    if not runs:
        return []
    walls = sorted(r["wall"] for r in runs)
    rows = [
        f"| {label} | {len(runs)} | {sum(r['cpu'] for r in runs):.1f} | "
        f"{statistics.median(walls):.2f} | {walls[int(0.9 * (len(walls) - 1))]:.2f} | "
        f"{walls[-1]:.2f} | {sum(r['pool'] for r in runs):.1f} | "
        f"{sum(r['wait'] for r in runs):.1f} | {len(pauses)} ({sum(pauses):.2f} s) | "
        f"{len(guard)} ({sum(guard):.2f} s) |"
    ]
    for r in sorted(runs, key=lambda r: -r["wall"])[:5]:
        rows.append(
            f"|  longest: {r['page']} ({r['outcome']}) |  | {r['cpu']:.2f} |  |  | "
            f"{r['wall']:.2f} | {r['pool']:.2f} | {r['wait']:.2f} | {r['gc_s']:.2f} |  |"
        )
    return rows


def floor_row(label: str, n: int, wall: float, one_wall: float, used: dict[str, float]) -> str:
    """A wave's time against the cores' floor: the CPU-s it used over the machine's cores,
    for every process, for ours (server, browser, driver) and for the server alone (a class
    whose browsers run on their own laptops); each also as a ratio to the one-session wave."""
    cores = os.cpu_count() or 1
    ours = used["server"] + used["browser"] + used["driver"]
    both = used["server"] + used["browser"]
    cells = [
        (sum(used.values()) / cores),
        ours / cores,
        used["server"] / cores,
    ]
    return (
        f"| {label} | {wall:.0f} ({wall / one_wall:.1f}x) | "
        + " | ".join(f"{c:.0f} ({c / one_wall:.1f}x)" for c in cells)
        + f" | {1.3 * max(1.0, n / 2):.1f}x | {100 * used['browser'] / max(both, 1e-9):.0f} % |"
    )


async def run_waves(pw, args, env, tables: dict[str, list[str]], log) -> None:
    rows = tables["waves"]
    if args.trace:
        TRACE.unlink(missing_ok=True)
        env = {**env, "NOISEVAR_TRACE": str(TRACE)}
    proc, base = start_server(env)
    sampler = CpuSampler(proc.pid, os.getpid()).start()
    browser = await pw.chromium.launch(executable_path=CHROMIUM, args=CHROME_ARGS)
    try:
        await wave(browser, base, 1, False, 10_000)  # warm the server: first imports, pool
        await asyncio.sleep(SESSION_TTL_S + 3)
        one, one_wall = None, None
        plan = [(n, False) for n in args.waves] + ([(args.shared, True)] if args.shared else [])
        for k, (n, shared) in enumerate(plan):
            label = f"{n}{' shared' if shared else ''}"
            before = tree_rss_mb(proc.pid)
            cpu0, unix0 = sampler.snapshot(), time.time()
            t0 = time.perf_counter()
            results = await wave(
                browser, base, n, shared, 100 * (k + 1), sampler if n == 1 else None
            )
            s = summary(results)
            wall = time.perf_counter() - t0
            if n == 1 and results[0].get("ok"):
                tables["one"] = one_session_cpu(results[0].cpu)
            cpu1, unix1 = sampler.snapshot(), time.time()
            after = await settle_memory(proc.pid)
            if n == 1 and not shared:
                one = s
            ref = one or s
            fair = 1.3 * max(1.0, n / 2)
            rows.append(
                f"| {label} | {s['done']}/{s['n']} | {s['median']:.2f} "
                f"({s['median'] / ref['median']:.1f}x) | {s['worst']:.2f} "
                f"({s['worst'] / ref['worst']:.1f}x) | {fair:.1f}x | {s['worst rows']:.2f} "
                f"({s['worst rows'] / ref['worst rows']:.1f}x) | {s['change']:.2f} | "
                f"{wall:.0f} | {before:.0f} -> {after:.0f} ({100 * (after / before - 1):+.0f} %) |"
            )
            used = {c: cpu1[c] - cpu0[c] for c in cpu1}
            per = len(STEPS) * max(1, s["done"])
            tables["cpu"].append(
                f"| {label} | {used['server']:.1f} | {used['browser']:.1f} | "
                f"{used['driver']:.1f} | {used['other']:.1f} | {used['server'] / per:.3f} | "
                f"{used['browser'] / per:.3f} | {(used['server'] + used['browser']) / per:.3f} | "
                f"{sum(used.values()) / wall:.2f} |"
            )
            if n == 1 and not shared:
                one_wall = wall
            tables["floor"].append(floor_row(label, n, wall, one_wall or wall, used))
            cells = [s["steps"].get(step, (0.0, 0.0)) for step in STEPS[1:]] + [s["rows"]]
            tables["steps"].append(
                f"| {label} | " + " | ".join(f"{m:.2f} / {w:.2f}" for m, w in cells) + " |"
            )
            tables["trace"] += trace_rows(label, unix0, unix1)
            log(rows[-1] + (f"  errors: {s['errors'][:3]}" if s["errors"] else ""))
            log(tables["cpu"][-1])
            log(tables["floor"][-1])
            log(tables["steps"][-1])
    finally:
        sampler.stop()
        await browser.close()
        os.killpg(proc.pid, 15)
        proc.wait(timeout=60)


async def run_proxy(pw, n: int, rows: list[str], log) -> None:
    env = {"NOISEVAR_WORKERS": "1", "STREAMLIT_SERVER_DISCONNECTED_SESSION_TTL": str(SESSION_TTL_S)}
    dep = local.start(apps=2, env=env)
    browser = await pw.chromium.launch(executable_path=CHROMIUM, args=CHROME_ARGS)
    try:
        t0 = time.perf_counter()
        s = summary(await wave(browser, dep.url, n, False, 5000))
        wall = time.perf_counter() - t0
        used = sorted(set(__import__("re").findall(r"upstream=(\S+)", dep.access_log())))
        rows.append(
            f"| {n} via nginx, 2 apps | {s['done']}/{s['n']} | {s['median']:.2f} | "
            f"{s['worst']:.2f} | {s['change']:.2f} | {wall:.0f} | {', '.join(used)} |"
        )
        log(rows[-1] + (f"  errors: {s['errors'][:3]}" if s["errors"] else ""))
        kinds = collections.Counter(e.split(" (status")[0] for e in s["errors"])
        for err, count in kinds.most_common(5):
            example = next(e for e in s["errors"] if e.startswith(err))
            rows.append(f"|  | {count} failed {example} |  |  |  |  |  |")
        for err in s["errors"]:
            print("  failed session:", err, flush=True)
    finally:
        await browser.close()
        keep = Path("/tmp") / "noisevar-load-proxy-logs"  # the apps' and nginx's own logs
        shutil.rmtree(keep, ignore_errors=True)
        shutil.copytree(
            dep.folder,
            keep,
            ignore=shutil.ignore_patterns(
                "*_temp", "client_body", "proxy", "fastcgi", "uwsgi", "scgi"
            ),
        )
        dep.stop()


async def run_big(pw, n: int, env: dict[str, str], rows: list[str], log) -> None:
    proc, base = start_server(env)
    browser = await pw.chromium.launch(executable_path=CHROMIUM, args=CHROME_ARGS)
    budget_mb = float(env.get("NOISEVAR_MEMORY_MB", 512))
    try:
        ctx = await browser.new_context(viewport={"width": 1400, "height": 900})
        start = tree_rss_mb(proc.pid)
        peak, trail, opens = 0.0, [], []
        for i in range(n):
            page = await ctx.new_page()
            t0 = time.perf_counter()
            await page.goto(f"{base}Estimator?sig=gen:fast-slow;n={BIG_N};seed={1000 + i}")
            await page.locator('[data-testid="stMetricValue"]').first.wait_for(timeout=900_000)
            opens.append(time.perf_counter() - t0)
            await page.close()
            rss = tree_rss_mb(proc.pid)
            peak = max(peak, rss)
            trail.append(rss)
            log(f"  2e6 record {i + 1}/{n}: {opens[-1]:.1f} s, server {rss:.0f} MB")
        await ctx.close()
        end = await settle_memory(proc.pid)
        rows.append(
            f"| {n} distinct 2e6 records, one after another | {start:.0f} | {peak:.0f} | "
            f"{trail[len(trail) // 2]:.0f} | {end:.0f} | {budget_mb:.0f} | "
            f"{statistics.median(opens):.1f} |"
        )
        log(rows[-1])
    finally:
        await browser.close()
        os.killpg(proc.pid, 15)
        proc.wait(timeout=60)


def report(args, tables: dict[str, list[str]], proxy: list[str], big: list[str], cpus: int) -> str:
    head = [
        "# Serving a class: concurrent browser sessions (`benchmarks/load.py`)",
        "",
        f"{platform.node()}: {cpus} cores, Python {platform.python_version()}, one headless "
        f"Chromium (Playwright), one context per session, `noisevar dashboard` (worker pool "
        f"{os.environ.get('NOISEVAR_WORKERS', 'sized to the machine')}). Each session: upload "
        f"a {SAMPLES:,}-sample CSV, Estimator + three Γ_amp steps, Compare, Noise model. "
        "Latency = action to the page's last change (settled: no script running, 0.4 s "
        "quiet); Compare's = to its first view (the table of every fast method, its figure "
        "and the record's diagnostics drawn and 0.4 s quiet, with a status line naming the "
        "maximum-likelihood peers still computing; their rows arrive later: 'compare, last "
        "row' and the 'with Compare to its last row' column time those). The browser and the "
        "server share the same cores.",
        "",
        f"Command: `python benchmarks/load.py {' '.join(sys.argv[1:])}`",
        "",
    ]
    out = head
    if tables["waves"]:
        out += [
            "| sessions | completed | median s (vs 1) | worst s (vs 1) | target (1.3 x N/2) "
            "| worst s with Compare to its last row (vs 1) "
            "| median slider step s | wave s | server MB before -> after close |",
            "|---|---|---|---|---|---|---|---|---|",
            *tables["waves"],
            "",
            f"CPU-s of each wave (benchmarks/cpu_split.py's sampler, every {PERIOD_S} s; per "
            f"interaction = wave CPU / (sessions x {len(STEPS)} steps: open, upload, "
            "Estimator, 3 slider steps, Compare, Noise model); driver = this benchmark and "
            "Playwright's driver; other = every other process on the machine):",
            "",
            "| sessions | server CPU-s | browser CPU-s | driver CPU-s | other CPU-s | server per "
            "interaction | browser per interaction | both per interaction | cores busy (all "
            "processes) |",
            "|---|---|---|---|---|---|---|---|---|",
            *tables["cpu"],
            "",
            "The cores' floor: a wave cannot take less than the CPU-s it used divided by the "
            "machine's cores; each figure also as a ratio to the one-session wave (the "
            "target's ratio applies to interactions, these to whole waves). 'Ours' = server + "
            "browser + driver; 'server alone' is the floor when each student's browser runs on "
            "their own computer, as in a real class:",
            "",
            "| sessions | wave s (vs 1) | floor, every process s (vs 1) | floor, ours s (vs 1) | "
            "floor, server alone s (vs 1) | target (1.3 x N/2) | browser's share of server + "
            "browser CPU |",
            "|---|---|---|---|---|---|---|",
            *tables["floor"],
            "",
            "One session (the N = 1 wave), CPU-s by step (from the previous step's end to "
            "this one's):",
            "",
            "| step | server CPU-s | browser CPU-s |",
            "|---|---|---|",
            *tables.get("one", []),
            "",
            "Each step's median / worst latency (s):",
            "",
            "| sessions | " + " | ".join(STEPS[1:]) + " | compare, last row |",
            "|---|" + "---|" * (len(STEPS[1:]) + 1),
            *tables["steps"],
            "",
        ]
    if tables["trace"]:
        out += [
            "The server's script runs (`--trace`: NOISEVAR_TRACE, dashboard/trace.py): wall = "
            "script start to end; cpu = the script thread's own CPU; pool = waiting for the "
            "worker pool (queue + computation); wait = wall - cpu - pool (runnable but not "
            "running: the GIL, or I/O); gc = the server's collection pauses of 10 ms or more "
            "in the wave (the longest runs: pauses inside the run); guard = the memory guard's "
            "collections in the wave (GIL held):",
            "",
            "| sessions | runs | script CPU-s | median wall s | p90 wall s | worst wall s | "
            "pool s | wait s | gc pauses (s) | guard collections |",
            "|---|---|---|---|---|---|---|---|---|---|",
            *tables["trace"],
            "",
        ]
    if proxy:
        out += [
            "| proxy run | completed | median s | worst s | median slider step s | wave s "
            "| processes used |",
            "|---|---|---|---|---|---|---|",
            *proxy,
            "",
        ]
    if big:
        out += [
            "| memory | server MB at start | peak | at the middle | after close | "
            "cache budget MB (NOISEVAR_MEMORY_MB) | median open s |",
            "|---|---|---|---|---|---|---|",
            *big,
            "",
        ]
    return "\n".join(out)


async def main_async(args) -> None:
    from playwright.async_api import async_playwright

    env = {"STREAMLIT_SERVER_DISCONNECTED_SESSION_TTL": str(SESSION_TTL_S)}
    tables: dict[str, list[str]] = {
        "waves": [],
        "cpu": [],
        "floor": [],
        "steps": [],
        "trace": [],
    }
    proxy: list[str] = []
    big: list[str] = []
    cpus = len(os.sched_getaffinity(0))

    def log(text: str) -> None:
        print(text, flush=True)
        OUT.write_text(report(args, tables, proxy, big, cpus))

    async with async_playwright() as pw:
        if args.waves or args.shared:
            await run_waves(pw, args, env, tables, log)
        if args.proxy:
            await run_proxy(pw, args.proxy, proxy, log)
        if args.big:
            await run_big(pw, args.big, env, big, log)
    OUT.write_text(report(args, tables, proxy, big, cpus))
    print(OUT.read_text())


def main() -> None:
    p = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    p.add_argument("--waves", type=int, nargs="*", default=[1, 4, 8, 16])
    p.add_argument("--shared", type=int, default=16)
    p.add_argument("--proxy", type=int, default=30)
    p.add_argument("--big", type=int, default=50)
    p.add_argument(
        "--trace", action="store_true", help="log the server's script runs (NOISEVAR_TRACE)"
    )
    p.add_argument("--out", type=Path, default=OUT, help="the Markdown table written")
    args = p.parse_args()
    globals()["OUT"] = args.out
    asyncio.run(main_async(args))


if __name__ == "__main__":
    main()

"""Shared AppTest helpers of the dashboard tests."""

from __future__ import annotations

import os
import shutil
import socket
import subprocess
import sys
import time
import urllib.request
from collections.abc import Callable
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from dashboard.widgets import HOW_IT_WORKS_KEY  # noqa: E402


def _how_it_works_opens(at: AppTest) -> bool:
    """The page's "How it works" expander is there, sends nothing while closed, and
    shows its equations once opened (the page is then rerun open)."""
    assert any("How it works" in e.label for e in at.expander)
    if at.session_state[HOW_IT_WORKS_KEY] if HOW_IT_WORKS_KEY in at.session_state else False:
        return bool(at.get("latex"))
    assert not at.get("latex"), "a closed How it works expander sends its equations"
    at.session_state[HOW_IT_WORKS_KEY] = True
    at.run()
    assert not at.exception, [e.value for e in at.exception]
    return bool(at.get("latex"))


@pytest.fixture
def how_it_works_opens() -> Callable[[AppTest], bool]:
    """:func:`_how_it_works_opens`, for the page tests."""
    return _how_it_works_opens


# ----------------------------------------------------------- the real-browser tests
CHROMIUM = os.environ.get("NOISEVAR_CHROMIUM", "/usr/bin/chromium")
CHROME_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]


def _free_port() -> int:
    with socket.socket(socket.AF_INET, socket.SOCK_STREAM) as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def pytest_collection_modifyitems(items):
    """One worker runs every test that needs the served app or the browser (pytest-xdist's
    ``loadgroup``): one ``streamlit run`` and one Chromium per suite, and one writer of
    ``test-artifacts/``."""
    for item in items:
        if {"server", "browser"} & set(getattr(item, "fixturenames", ())):
            item.add_marker(pytest.mark.xdist_group("browser"))


@pytest.fixture(scope="session")
def server():
    """The app served by ``streamlit run`` on a free port, once per session."""
    port = _free_port()
    env = {**os.environ, "STREAMLIT_BROWSER_GATHER_USAGE_STATS": "false"}
    log = (ROOT / "test-artifacts").resolve()
    log.mkdir(parents=True, exist_ok=True)
    out = open(log / "streamlit-server.log", "w")  # noqa: SIM115 - closed in teardown
    proc = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "streamlit",
            "run",
            "app.py",
            "--server.headless",
            "true",
            "--server.address",
            "127.0.0.1",
            "--server.port",
            str(port),
            "--server.fileWatcherType",
            "none",
        ],
        cwd=ROOT,
        env=env,
        stdout=out,
        stderr=subprocess.STDOUT,
    )
    base = f"http://127.0.0.1:{port}"
    deadline = time.time() + 90
    while True:
        try:
            with urllib.request.urlopen(f"{base}/_stcore/health", timeout=2) as r:
                if r.status == 200:
                    break
        except OSError:
            pass
        if proc.poll() is not None or time.time() > deadline:
            proc.terminate()
            out.close()
            pytest.fail(f"streamlit did not become healthy; see {log / 'streamlit-server.log'}")
        time.sleep(0.5)
    yield base
    proc.terminate()
    try:
        proc.wait(timeout=15)
    except subprocess.TimeoutExpired:
        proc.kill()
    out.close()


@pytest.fixture(scope="session")
def browser():
    """One headless Chromium for every browser test (``/usr/bin/chromium``, no download)."""
    playwright_api = pytest.importorskip("playwright.sync_api")
    if not Path(CHROMIUM).exists():
        pytest.fail(f"no Chromium at {CHROMIUM} (apt-get install chromium)")
    shots = ROOT / "test-artifacts" / "browser"
    if shots.exists():
        shutil.rmtree(shots)
    shots.mkdir(parents=True)
    print(f"\nbrowser screenshots: {shots}")
    with playwright_api.sync_playwright() as p:
        b = p.chromium.launch(executable_path=CHROMIUM, args=CHROME_ARGS, headless=True)
        yield b
        b.close()

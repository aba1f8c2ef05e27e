"""The README's proxy recipe, on loopback: two app processes behind Debian's nginx (issue 29)."""

from __future__ import annotations

import re
import socket
import sys
import urllib.request
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT / "deploy"))
sys.path.insert(0, str(ROOT / "tests"))

import local  # noqa: E402
from test_cli_dashboard import _handshake  # noqa: E402


@pytest.fixture(scope="module")
def deployment():
    dep = local.start(apps=2)
    yield dep
    dep.stop()


def _get(dep: local.Deployment, route: str | None = None, host: str | None = None) -> str:
    req = urllib.request.Request(dep.url)
    if route:
        req.add_header("Cookie", f"noisevar_route={route}")
    if host:
        req.add_header("Host", host)
    with urllib.request.urlopen(req, timeout=20) as resp:
        assert resp.status == 200
        assert "noisevar_route=" in resp.headers.get("Set-Cookie", "")
        return resp.read().decode()


def test_the_proxy_serves_the_app_and_its_websocket(deployment):
    assert "<noscript>" in _get(deployment)  # Streamlit's page
    status = _handshake(deployment.port, f"127.0.0.1:{deployment.port}", deployment.url[:-1])
    assert " 101 " in status, status


def _raw_reply(port: int, host: str) -> bytes:
    with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
        s.sendall(f"GET / HTTP/1.1\r\nHost: {host}\r\nConnection: close\r\n\r\n".encode())
        return s.recv(4096)


def test_a_foreign_host_gets_no_answer(deployment):
    assert _raw_reply(deployment.port, f"127.0.0.1:{deployment.port}").startswith(b"HTTP/1.1 200")
    for host in ("evil.example", "evil.example:80", "10.0.0.1"):
        assert _raw_reply(deployment.port, host) == b"", host  # 444: closed, no answer


def test_a_browser_always_reaches_the_same_process_and_browsers_spread(deployment):
    for i in range(20):
        for _ in range(2):
            _get(deployment, route=f"browser{i}")
    backends: dict[str, set[str]] = {}
    for line in deployment.access_log().splitlines():
        m = re.search(r"route=(browser\d+) upstream=(\S+)", line)
        if m:
            backends.setdefault(m.group(1), set()).add(m.group(2))
    assert len(backends) == 20 and all(len(b) == 1 for b in backends.values())
    assert {b.pop() for b in backends.values()} == {f"127.0.0.1:{p}" for p in deployment.app_ports}

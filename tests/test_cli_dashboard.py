"""``noisevar dashboard``: safe from any directory (issue 29, item 8)."""

from __future__ import annotations

import base64
import os
import signal
import socket
import subprocess
import sys
import time
from pathlib import Path

import pytest

from noisevar.cli import main
from noisevar.cli.dashboard import config_settings

ROOT = Path(__file__).resolve().parents[1]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def _listening(port: int) -> list[str]:
    """Local addresses listening on ``port``, read from /proc/net/tcp and tcp6."""
    found = []
    for table in ("/proc/net/tcp", "/proc/net/tcp6"):
        for line in Path(table).read_text().splitlines()[1:]:
            fields = line.split()
            addr, hexport = fields[1].rsplit(":", 1)
            if int(hexport, 16) == port and fields[3] == "0A":  # 0A: LISTEN
                found.append(addr)
    return found


def _handshake(port: int, host: str, origin: str) -> str:
    """The status line of a websocket handshake with these Host and Origin headers."""
    key = base64.b64encode(os.urandom(16)).decode()
    request = (
        f"GET /_stcore/stream HTTP/1.1\r\nHost: {host}\r\nOrigin: {origin}\r\n"
        "Upgrade: websocket\r\nConnection: Upgrade\r\nSec-WebSocket-Version: 13\r\n"
        f"Sec-WebSocket-Key: {key}\r\n\r\n"
    )
    with socket.create_connection(("127.0.0.1", port), timeout=10) as s:
        s.sendall(request.encode())
        return s.recv(4096).decode(errors="replace").splitlines()[0]


def test_every_config_setting_is_passed_explicitly(capsys):
    assert main(["dashboard", "--print-command"]) == 0
    cmd = capsys.readouterr().out
    for key in config_settings():
        assert f"--{key}=" in cmd, key
    assert "--server.address=127.0.0.1" in cmd
    assert "--server.enableXsrfProtection=true" in cmd
    assert str(ROOT / "app.py") in cmd


@pytest.mark.parametrize(
    "argv",
    [
        ["--address", "0.0.0.0"],
        ["--port", "0"],
        ["--port", "70000"],
        ["--max-upload-mb", "0"],
    ],
)
def test_bad_options_are_one_error(argv, capsys):
    assert main(["dashboard", *argv, "--print-command"]) == 2
    err = capsys.readouterr().err
    assert err.startswith("noisevar: error:") and err.count("\n") == 1


def test_started_from_another_directory_it_listens_on_loopback_only(tmp_path):
    # a hostile config in the current directory: every interface, no XSRF, no host check
    (tmp_path / ".streamlit").mkdir()
    (tmp_path / ".streamlit" / "config.toml").write_text(
        '[server]\naddress = "0.0.0.0"\nenableXsrfProtection = false\nenableCORS = false\n'
    )
    port = _free_port()
    proc = subprocess.Popen(
        [sys.executable, "-m", "noisevar", "dashboard", "--port", str(port)],
        cwd=tmp_path,
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
        start_new_session=True,
    )
    try:
        deadline = time.monotonic() + 60
        while not _listening(port) and time.monotonic() < deadline:
            assert proc.poll() is None, "the dashboard exited"
            time.sleep(0.2)
        assert _listening(port) == ["0100007F"], _listening(port)  # 127.0.0.1, no tcp6
        environ = Path(f"/proc/{proc.pid}/environ").read_bytes().split(b"\0")
        assert b"MALLOC_MMAP_THRESHOLD_=1048576" in environ  # freed arrays go back
        # the websocket is refused under a foreign Host (DNS rebinding), accepted locally
        assert " 101 " in _handshake(port, f"127.0.0.1:{port}", f"http://127.0.0.1:{port}")
        foreign = _handshake(port, f"evil.example:{port}", f"http://evil.example:{port}")
        assert " 101 " not in foreign, foreign
    finally:
        os.killpg(proc.pid, signal.SIGTERM)
        proc.wait(timeout=30)
    assert not _listening(port)

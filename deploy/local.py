"""The proxy recipe on loopback: app processes behind Debian's nginx, started and stopped.

Used by ``tests/test_deploy_nginx.py`` and ``benchmarks/load.py``; also a way to try the
recipe: ``python deploy/local.py --apps 2 --port 8080`` (Ctrl-C stops everything).
The configuration served is ``deploy/nginx.conf`` with its ports, and its pid and log
paths moved into a temporary folder: nothing else is changed.
"""

from __future__ import annotations

import argparse
import os
import re
import shutil
import signal
import socket
import subprocess
import sys
import tempfile
import time
from dataclasses import dataclass, field
from pathlib import Path

HERE = Path(__file__).resolve().parent
RECIPE = HERE / "nginx.conf"


def free_port() -> int:
    """A free TCP port on 127.0.0.1."""
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return int(s.getsockname()[1])


def wait_listening(port: int, timeout: float = 60.0) -> None:
    """Return once something accepts connections on 127.0.0.1:``port``."""
    deadline = time.monotonic() + timeout
    while time.monotonic() < deadline:
        try:
            with socket.create_connection(("127.0.0.1", port), timeout=1):
                return
        except OSError:
            time.sleep(0.2)
    raise TimeoutError(f"nothing listens on port {port} after {timeout:.0f} s")


def render(app_ports: list[int], port: int, folder: Path) -> str:
    """``deploy/nginx.conf`` for these ports, with its pid and logs in ``folder``."""
    text = RECIPE.read_text()
    servers = "".join(f"        server 127.0.0.1:{p};\n" for p in app_ports)
    text = re.sub(r"(        server 127\.0\.0\.1:\d+;\n)+", servers, text)
    text = text.replace("listen 8080", f"listen 127.0.0.1:{port}")
    text = re.sub(r"^pid .*;", f"pid {folder / 'nginx.pid'};", text, flags=re.M)
    text = re.sub(r"error_log /var/log/nginx/\S+", f"error_log {folder / 'error.log'}", text)
    text = re.sub(r"access_log /var/log/nginx/\S+", f"access_log {folder / 'access.log'}", text)
    temp = "".join(
        f"    {kind}_temp_path {folder / kind};\n"
        for kind in ("client_body", "proxy", "fastcgi", "uwsgi", "scgi")
    )
    return text.replace("http {\n", "http {\n" + temp, 1)


@dataclass
class Deployment:
    """App processes and nginx on loopback (stop with :meth:`stop`)."""

    port: int
    app_ports: list[int]
    folder: Path
    procs: list[subprocess.Popen] = field(default_factory=list)

    @property
    def url(self) -> str:
        return f"http://127.0.0.1:{self.port}/"

    def app_pids(self) -> list[int]:
        return [p.pid for p in self.procs[:-1]]

    def access_log(self) -> str:
        path = self.folder / "access.log"
        return path.read_text() if path.is_file() else ""

    def stop(self) -> None:
        for proc in reversed(self.procs):
            if proc.poll() is None:
                os.killpg(proc.pid, signal.SIGTERM)
        for proc in self.procs:
            try:
                proc.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(proc.pid, signal.SIGKILL)
                proc.wait()
        shutil.rmtree(self.folder, ignore_errors=True)


def start(apps: int = 2, port: int | None = None, env: dict[str, str] | None = None) -> Deployment:
    """Start ``apps`` dashboard processes (``noisevar dashboard``) and nginx in front."""
    nginx = shutil.which("nginx") or "/usr/sbin/nginx"
    folder = Path(tempfile.mkdtemp(prefix="noisevar-proxy-"))
    dep = Deployment(port or free_port(), [free_port() for _ in range(apps)], folder)
    try:
        for app_port in dep.app_ports:
            cmd = [sys.executable, "-m", "noisevar", "dashboard", "--port", str(app_port)]
            dep.procs.append(_spawn(cmd, folder / f"app-{app_port}.log", env))
        for app_port in dep.app_ports:
            wait_listening(app_port)
        conf = folder / "nginx.conf"
        conf.write_text(render(dep.app_ports, dep.port, folder))
        cmd = [nginx, "-e", "stderr", "-p", str(folder), "-c", str(conf), "-g", "daemon off;"]
        dep.procs.append(_spawn(cmd, folder / "nginx.log", env))
        wait_listening(dep.port, 20)
    except BaseException:
        dep.stop()
        raise
    return dep


def _spawn(cmd: list[str], log: Path, env: dict[str, str] | None) -> subprocess.Popen:
    with log.open("wb") as out:
        return subprocess.Popen(
            cmd,
            stdout=out,
            stderr=subprocess.STDOUT,
            start_new_session=True,
            env={**os.environ, **(env or {})},
        )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--apps", type=int, default=2)
    parser.add_argument("--port", type=int, default=8080)
    args = parser.parse_args()
    dep = start(args.apps, args.port)
    print(f"{dep.url} -> apps on ports {dep.app_ports} (Ctrl-C stops)")
    try:
        signal.pause()
    except KeyboardInterrupt:
        pass
    finally:
        dep.stop()


if __name__ == "__main__":
    main()

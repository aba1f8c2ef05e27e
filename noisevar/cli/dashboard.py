"""``noisevar dashboard``: start the Streamlit app with its settings passed explicitly.

``streamlit run app.py`` reads ``.streamlit/config.toml`` from the current directory (and
the user's home): started from anywhere else, Streamlit's own defaults apply and the
server listens on every interface. This launcher reads the app's own
``.streamlit/config.toml`` (the one home of the settings, next to ``app.py``) and passes
every setting on the command line, which takes precedence over any other config file, then
adds its own: the address (``127.0.0.1`` unless ``--serve-others`` or ``--address``),
the port, XSRF and CORS protection on, and the Host allow-list that refuses a websocket
whose Host header is not one of the names the app is served under (DNS rebinding).
noisevar never imports Streamlit: the app runs as ``python -m streamlit run``, in the
launcher's own process (``exec``), so that stopping the launcher stops the server.
"""

from __future__ import annotations

import argparse
import ipaddress
import os
import socket
import subprocess
import sys
import tomllib
from pathlib import Path
from typing import Any

from noisevar.errors import NoisevarError

#: The source checkout's root, where ``app.py`` and ``.streamlit/config.toml`` live.
ROOT = Path(__file__).resolve().parents[2]
#: Port of a local run (Streamlit's usual one).
DEFAULT_PORT = 8501
#: Host names of the local machine, always accepted.
LOCAL_HOSTS = ("localhost", "127.0.0.1", "::1")
#: The C allocator's settings for the server, unless the environment sets them: every block
#: of 1 MiB or more (an array of 131,072 float64 samples) is its own mapping, returned to
#: the system when freed, and two arenas at most. By default glibc raises that threshold
#: after each free (up to 32 MiB) and gives threads their own arenas, so the arrays of
#: records opened by many sessions (one script thread each) stay in the server's memory.
MALLOC_ENV = {"MALLOC_MMAP_THRESHOLD_": "1048576", "MALLOC_ARENA_MAX": "2"}
#: Settings the launcher always passes, whatever the config file says.
SAFE_SETTINGS: dict[str, object] = {
    "server.headless": True,
    "server.enableXsrfProtection": True,
    "server.enableCORS": True,
    "server.enableStaticServing": False,
    "server.runOnSave": False,
    "server.fileWatcherType": "none",
    "browser.gatherUsageStats": False,
}


def app_path(root: Path = ROOT) -> Path:
    """The dashboard's ``app.py``, or one clear error when this install has none."""
    app = root / "app.py"
    if not app.is_file():
        raise NoisevarError(
            f"the dashboard's app.py is not in {root}: the dashboard runs from a source "
            "checkout (pip install -e '.[app]')"
        )
    return app


def config_settings(root: Path = ROOT) -> dict[str, object]:
    """Every setting of the app's ``.streamlit/config.toml``, as ``{"section.key": value}``."""
    path = root / ".streamlit" / "config.toml"
    if not path.is_file():
        return {}
    with path.open("rb") as fh:
        table = tomllib.load(fh)
    return {
        f"{section}.{key}": value
        for section, values in table.items()
        if isinstance(values, dict)
        for key, value in values.items()
    }


def _flag_values(value: object) -> list[str]:
    if isinstance(value, bool):
        return ["true" if value else "false"]
    if isinstance(value, list | tuple):
        return [str(v) for v in value]
    return [str(value)]


def allowed_hosts(address: str, extra: list[str], serve_others: bool) -> list[str]:
    """The Host names the server accepts a websocket under (``server.allowedHosts``).

    Parameters
    ----------
    address : str
        The address the server listens on.
    extra : list of str
        Names given with ``--allowed-host`` (the name others reach the app by).
    serve_others : bool
        Also accept this machine's own names (``hostname``, its fully qualified name).

    Returns
    -------
    list of str
    """
    hosts = [*LOCAL_HOSTS, *extra]
    if serve_others:
        hosts += [socket.gethostname(), socket.getfqdn()]
    try:
        if not ipaddress.ip_address(address).is_unspecified:
            hosts.append(address)
    except ValueError:
        hosts.append(address)  # a host name given as the address
    return list(dict.fromkeys(h.strip().lower() for h in hosts if h.strip()))


def streamlit_command(args: argparse.Namespace, root: Path = ROOT) -> list[str]:
    """The ``python -m streamlit run`` command line, every setting explicit."""
    address = args.address or ("0.0.0.0" if args.serve_others else "127.0.0.1")
    serve_others = args.serve_others or not ipaddress.ip_address(_ip_of(address)).is_loopback
    settings = {**config_settings(root), **SAFE_SETTINGS}
    settings["server.address"] = address
    settings["server.port"] = args.port
    settings["server.allowedHosts"] = allowed_hosts(address, args.allowed_host, serve_others)
    if args.max_upload_mb is not None:
        settings["server.maxUploadSize"] = args.max_upload_mb
    cmd = [sys.executable, "-m", "streamlit", "run", str(app_path(root))]
    for key, value in settings.items():
        cmd += [f"--{key}={v}" for v in _flag_values(value)]
    return cmd


def _ip_of(address: str) -> str:
    try:
        return str(ipaddress.ip_address(address))
    except ValueError:
        try:
            return socket.gethostbyname(address)
        except OSError as exc:
            raise NoisevarError(f"--address {address!r}: not an address of this machine") from exc


def _check(args: argparse.Namespace) -> None:
    if not 1 <= args.port <= 65535:
        raise NoisevarError(f"--port {args.port}: choose 1 to 65535")
    if args.max_upload_mb is not None and not 1 <= args.max_upload_mb <= 4096:
        raise NoisevarError(f"--max-upload-mb {args.max_upload_mb}: choose 1 to 4096")
    if args.address and not args.serve_others:
        ip = ipaddress.ip_address(_ip_of(args.address))
        if not ip.is_loopback:
            raise NoisevarError(
                f"--address {args.address} serves other machines: add --serve-others to say so"
            )


def _cmd_dashboard(args: argparse.Namespace) -> int:
    _check(args)
    cmd = streamlit_command(args)
    if args.print_command:
        print(" ".join(cmd))
        return 0
    env = {**MALLOC_ENV, **os.environ}
    if args.memory_mb is not None:
        env["NOISEVAR_MEMORY_MB"] = str(args.memory_mb)
    sys.stdout.flush()
    os.chdir(ROOT)  # the app's own folder: no other directory's config or files
    if os.name == "posix":  # the launcher becomes the server: stopping one stops the other
        os.execve(sys.executable, cmd, env)
    return subprocess.call(cmd, env=env)  # pragma: no cover - Windows


def add_parser(sub: Any) -> None:
    """Register ``dashboard`` on the sub-command set ``sub``."""
    p = sub.add_parser(
        "dashboard",
        help="start the dashboard (127.0.0.1 only unless --serve-others)",
        description="Start the Streamlit dashboard with its settings passed explicitly, "
        "from any directory. It listens on 127.0.0.1 only; --serve-others opens it to the "
        "network (put it behind the README's proxy recipe).",
    )
    p.add_argument("--port", type=int, default=DEFAULT_PORT, help="port (default 8501)")
    p.add_argument(
        "--serve-others",
        action="store_true",
        help="listen on every interface (or --address) and accept this machine's names",
    )
    p.add_argument("--address", help="address to listen on (not loopback: needs --serve-others)")
    p.add_argument(
        "--allowed-host",
        action="append",
        default=[],
        metavar="NAME",
        help="a Host name the app is reached by (repeat; '*' accepts any: not recommended)",
    )
    p.add_argument("--max-upload-mb", type=int, help="largest upload (default: the config's)")
    p.add_argument(
        "--memory-mb",
        type=int,
        help="memory budget of the server's cached results (MB; default: NOISEVAR_MEMORY_MB, "
        "else dashboard/budget.py's)",
    )
    p.add_argument(
        "--print-command", action="store_true", help="print the streamlit command and exit"
    )
    p.set_defaults(func=_cmd_dashboard)

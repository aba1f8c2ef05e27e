"""CPU taken by the browser and by the dashboard server while ``load.py`` runs (issue 29).

:class:`CpuSampler` reads every process's CPU time (``/proc/PID/stat``: user + system)
every quarter of a second on a thread of its own and adds each process's increments to
its class: ``server`` (the dashboard server's process and its descendants: fork server,
pool workers), ``browser`` (Chromium's processes) or ``other``. ``load.py`` runs one
beside its waves and reports each wave's CPU-s per interaction. Run alone, it samples
every process by its command line, as the first version did::

    python benchmarks/cpu_split.py OUT.log &
    python benchmarks/load.py --waves 1 4 8 --shared 0 --proxy 0 --big 0
    kill %1

Each line of ``OUT.log``: unix time, then the running totals (CPU-s) of browser and server
processes since the sampler started.

Notes
-----
A process that exits between two looks loses at most its last quarter of a second (a
Chromium renderer ends once, when its session's context closes). A process started since the
previous look counts all its CPU; one already running at the first look counts from
there. Processes are told apart by (pid, start time), so a reused pid is a new process.
"""

from __future__ import annotations

import os
import sys
import threading
import time
from pathlib import Path

TICK = os.sysconf("SC_CLK_TCK")
#: Seconds between two looks.
PERIOD_S = 0.25


def _stat(pid: str) -> tuple[int, float, float, str] | None:
    """(parent pid, start time in ticks, CPU-s, command name) of a process, or None."""
    try:
        text = Path(f"/proc/{pid}/stat").read_text()
    except OSError:
        return None
    name = text[text.find("(") + 1 : text.rfind(")")]
    fields = text[text.rfind(")") + 2 :].split()
    return int(fields[1]), float(fields[19]), (int(fields[11]) + int(fields[12])) / TICK, name


def _tree(stats: dict[int, tuple[int, float, float, str]], root: int) -> set[int]:
    """``root`` and its descendants among ``stats`` (pid -> (parent, ...))."""
    tree, grew = {root}, True
    while grew:
        new = {p for p, s in stats.items() if s[0] in tree and p not in tree}
        tree |= new
        grew = bool(new)
    return tree


def category(cmd: str) -> str:
    """``browser``, ``server`` or ``other``, by a process's command line (stand-alone use)."""
    if "chrom" in cmd:
        return "browser"
    if any(k in cmd for k in ("streamlit", "dashboard", "multiprocessing")):
        return "server"
    return "other"


class CpuSampler:
    """Running CPU-s totals by class: ``server`` (``server_pid`` and its descendants),
    ``browser`` (Chromium), ``driver`` (``client_pid`` and its other descendants: the
    benchmark and Playwright's driver), ``other``.

    Parameters
    ----------
    server_pid : int
        The dashboard server's process id.
    client_pid : int, optional
        The benchmark's own process id.
    own_browser : bool
        Count as ``browser`` only the Chromium processes ``client_pid`` started (other
        jobs' browsers, such as another benchmark's or a test's, go to ``other``).
    """

    def __init__(
        self, server_pid: int, client_pid: int | None = None, own_browser: bool = False
    ) -> None:
        self.server_pid = server_pid
        self.client_pid = client_pid
        self.own_browser = own_browser
        self.totals = {"server": 0.0, "browser": 0.0, "driver": 0.0, "other": 0.0}
        self._seen: dict[tuple[int, float], float] = {}
        self._stop = threading.Event()
        self._lock = threading.Lock()
        self._thread = threading.Thread(target=self._run, daemon=True)
        self._last = float("inf")  # the previous look, in ticks since boot

    def look(self) -> None:
        """Add every process's CPU since the last look to its class."""
        now = float(Path("/proc/uptime").read_text().split()[0]) * TICK
        stats = {}
        for entry in os.listdir("/proc"):
            if entry.isdigit() and (s := _stat(entry)) is not None:
                stats[int(entry)] = s
        server = _tree(stats, self.server_pid)
        client = _tree(stats, self.client_pid) if self.client_pid else set()
        with self._lock:
            for pid, (_, start, cpu, name) in stats.items():
                key = (pid, start)
                if key not in self._seen:  # new since the last look: all its CPU counts
                    self._seen[key] = 0.0 if start >= self._last else cpu
                if pid in server:
                    kind = "server"
                elif "chrom" in name.lower() and (not self.own_browser or pid in client):
                    kind = "browser"
                else:
                    kind = "driver" if pid in client else "other"
                self.totals[kind] += cpu - self._seen[key]
                self._seen[key] = cpu
            self._last = now

    def snapshot(self) -> dict[str, float]:
        """The running totals now (after a fresh look)."""
        self.look()
        with self._lock:
            return dict(self.totals)

    def _run(self) -> None:
        while not self._stop.wait(PERIOD_S):
            self.look()

    def start(self) -> CpuSampler:
        self.look()
        self._thread.start()
        return self

    def stop(self) -> None:
        self._stop.set()
        self._thread.join(timeout=5)


def main(path: str) -> None:
    import psutil

    seen: dict[tuple[int, float], float] = {}
    total = {"browser": 0.0, "server": 0.0, "other": 0.0}
    with open(path, "w", encoding="utf-8") as out:
        while True:
            for p in psutil.process_iter(["cmdline"]):
                try:
                    t = p.cpu_times()
                    key = (p.pid, p.create_time())
                except psutil.Error:
                    continue
                now = t.user + t.system
                total[category(" ".join(p.info["cmdline"] or []))] += now - seen.get(key, now)
                seen[key] = now
            out.write(f"{time.time():.0f} {total['browser']:.1f} {total['server']:.1f}\n")
            out.flush()
            time.sleep(1.0)


if __name__ == "__main__":
    main(sys.argv[1])

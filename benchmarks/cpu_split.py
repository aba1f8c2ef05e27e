"""CPU taken by the browser and by the dashboard server while ``load.py`` runs (issue 29).

Samples every process once a second (psutil) and sums each one's CPU-time increments by
its command line: Chromium's processes, the server's (Streamlit app, fork server, pool
workers), the rest. Run it beside the load benchmark and stop it after::

    python benchmarks/cpu_split.py OUT.log &
    python benchmarks/load.py --waves 1 4 8 --shared 0 --proxy 0 --big 0
    kill %1

Each line of ``OUT.log``: unix time, then the running totals (CPU-s) of browser, server
and other processes since the sampler started.
"""

from __future__ import annotations

import sys
import time

import psutil


def category(cmd: str) -> str:
    """``browser``, ``server`` or ``other``, by a process's command line."""
    if "chrom" in cmd:
        return "browser"
    if any(k in cmd for k in ("streamlit", "dashboard", "multiprocessing")):
        return "server"
    return "other"


def main(path: str) -> None:
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

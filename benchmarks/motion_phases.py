"""Where `auto`'s time goes on a record with motion: CPU seconds per phase (issue 26).

    python benchmarks/motion_phases.py [--repeats 5] [--against DIR] [--rounds 5]

The record is ``speed.py``'s ``auto (motion)`` one (1e6 samples, five bursts). Each phase is
timed by wrapping the pipeline's steps (process CPU time, every thread): pass one (the
estimate and the diagnostic sums), the coloured-noise pass, the diagnostics from their sums
(PELT and the power-law identification shown apart), the reversed grid's profile pass (with
its PELT) and the still stretches' estimates. Each is given against one third-order
``lfilter`` pass over 1e6 samples (CPU, the least measured in the same process).
``--against DIR`` runs each round in fresh processes, alternating this checkout with the
package under ``DIR`` (``PYTHONPATH``; e.g. an export of main), and reports the medians
of both. The critical path CPU is the total less the shorter of each pair of parts that
run at once (:meth:`ChunkedAuto.branches`; the power law beside the profile): what the
wall time would be on idle cores, whatever the other jobs do. ``--workers 1`` runs all
one after the other. Writes ``benchmarks/results/motion_phases.md``.
"""

from __future__ import annotations

import argparse
import json
import os
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np

HERE = Path(__file__).resolve().parent
RESULTS = HERE / "results"
PHASES = (
    "pass one (estimate + diagnostic sums)",
    "coloured-noise pass (span 5)",
    "diagnostics from their sums",
    "  of which the power-law identification",
    "  PELT on both grids' profiles (its halves in the row above and the reversed pass)",
    "reversed grid's profile pass (with its PELT)",
    "still stretches' estimates",
    "total",
)
#: Rows computed from the phases (not timed by a wrapper).
CRITICAL = "critical path CPU (pass one + the longer of each pair of parallel parts)"
WALL = "wall time (mean)"


def _measure(repeats: int, workers: int) -> dict[str, float]:
    """CPU seconds per phase (mean over ``repeats``) and the least lfilter CPU time."""
    from scipy import signal

    import noisevar
    from noisevar import diagnostics
    from noisevar.diagnostics import power_law, regimes
    from noisevar.estimators.auto import chunked

    sys.path.insert(0, str(HERE))
    from speed import motion_record

    acc: dict[str, float] = {}
    local = threading.local()  # inside a branch: its thread's CPU time is its own

    def clock() -> float:
        return time.thread_time() if getattr(local, "branch", False) else time.process_time()

    def timed(f, label, clock=clock):
        def g(*a, **k):
            c = clock()
            try:
                return f(*a, **k)
            finally:
                acc[label] = acc.get(label, 0.0) + clock() - c

        return g

    def in_branch(f, label):
        def g():
            local.branch = True
            c = time.thread_time()
            try:
                return f()
            finally:
                acc[label] = acc.get(label, 0.0) + time.thread_time() - c
                local.branch = False

        return g

    branches = getattr(chunked.ChunkedAuto, "branches", None)
    if branches is not None:  # the coloured-noise pass and the still levels at once

        def both(self, *work):
            return branches(self, *(in_branch(w, f"branch {i}") for i, w in enumerate(work)))

        chunked.ChunkedAuto.branches = both
    init = chunked.ChunkedAuto.__init__

    def init_workers(self, *a, **k):
        k.setdefault("workers", workers)
        init(self, *a, **k)

    chunked.ChunkedAuto.__init__ = init_workers

    ca = chunked.ChunkedAuto
    estimate = ca.estimate

    def est(self, params):
        if not self.diagnostics:
            label = PHASES[6]
        else:
            label = PHASES[1] if "span" in params else PHASES[0]
        return timed(estimate, label)(self, params)

    ca.estimate = est
    ca.diagnose = timed(ca.diagnose, PHASES[2])
    ca.still_ranges = timed(ca.still_ranges, PHASES[5])
    regimes._pelt = timed(regimes._pelt, PHASES[4], time.thread_time)  # one thread, Python
    # beside the profile, in a thread of its own (or the diagnostics' thread)
    diagnostics.power_law_types = timed(power_law.power_law_types, PHASES[3], time.thread_time)
    x = motion_record(1_000_000)
    z = noisevar.generate("gps-circle", n=1_000_000, seed=3).measured
    b, a = signal.butter(3, 0.05)
    noisevar.estimate(x, method="auto")  # warm caches
    acc.clear()
    total, wall, ref = 0.0, 0.0, np.inf
    for _ in range(repeats):
        c0 = time.process_time()
        signal.lfilter(b, a, z)
        c1, t1 = time.process_time(), time.perf_counter()
        noisevar.estimate(x, method="auto")
        total += time.process_time() - c1
        wall += time.perf_counter() - t1
        ref = min(ref, c1 - c0)
    out = {k: v / repeats for k, v in acc.items()}
    out[PHASES[-1]] = total / repeats
    out[WALL] = wall / repeats
    # the shorter of two parts that run at once is off the critical path
    law, diag = out.get(PHASES[3], 0.0), out.get(PHASES[2], 0.0)
    off = min(law, diag - law) if branches is not None and workers > 1 else 0.0
    if "branch 1" in out and workers > 1:
        off += min(out["branch 0"], out["branch 1"])
    out[CRITICAL] = out[PHASES[-1]] - off
    out["lfilter"] = float(ref)
    return out


def _in_process(path: str | None, repeats: int, workers: int, nice: int) -> dict[str, float]:
    env = dict(os.environ)
    if path is not None:
        env["PYTHONPATH"] = path
    cmd = ["nice", "-n", str(nice), sys.executable, __file__, "--child", "--repeats", str(repeats)]
    cmd += ["--workers", str(workers)]
    out = subprocess.run(cmd, env=env, capture_output=True, text=True, check=True)
    return json.loads(out.stdout)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print Markdown."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--repeats", type=int, default=5)
    ap.add_argument("--rounds", type=int, default=5)
    ap.add_argument("--against", help="a directory holding another noisevar package")
    ap.add_argument("--nice", type=int, default=10)
    ap.add_argument("--workers", type=int, default=2, help="threads of the chunked engine")
    ap.add_argument("--child", action="store_true", help=argparse.SUPPRESS)
    args = ap.parse_args(argv)
    if args.child:
        print(json.dumps(_measure(args.repeats, args.workers)))
        return 0
    here = str(HERE.parent)
    runs: dict[str, list[dict[str, float]]] = {"this": []}
    if args.against:
        runs["against"] = []
    for _ in range(args.rounds):
        runs["this"].append(_in_process(here, args.repeats, args.workers, args.nice))
        if args.against:
            runs["against"].append(_in_process(args.against, args.repeats, args.workers, args.nice))
    lf = float(np.median([r["lfilter"] for rs in runs.values() for r in rs]))
    head = "| phase | CPU ms per 1e6 | x one lfilter pass |"
    rule = "|---|---|---|"
    if args.against:
        head += " against: CPU ms | x lfilter |"
        rule += "---|---|"
    lines = [
        "### `auto (motion)` by phase (`python benchmarks/motion_phases.py`)",
        "",
        f"Medians over {args.rounds} processes of the mean of {args.repeats} runs each; "
        f"one lfilter pass {1000 * lf:.1f} ms CPU; load average at the end "
        f"{os.getloadavg()[0]:.1f}"
        + (f"; against `{args.against}`, alternated" if args.against else "")
        + f"; {args.workers} threads (`--workers`), `nice -n {args.nice}`. Parts that run at once "
        "(the coloured-noise pass beside the reversed pass and the still estimates; the "
        "power-law identification beside the rest of the diagnostics) are each their own "
        "thread's CPU time; the wall row is over the lfilter pass's CPU time.",
        "",
        head,
        rule,
    ]
    for phase in (*PHASES, CRITICAL, WALL):
        row = f"| {phase.strip()} |"
        for rs in runs.values():
            ms = 1000 * float(np.median([r.get(phase, 0.0) for r in rs]))
            row += f" {ms:.1f} | {ms / (1000 * lf):.1f} |"
        lines.append(row)
    text = "\n".join(lines)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "motion_phases.md").write_text(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

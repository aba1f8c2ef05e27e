"""Speed and memory of every estimator on 1e6 samples.

    python benchmarks/speed.py [--n 1000000] [--repeats 5]

Reports seconds per 1e6 samples (best of ``repeats``), the ratio to one
third-order ``scipy.signal.lfilter`` pass over the same array measured in the
same run (the lfilter pass is timed again just before every repetition of
every method, and the ratio uses the best lfilter time seen beside that
method, so a machine whose load changes during the run does not skew it), the
least CPU time of the process (all threads) per 1e6 samples and its ratio to
the same lfilter pass's least CPU time (less moved by other jobs than the elapsed
time; before issue 26's second speed round it was over the pass's elapsed time,
which reads low on a loaded machine), and
the peak memory traced by ``tracemalloc`` over the input array's
size. The MLE methods are timed on 1e5 samples and scaled (one fit on 1e6
samples takes minutes). ``auto (motion)`` is ``auto`` on a record with motion
(:func:`motion_record`: the case its regimes, still stretches and coloured-noise
pass exist for). Prints Markdown; also writes ``benchmarks/results/speed.md``.
"""

from __future__ import annotations

import argparse
import os
import platform
import sys
import time
import tracemalloc
from pathlib import Path

import numpy as np
from scipy import signal

import noisevar

RESULTS = Path(__file__).resolve().parent / "results"
SLOW = {"mle-level": 100_000, "mle-trend": 100_000}


def _best_time(fn, repeats: int) -> float:
    best = np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return float(best)


def _best_time_beside(fn, reference, repeats: int) -> tuple[float, float, float, float]:
    """Best times of ``fn`` and of ``reference``, each run just before ``fn`` every time.

    The third and fourth values are the least CPU times (the process's, every thread's)
    of ``fn`` and of ``reference``: less moved by other jobs on the machine than the
    elapsed times, and compared with each other (a CPU time over an elapsed one reads
    low on a loaded machine).
    """
    best, best_ref, best_cpu, best_ref_cpu = np.inf, np.inf, np.inf, np.inf
    for _ in range(repeats):
        t0 = time.perf_counter()
        c0 = time.process_time()
        reference()
        c1 = time.process_time()
        t1 = time.perf_counter()
        fn()
        c2 = time.process_time()
        t2 = time.perf_counter()
        best_ref, best = min(best_ref, t1 - t0), min(best, t2 - t1)
        best_cpu, best_ref_cpu = min(best_cpu, c2 - c1), min(best_ref_cpu, c1 - c0)
    return float(best), float(best_ref), float(best_cpu), float(best_ref_cpu)


def motion_record(n: int, seed: int = 1) -> np.ndarray:
    """White noise (σ = 1) with a burst of motion every 200,000 samples from sample 50,000.

    Each burst: 30,000 samples of a sinusoid of period 40 samples and amplitude 20 times
    a normal factor (mean 1, sd 0.3); seeded.
    """
    rng = np.random.default_rng(seed)
    x = rng.normal(size=n)
    t = np.arange(n)
    for s in range(50_000, n, 200_000):
        burst = slice(s, s + 30_000)
        x[burst] += 20 * np.sin(2 * np.pi * t[burst] / 40) * rng.normal(1, 0.3)
    return x


def _peak_bytes(fn) -> int:
    tracemalloc.start()
    tracemalloc.reset_peak()
    fn()
    _, peak = tracemalloc.get_traced_memory()
    tracemalloc.stop()
    return int(peak)


def main(argv: list[str] | None = None) -> int:
    """Run the benchmark and print Markdown."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=1_000_000)
    ap.add_argument("--repeats", type=int, default=5)
    args = ap.parse_args(argv)
    g = noisevar.generate("gps-circle", n=args.n, seed=3)
    z = g.measured
    b, a = signal.butter(3, 0.05)
    t_lfilter = _best_time(lambda: signal.lfilter(b, a, z), args.repeats * 2)
    rows = []
    motion = motion_record(args.n)
    for method in [*noisevar.methods(), "auto (motion)"]:
        kw = {}
        if method == "somd-redundant":
            kw["reference"] = g.clean + np.random.default_rng(4).normal(0, 0.5, args.n)
        n = SLOW.get(method, args.n)
        x = motion if method == "auto (motion)" else z[:n]
        if "reference" in kw:
            kw["reference"] = kw["reference"][:n]
        label, method = method, method.split(" ")[0]
        noisevar.estimate(x, method=method, **kw)  # warm caches (c(h), sequences)
        reps = 1 if method in SLOW else args.repeats
        t, t_ref, cpu, cpu_ref = _best_time_beside(
            lambda x=x, kw=kw, m=method: noisevar.estimate(x, method=m, **kw),
            lambda: signal.lfilter(b, a, z),
            reps,
        )
        t_lfilter = min(t_lfilter, t_ref)
        per_million = t * 1_000_000 / n
        peak = (
            _peak_bytes(lambda x=x, kw=kw, m=method: noisevar.estimate(x, method=m, **kw))
            if method not in SLOW
            else None
        )
        ref = t_ref * 1_000_000 / args.n
        cpu, cpu_ref = cpu * 1_000_000 / n, cpu_ref * 1_000_000 / args.n
        rows.append((label, n, per_million, per_million / ref, peak, cpu, cpu / cpu_ref))
    lines = [
        f"### Speed (`python benchmarks/speed.py`), n = {args.n:,}, "
        f"{platform.machine()}, {os.cpu_count()} cores, numpy {np.__version__}",
        "",
        f"One third-order `lfilter` pass over the same {args.n:,} samples: "
        f"{1000 * t_lfilter:.1f} ms (best over the run; each method's ratio uses the best "
        "lfilter time measured beside it).",
        "",
        "| method | s per 1e6 samples | x one lfilter pass | CPU s per 1e6 (all threads) "
        "| CPU x one lfilter pass's CPU | peak memory / input array |",
        "|---|---|---|---|---|---|",
    ]
    for method, n, per_million, ratio, peak, cpu, cpu_ratio in rows:
        mem = "—" if peak is None else f"{peak / z.nbytes:.1f}x"
        note = f" (timed on {n:,})" if n != args.n else ""
        lines.append(
            f"| {method} | {per_million:.3f}{note} | {ratio:.1f} | {cpu:.3f} | {cpu_ratio:.1f} "
            f"| {mem} |"
        )
    auto = next(r for r in rows if r[0] == "auto")
    lines += [
        "",
        f"Targets for `auto`: < 0.5 s per 1e6 samples: {auto[2]:.3f} s "
        f"({'ok' if auto[2] < 0.5 else 'MISSED'}); within 10x one lfilter pass: {auto[3]:.1f}x "
        f"({'ok' if auto[3] <= 10 else 'MISSED'}); peak memory under 30x the input: "
        f"{auto[4] / z.nbytes:.1f}x ({'ok' if auto[4] / z.nbytes < 30 else 'MISSED'}). "
        f"CPU time of `auto` (both threads): {auto[5]:.3f} s, {auto[6]:.1f}x the pass's CPU time. "
        f"Load average at the end: {os.getloadavg()[0]:.1f}.",
    ]
    moving = next(r for r in rows if r[0] == "auto (motion)")
    lines += [
        "",
        f"`auto` on a record with motion (5 bursts, regimes, still stretches and the "
        f"coloured-noise pass all run): {moving[2]:.3f} s per 1e6 samples, {moving[3]:.1f}x "
        f"one lfilter pass ({'ok' if moving[3] <= 10 else 'MISSED'} against 10x); CPU "
        f"{moving[5]:.3f} s, {moving[6]:.1f}x the pass's CPU time.",
    ]
    text = "\n".join(lines)
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "speed.md").write_text(text + "\n")
    print(text)
    return 0


if __name__ == "__main__":
    sys.exit(main())

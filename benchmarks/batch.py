"""Batch throughput: one process, ``--jobs 2``, a dask.distributed cluster; resume after a kill.

    python benchmarks/batch.py [--files 2000] [--n 100000] [--channels 3] [--resume-files 400]

Writes ``--files`` ``.npy`` files of ``--channels`` x ``--n`` float64 samples (random walks
plus white noise) into a temporary folder (deleted at the end), then times
``noisevar.batch`` over all of them:

1. in this process (``jobs=1``; the estimator's compiled code warmed first);
2. with ``jobs=2`` (two local worker processes: their start-up is included);
3. on a ``dask.distributed`` cluster the benchmark starts on loopback (a scheduler and
   two worker processes of one thread each), cluster start-up timed apart: tuned (see
   :func:`_cluster`) and with dask's defaults;
4. per-task overhead: 2,000 no-op tasks through each executor;
5. resume: ``noisevar batch DIR --out noise.parquet`` on the last ``--resume-files`` files
   in a subprocess, SIGKILLed when its journal holds about half of them; the rerun must
   do only the rest.

Every run's rows must equal the first's (``elapsed_s`` aside). The machine is shared, so
the benchmark also measures the machine's own two-process ceiling at the time (a
fixed NumPy workload in one process, then in two at once) and the load average.
Writes ``benchmarks/results/batch.md``.
"""

from __future__ import annotations

import argparse
import multiprocessing
import os
import platform
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

import numpy as np
import pandas as pd

ROOT = Path(__file__).resolve().parents[1]
sys.path.insert(0, str(ROOT))

import noisevar  # noqa: E402
from noisevar.batch import task_size  # noqa: E402
from noisevar.batch._output import read_journal  # noqa: E402
from noisevar.batch._task import run_task  # noqa: E402

RESULTS = ROOT / "benchmarks" / "results"


def _noop(i: int) -> int:
    return i


def _cpu_seconds() -> float:
    import resource

    use = resource.getrusage(resource.RUSAGE_SELF)
    return use.ru_utime + use.ru_stime


def _spin(_: int) -> float:
    """A fixed CPU workload (for the machine's two-process ceiling)."""
    rng = np.random.default_rng(0)
    x = rng.normal(size=200_000)
    t0 = time.perf_counter()
    for _ in range(60):
        x = np.sort(x)[::-1].copy()
    return time.perf_counter() - t0


def make_files(folder: Path, n_files: int, n: int, channels: int, seed: int = 0) -> list[Path]:
    """``n_files`` random-walk-plus-noise records, one ``.npy`` of shape (n, channels) each."""
    rng = np.random.default_rng(seed)
    out = []
    for i in range(n_files):
        walk = np.cumsum(rng.normal(0.0, 0.01, (n, channels)), axis=0)
        path = folder / f"unit{i:05d}.npy"
        np.save(path, walk + rng.normal(0.0, 1.0 + (i % 7) / 10, (n, channels)))
        out.append(path)
    return out


def _rows(frame: pd.DataFrame) -> pd.DataFrame:
    return frame.drop(columns="elapsed_s").reset_index(drop=True)


def _timed(fn):
    t0 = time.perf_counter()
    out = fn()
    return out, time.perf_counter() - t0


def ceiling() -> float:
    """The machine's two-process speed-up now: a fixed workload in one process, then two."""
    ctx = multiprocessing.get_context("spawn")  # the fork server is left to noisevar.batch
    with ProcessPoolExecutor(2, mp_context=ctx) as pool:
        list(pool.map(_spin, [0, 0]))  # start both workers
        _, one = _timed(lambda: list(pool.map(_spin, [0])))
        _, two = _timed(lambda: list(pool.map(_spin, [0, 1])))
    return 2 * one / two


def overhead_pool(n_tasks: int) -> tuple[float, float]:
    """Pool start-up (s) and per-task round trip (s) of two forkserver processes."""
    ctx = multiprocessing.get_context("forkserver")  # set up by the batches before this
    t0 = time.perf_counter()
    with ProcessPoolExecutor(2, mp_context=ctx) as pool:
        list(pool.map(_noop, [0, 1]))
        start = time.perf_counter() - t0
        _, took = _timed(
            lambda: [f.result() for f in [pool.submit(_noop, i) for i in range(n_tasks)]]
        )
    return start, took / n_tasks


def overhead_dask(client, n_tasks: int) -> float:
    """Per-task round trip (s) of the cluster: submit no-op tasks, wait for all."""
    from distributed import wait

    def run() -> None:
        futs = [client.submit(_noop, i, pure=False) for i in range(n_tasks)]
        wait(futs)

    _, took = _timed(run)
    return took / n_tasks


def kill_and_resume(files: list[Path], reference: pd.DataFrame) -> dict:
    """Run the CLI on ``files`` (moved to a folder of their own), SIGKILL it halfway, rerun.

    Returns how many files the rerun did, and whether its table equals ``reference``'s
    rows of those files (the paths changed with the move, the numbers must not).
    """
    n_files = len(files)
    folder = files[0].parent.parent / "resume_logs"
    folder.mkdir()
    for f in files:
        f.rename(folder / f.name)
    moved = {str(f): str(folder / f.name) for f in files}
    reference = reference[reference["file"].isin(moved)].assign(file=lambda d: d["file"].map(moved))
    out = folder.parent / "resume" / "noise.parquet"
    out.parent.mkdir()
    journal = out.with_name(out.name + ".journal.jsonl")
    env = {**os.environ, "PYTHONPATH": str(ROOT)}
    cmd = [sys.executable, "-m", "noisevar", "batch", str(folder), "--out", str(out), "--quiet"]
    proc = subprocess.Popen(cmd, env=env, stderr=subprocess.DEVNULL)
    rows_half = n_files * reference["channel"].nunique() // 2
    while proc.poll() is None:
        if journal.is_file() and sum(1 for _ in journal.open()) >= rows_half:
            proc.send_signal(signal.SIGKILL)
            break
        time.sleep(0.2)
    proc.wait()
    done_before = len({r["file"] for r in read_journal(journal)})
    seen: list[tuple[int, int]] = []
    frame, took = _timed(
        lambda: noisevar.batch(folder, out=out, progress=lambda d, t: seen.append((d, t)))
    )
    same = _rows(frame).equals(_rows(reference))
    return {
        "killed_after": done_before,
        "redone": seen[-1][1],
        "took": took,
        "same": same,
        "files": n_files,
    }


def interleaved(files: list[Path], clients: dict, rounds: int) -> dict[str, list[float]]:
    """One process, ``jobs=2`` and each cluster in turn, ``rounds`` times, on the same files.

    On a shared machine the load changes from minute to minute; alternating them and
    keeping each one's best time compares them under the same conditions.
    """
    runs = {
        "one": lambda: noisevar.batch(files, jobs=1, progress=False),
        "jobs2": lambda: noisevar.batch(files, jobs=2, progress=False),
    }
    for name, client in clients.items():
        runs[name] = lambda c=client: noisevar.batch(files, client=c, progress=False)
    times: dict[str, list[float]] = {k: [] for k in runs}
    for r in range(rounds):
        for name, run in runs.items():
            times[name].append(_timed(run)[1])
        print(
            f"round {r + 1}: " + ", ".join(f"{k} {v[-1]:.1f} s" for k, v in times.items()),
            flush=True,
        )
    return times


def _cluster(tuned: bool):
    """A scheduler and two one-thread worker processes on loopback, and its client.

    ``tuned=False``: dask's defaults. Its nannies start workers with
    ``MALLOC_TRIM_THRESHOLD_=65536`` (glibc returns every freed array at once, and the next
    one is page-faulted in again), and each worker samples its task thread's stack every
    10 ms (the statistical profiler of the dask dashboard). ``tuned=True`` drops both, as
    README advises for a CPU-bound batch; dask's other settings are kept.
    """
    import dask
    from distributed import Client, LocalCluster

    env = dict(dask.config.get("distributed.nanny.pre-spawn-environ"))
    settings: dict = {}
    if tuned:
        env.pop("MALLOC_TRIM_THRESHOLD_", None)
        settings["distributed.worker.profile.enabled"] = False
    with dask.config.set({"distributed.nanny.pre-spawn-environ": env, **settings}):
        cluster = LocalCluster(
            n_workers=2,
            threads_per_worker=1,
            processes=True,
            host="127.0.0.1",
            dashboard_address=None,
            silence_logs=40,
        )
    client = Client(cluster)
    client.wait_for_workers(2)
    return cluster, client


def _full_pass(client, files: list[Path]) -> tuple[pd.DataFrame, float, float]:
    """Every file on the cluster: the table, the wall time and the workers' CPU seconds."""
    noisevar.batch(files[:4], client=client, progress=False)  # the workers' imports warmed
    before = sum(client.run(_cpu_seconds).values())
    frame, took = _timed(lambda: noisevar.batch(files, client=client, progress=False))
    return frame, took, sum(client.run(_cpu_seconds).values()) - before


def cluster_run(files: list[Path], reference: pd.DataFrame, subset: int, rounds: int) -> dict:
    t0 = time.perf_counter()
    cluster, client = _cluster(tuned=True)
    start = time.perf_counter() - t0
    default, dclient = _cluster(tuned=False)
    try:
        frame, took, cpu = _full_pass(client, files)
        print(f"dask (tuned): {took:.1f} s", flush=True)
        dframe, dtook, dcpu = _full_pass(dclient, files)
        print(f"dask (defaults): {dtook:.1f} s", flush=True)
        per_task = overhead_dask(client, 2000)
        clients = {"dask": client, "dask_default": dclient}
        rounds_times = interleaved(files[:subset], clients, rounds)
    finally:
        for c in (client, dclient, cluster, default):
            c.close()
    same = _rows(frame).equals(_rows(reference)) and _rows(dframe).equals(_rows(reference))
    return {
        "start": start,
        "took": took,
        "per_task": per_task,
        "cpu": cpu,
        "rounds": rounds_times,
        "default_took": dtook,
        "default_cpu": dcpu,
        "same": same,
    }


def extrapolate(n_files: int, per_file: float, per_task: float, bytes_per_file: int) -> list:
    """On paper: 1e6 files on 100 nodes (cores per node and storage bandwidth assumed)."""
    lines = []
    for cores, bandwidth in ((32, 2e9), (32, 20e9)):
        workers = 100 * cores
        k = task_size(1_000_000, workers)
        tasks = -(-1_000_000 // k)
        compute = 1_000_000 * per_file / workers
        io = 1_000_000 * bytes_per_file / bandwidth
        sched = tasks * per_task
        lines.append((cores, bandwidth, workers, k, tasks, compute, io, sched))
    return lines


def main() -> None:  # long: one script, its steps in order
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--files", type=int, default=2000)
    ap.add_argument("--n", type=int, default=100_000)
    ap.add_argument("--channels", type=int, default=3)
    ap.add_argument("--subset", type=int, default=100, help="files of the interleaved rounds")
    ap.add_argument("--rounds", type=int, default=3)
    ap.add_argument(
        "--resume-files",
        type=int,
        default=400,
        help="files of the kill-and-resume run (the last ones of the set)",
    )
    args = ap.parse_args()

    tmp = Path(tempfile.mkdtemp(prefix="nv-batch-"))
    signal.signal(signal.SIGTERM, lambda *_: sys.exit(143))  # a stopped run still cleans up
    try:
        folder = tmp / "logs"
        folder.mkdir()
        files, gen = _timed(lambda: make_files(folder, args.files, args.n, args.channels))
        size = files[0].stat().st_size
        print(f"generated {len(files)} files of {size / 1e6:.1f} MB in {gen:.0f} s", flush=True)
        run_task([str(files[0])], "all", "auto", {})  # compiled code loaded in this process
        load = [os.getloadavg()[0]]
        ceil = ceiling()
        print(f"two-process ceiling now: {ceil:.2f}x, load {load[0]:.1f}", flush=True)
        c0 = time.process_time()
        one, t1 = _timed(lambda: noisevar.batch(files, jobs=1, progress=False))
        cpu1 = time.process_time() - c0
        print(f"jobs=1: {t1:.1f} s", flush=True)
        load.append(os.getloadavg()[0])
        two, t2 = _timed(lambda: noisevar.batch(files, jobs=2, progress=False))
        print(f"jobs=2: {t2:.1f} s", flush=True)
        load.append(os.getloadavg()[0])
        dask = cluster_run(files, one, args.subset, args.rounds)
        load.append(os.getloadavg()[0])
        pool_start, pool_task = overhead_pool(2000)
        ceil = (ceil, ceiling())
        resume = kill_and_resume(files[-args.resume_files :], one)
        print(f"resume: {resume}", flush=True)
        load.append(os.getloadavg()[0])
    finally:
        shutil.rmtree(tmp, ignore_errors=True)

    ok = all(r.get("same", True) for r in (dask, resume)) and _rows(two).equals(_rows(one))
    per_file = t1 / len(files)
    paper = extrapolate(len(files), per_file, dask["per_task"], size)
    md = report(
        args,
        len(files),
        size,
        gen,
        (t1, cpu1),
        t2,
        dask,
        pool_start,
        pool_task,
        resume,
        ceil,
        load,
        ok,
        paper,
    )
    RESULTS.mkdir(exist_ok=True)
    (RESULTS / "batch.md").write_text(md)
    print(md)


def _scaled(args, n_files, t1, t2, dask, pool_start) -> list[str]:
    """When fewer than the target 2,000 files were run: what 2,000 would take (on paper)."""
    if n_files >= 2000:
        return []
    k = 2000 / n_files
    # start-up is paid once; the rest grows with the number of files
    e2 = pool_start + (t2 - pool_start) * k
    return [
        f"Extrapolation, not a measurement: {n_files:,} files were run instead of 2,000 (time "
        f"on the shared machine). At the per-file times above, 2,000 files would take about "
        f"{t1 * k:.0f} s in one process, {e2:.0f} s with `--jobs 2` and "
        f"{dask['took'] * k:.0f} s on the cluster (+{dask['start']:.0f} s to start it).",
        "",
    ]


def report(
    args, n_files, size, gen, t1, t2, dask, pool_start, pool_task, resume, ceil, load, ok, paper
) -> str:  # long: the Markdown report, one line per figure
    t1, cpu1 = t1
    samples = n_files * args.channels * args.n
    best = {k: min(v) for k, v in dask["rounds"].items()}
    s2, sd = best["one"] / best["jobs2"], best["one"] / best["dask"]
    sdd = best["one"] / best["dask_default"]
    tick = lambda good: "ok" if good else "NOT met"  # noqa: E731
    lines = [
        f"### Batch (`python benchmarks/batch.py --files {args.files}`), "
        f"{n_files:,} files x {args.channels} channels x {args.n:,} samples "
        f"(.npy, {size / 1e6:.1f} MB each, {n_files * size / 1e9:.1f} GB), method auto, "
        f"{platform.machine()}, {os.cpu_count()} cores, numpy {np.__version__}",
        "",
        f"Files generated in {gen:.0f} s in a temporary folder, deleted after the run. "
        f"Load average (1 min) before and after each step: "
        f"{', '.join(f'{x:.1f}' for x in load)} (the 2 cores are shared with other jobs). "
        f"The machine's own two-process ceiling (a fixed NumPy workload in one process, then in "
        f"two at once) before the timed runs: {ceil[0]:.2f}x, after them: {ceil[1]:.2f}x.",
        "",
        f"CPU time: the one-process run used {cpu1:.0f} CPU-seconds in {t1:.0f} s ({cpu1 / t1:.0%} "
        f"of a core: the rest went to other jobs); the tuned cluster's two workers used "
        f"{dask['cpu']:.0f} CPU-seconds together for the same files, the default cluster's "
        f"{dask['default_cpu']:.0f}.",
        "",
        "| run | wall time (s) | files/s | samples/s | speed-up vs one process |",
        "|---|---|---|---|---|",
        f"| one process (`jobs=1`) | {t1:.1f} | {n_files / t1:.1f} | {samples / t1:.3g} | 1.00x |",
        f"| `--jobs 2` (2 local processes, start-up included) | {t2:.1f} | {n_files / t2:.1f} | "
        f"{samples / t2:.3g} | {t1 / t2:.2f}x |",
        f"| dask.distributed: scheduler + 2 worker processes on loopback, tuned (see below) | "
        f"{dask['took']:.1f} | {n_files / dask['took']:.1f} | {samples / dask['took']:.3g} | "
        f"{t1 / dask['took']:.2f}x |",
        f"| the same with dask's defaults | {dask['default_took']:.1f} | "
        f"{n_files / dask['default_took']:.1f} | {samples / dask['default_took']:.3g} | "
        f"{t1 / dask['default_took']:.2f}x |",
        "",
        "These passes ran one after the other; as a check on load changes between them, the "
        f"rounds below alternate all four on the first {min(args.subset, n_files)} files, "
        f"{args.rounds} rounds, and compare best times:",
        "",
        "| round | one process (s) | `--jobs 2` (s) | dask cluster, tuned (s) | dask cluster, "
        "dask's defaults (s) |",
        "|---|---|---|---|---|",
        *[
            f"| {i + 1} | {a:.1f} | {b:.1f} | {c:.1f} | {d:.1f} |"
            for i, (a, b, c, d) in enumerate(
                zip(
                    dask["rounds"]["one"],
                    dask["rounds"]["jobs2"],
                    dask["rounds"]["dask"],
                    dask["rounds"]["dask_default"],
                    strict=True,
                )
            )
        ],
        f"| best | {best['one']:.1f} | {best['jobs2']:.1f} | {best['dask']:.1f} | "
        f"{best['dask_default']:.1f} |",
        "",
        "Tuned: two of dask's defaults cost a CPU-bound batch. Its nannies start workers with "
        "`MALLOC_TRIM_THRESHOLD_=65536` (`distributed.nanny.pre-spawn-environ`): glibc then "
        "returns every freed array to the system at once and page-faults the next one in "
        "again. And each worker's statistical profiler (`distributed.worker.profile`, for the "
        "dask dashboard) samples the task thread's stack every 10 ms, taking the GIL from it. "
        "The tuned cluster leaves glibc's own adaptive threshold (as the `--jobs` processes "
        "have) and turns the profiler off, keeping dask's other settings; README's scale "
        "section says how to set both on a cluster.",
        "",
        f"Targets, on the full passes: `--jobs 2` >= 1.7x one process: {t1 / t2:.2f}x "
        f"({tick(t1 / t2 >= 1.7)}; best of the rounds {s2:.2f}x); dask cluster >= 1.6x: tuned "
        f"{t1 / dask['took']:.2f}x ({tick(t1 / dask['took'] >= 1.6)}; best of the rounds "
        f"{sd:.2f}x), with dask's defaults {t1 / dask['default_took']:.2f}x (rounds {sdd:.2f}x); "
        f"the machine's own two-process "
        f"ceiling was {ceil[0]:.2f}x before and {ceil[1]:.2f}x after. Rows of every full pass "
        f"equal the one-process rows (`elapsed_s` aside): {'yes' if ok else 'NO'}.",
        "",
        f"Per-task overhead (2,000 no-op tasks): dask cluster {dask['per_task'] * 1e3:.2f} ms a "
        f"task (cluster start-up {dask['start']:.1f} s, not in the time above); two forkserver "
        f"processes (`--jobs`) {pool_task * 1e3:.2f} ms a task (pool start-up "
        f"{pool_start:.1f} s). `--jobs` uses the process pool: it starts faster and costs less "
        f"a task; both are small against a task of "
        f"{task_size(n_files, 2)} files x {t1 / n_files * 1e3:.0f} ms.",
        "",
        f"Resume: `noisevar batch` on {resume['files']:,} of the files (moved to a folder of "
        f"their own) SIGKILLed after {resume['killed_after']:,} of them; the rerun did "
        f"{resume['redone']:,} files "
        f"({tick(resume['redone'] == resume['files'] - resume['killed_after'])}: exactly the "
        f"rest) in "
        f"{resume['took']:.1f} s, and its table equals the uninterrupted one: "
        f"{'yes' if resume['same'] else 'NO'}.",
        "",
        *_scaled(args, n_files, t1, t2, dask, pool_start),
        "On paper, 1e6 such files on 100 nodes (an extrapolation from the per-file time and "
        "per-task overhead measured here, not a measurement; cores per node and storage "
        "bandwidth are assumptions):",
        "",
        "| cores/node | storage bandwidth | workers | files/task | tasks | compute | read | "
        "scheduler |",
        "|---|---|---|---|---|---|---|---|",
    ]
    for cores, bw, workers, k, tasks, compute, io, sched in paper:
        lines.append(
            f"| {cores} | {bw / 1e9:.0f} GB/s | {workers:,} | {k} | {tasks:,} | {compute:.0f} s "
            f"| {io:.0f} s | {sched:.0f} s |"
        )
    lines += [
        "",
        f"Compute is 1e6 x {t1 / n_files * 1e3:.0f} ms (this machine's per-file time) over the "
        "workers; read is 1e6 files over the storage bandwidth; scheduler is the tasks times "
        "the per-task overhead measured here (the dask scheduler is one process, so this part "
        "does not shrink with more nodes; the overhead was measured on this loaded machine and "
        "is likely smaller on an idle scheduler). The largest of the three bounds the run, row "
        "by row above. The driver then holds 3e6 rows (a few hundred MB) and its journal grows "
        "by one JSON line a row.",
        "",
    ]
    return "\n".join(lines)


if __name__ == "__main__":
    main()

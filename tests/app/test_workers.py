"""Heavy computations on the worker pool (issue 29, item 7): same results, errors, queue, exit."""

from __future__ import annotations

import os
import signal
import subprocess
import sys
import textwrap
import time
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

import noisevar  # noqa: E402
from dashboard import workers  # noqa: E402
from noisevar.estimators.compare import run_monte_carlo  # noqa: E402


@pytest.fixture(autouse=True)
def _two_workers(monkeypatch):
    monkeypatch.setattr(workers, "WORKERS", 2)


def test_a_monte_carlo_in_chunks_equals_one_sequential_run():
    kwargs = dict(signal="fast-slow", runs=13, methods=["diff2", "mad-diff"], n=1000, seed=5)
    snaps = list(workers.monte_carlo_chunks(**kwargs))
    ref = run_monte_carlo(**kwargs)
    last = snaps[-1]
    assert last.finished and last.runs_done == 13 and len(snaps) == len(workers.chunk_sizes(13, 2))
    assert [s.runs_done for s in snaps] == sorted({s.runs_done for s in snaps})
    for m in ref.methods:
        np.testing.assert_array_equal(last.relative_errors[m], ref.relative_errors[m])
    assert last.failures == ref.failures and last.first_error == ref.first_error
    assert last.true_variance == ref.true_variance and last.seed == ref.seed


def test_errors_come_back_whole():
    z = np.random.default_rng(3).normal(size=3000)
    with pytest.raises(noisevar.NoWindowKept) as info:
        workers.call(noisevar.estimate, z, method="somd", gamma_amp=1e-9, gamma_ang=1e-9)
    assert info.value.summary["kept"] == 0 and info.value.diagnosis is not None
    with pytest.raises(noisevar.NoisevarError):
        list(workers.monte_carlo_chunks(signal="fast-slow", runs=0, methods=["diff2"]))
    assert workers.call(noisevar.estimate, z, method="diff2").variance == pytest.approx(
        noisevar.estimate(z, method="diff2").variance, rel=0, abs=0
    )


def test_the_queue_position_counts_the_tasks_ahead():
    pool = workers.pool()
    tasks = [pool.submit(time.sleep, 0.6) for _ in range(5)]
    time.sleep(0.2)
    positions = [pool.ahead(ticket) for ticket, _ in tasks]
    assert positions == [0, 0, 1, 2, 3]
    shown: list[str] = []
    workers.wait(*tasks[-1], show=shown.append)
    assert any("Queued: " in s for s in shown)


def test_workers_die_with_a_killed_server(tmp_path):
    script = textwrap.dedent(
        f"""
        import os, sys, time
        sys.path.insert(0, {str(ROOT)!r})
        from dashboard import workers
        workers.WORKERS = 2
        pool = workers.pool()
        pids = [pool.submit(os.getpid)[1].result() for _ in range(4)]
        print(" ".join(map(str, set(pids))), flush=True)
        time.sleep(60)
        """
    )
    proc = subprocess.Popen([sys.executable, "-c", script], stdout=subprocess.PIPE, text=True)
    pids = [int(p) for p in proc.stdout.readline().split()]
    assert pids and os.getpid() not in pids
    proc.send_signal(signal.SIGKILL)
    proc.wait()
    deadline = time.monotonic() + 10
    while any(_alive(p) for p in pids) and time.monotonic() < deadline:
        time.sleep(0.2)
    assert not [p for p in pids if _alive(p)]


def _alive(pid: int) -> bool:
    try:
        stat = Path(f"/proc/{pid}/stat").read_text()
    except FileNotFoundError:
        return False
    return stat.split(")")[-1].split()[0] != "Z"


def test_no_pool_runs_on_the_calling_thread(monkeypatch):
    monkeypatch.setattr(workers, "WORKERS", 0)
    assert workers.pool() is None
    assert workers.call(os.getpid) == os.getpid()


def test_every_worker_starts_with_the_pool():
    """A pool that grew a worker during a class raised the server's memory by a worker's
    size after the wave (+29 % at N = 4 in benchmarks/load.py): all start at once."""
    pool = workers.Pool(2)
    try:
        assert len(pool._executor._processes) == 2  # noqa: SLF001 - the executor's own table
    finally:
        pool.shutdown()


def test_workers_run_below_the_script_threads():
    """At N = 16 a slider step's page waited 24 s (median) while two workers computed
    Compare tables at the script threads' priority (benchmarks/load.py): workers are
    niced by WORKER_NICE."""
    pool = workers.Pool(2)
    try:
        _, future = pool.submit(os.nice, 0)
        assert future.result(timeout=30) == min(os.nice(0) + workers.WORKER_NICE, 19)
    finally:
        pool.shutdown()


def test_an_estimate_goes_before_the_waiting_batches():
    """A slider step's estimate waited behind every Compare table asked before it (45 s at
    N = 8 in benchmarks/load.py): first-rank tasks pass the waiting batches, FIFO within
    a rank, and a cancelled waiting task frees its place without running."""
    pool = workers.Pool(1)  # one worker: the order of the runs is the dispatch order
    try:
        busy = pool.submit(time.sleep, 0.5)
        time.sleep(0.1)
        batches = [pool.submit(time.monotonic) for _ in range(3)]
        dropped = pool.submit(time.monotonic)
        first = pool.submit_first(time.monotonic)
        assert pool.ahead(first[0]) == 1 and pool.ahead(batches[0][0]) == 2
        assert dropped[1].cancel() and pool.queued() == 5
        done_at = [f.result(timeout=30) for _, f in (*batches, first)]
        assert done_at[3] < min(done_at[:3]) and done_at[:3] == sorted(done_at[:3])
        assert busy[1].done() and pool.queued() == 0
    finally:
        pool.shutdown()
    assert workers.call_batch(os.getpid) != os.getpid()


def test_an_estimate_runs_on_its_own_thread_while_every_worker_computes():
    pool = workers.pool()
    busy = [pool.submit(time.sleep, 1.0) for _ in range(2)]
    time.sleep(0.2)
    assert pool.busy() and workers.call(os.getpid) == os.getpid()
    for _, future in busy:
        future.result(timeout=30)
    assert not pool.busy() and workers.call(os.getpid) != os.getpid()
    busy = [pool.submit(time.sleep, 1.0) for _ in range(2)]
    time.sleep(0.2)
    big = np.zeros(workers.INLINE_MAX_SAMPLES + 1)
    assert workers.call(np.size, big) == big.size  # a long record waits for a worker
    assert not pool.busy()
    for _, future in busy:
        future.result(timeout=30)


def test_a_killed_worker_restarts_the_pool():
    """A worker killed while computing (the kernel's OOM killer, an admin) broke the executor
    for good: every page of every session raised "A child process terminated abruptly, the
    process pool is not usable anymore" until the server was restarted (real_audit11's pages
    on a loaded machine). Its tasks run again on a new pool; a task that kills its worker
    each time fails once, in one line."""
    pool = workers.Pool(2)
    try:
        tasks = [pool.submit(time.sleep, 1.5) for _ in range(2)]
        time.sleep(0.9)  # both computing (after the 0.5 s start pause)
        for pid in list(pool._executor._processes):
            os.kill(pid, signal.SIGKILL)
        assert [f.result(timeout=60) for _, f in tasks] == [None, None]
        _, dies = pool.submit(os._exit, 1)
        with pytest.raises(noisevar.NoisevarError, match="worker process stopped"):
            dies.result(timeout=60)
        _, after = pool.submit(abs, -3)
        assert after.result(timeout=60) == 3 and pool.queued() == 0
    finally:
        pool.shutdown()

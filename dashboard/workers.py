"""Heavy computations off the script thread: one worker process pool per server.

A Streamlit server is one Python process: every session's script shares one GIL, so a
class clicking together waits in line for one core. The heavy calls (the Compare table,
the Monte Carlo, an estimate of a long record) run here instead, in a process pool sized
to the machine (:data:`WORKERS`, ``NOISEVAR_WORKERS`` overrides it; 0 runs them on the
script thread). The queue is bounded (:data:`QUEUE_PER_WORKER` tasks per worker wait at
most: a further request waits on its script thread), and a waiting page shows its place
in the queue.

Notes
-----
Every worker starts with the pool (not one more each time the queue grows), from a fork
server that preloads noisevar and warms its kernels (:mod:`dashboard.worker_preload`: a
new worker costs a fork, not an import). They die
with the server: the fork server exits when the server is gone, and each worker asks the
kernel for SIGKILL when the fork server goes (Linux ``PR_SET_PDEATHSIG``) and also
watches its parent's id, so a killed server leaves no worker behind. A worker that dies
(the kernel's OOM killer) breaks its executor: a new one is started and its tasks run
again once (:meth:`Pool._renew`), so one killed worker does not fail every later page.
A Monte Carlo runs as chunks of consecutive runs (run ``i`` draws with seed
``seed + i`` in :func:`noisevar.estimators.compare.monte_carlo`, so a chunk is the same
runs), at most :data:`CHUNKS_IN_FLIGHT` at once per session, merged in order: the result
equals one sequential run, apart from the timings.

The executor gets at most one task per worker; the rest wait in the pool, by rank and
then arrival. An estimate (:func:`call`: what a slider step waits for, milliseconds on a
short record) goes before every waiting batch (:func:`call_batch`: the Compare table,
seconds per session with the maximum-likelihood peers; Monte Carlo chunks). In one
executor queue, a class's slider steps waited behind every Compare table asked before
them: 64 s at N = 8 for a step that takes 0.1 s alone (``benchmarks/load.py``). When every
worker is computing, an estimate of a short record runs on its script thread instead.
"""

from __future__ import annotations

import atexit
import concurrent.futures as cf
import ctypes
import functools
import heapq
import itertools
import logging
import multiprocessing as mp
import os
import signal
import threading
import time
from collections.abc import Callable, Iterator
from dataclasses import dataclass, replace
from typing import Any, TypeVar

import numpy as np

from dashboard import trace
from noisevar.errors import NoisevarError
from noisevar.estimators.compare import MonteCarloResult, monte_carlo, run_monte_carlo

LOG = logging.getLogger("noisevar.dashboard")
T = TypeVar("T")

#: Environment variable setting the number of workers (0: no pool, the script thread).
WORKERS_ENV = "NOISEVAR_WORKERS"
#: Tasks that may wait per worker before a new request blocks its script thread.
QUEUE_PER_WORKER = 8
#: Monte Carlo chunks of one session computing at once.
CHUNKS_IN_FLIGHT = 2
#: Seconds each worker sleeps when the pool starts (so that all of them start at once).
START_PAUSE_S = 0.5
#: Largest input (samples, all arrays together) a first-rank call computes on its script
#: thread while every worker is busy (an estimate of 1e5 samples: tens of milliseconds).
INLINE_MAX_SAMPLES = 100_000
#: Niceness added to every worker: the script threads (what each interaction waits for,
#: in the server's own process) keep the cores first, the pool's long computations (the
#: Compare table's maximum-likelihood peers) take what is left (issue 29).
WORKER_NICE = 10
#: What a task gets whose worker died twice (the pool is restarted each time).
WORKER_DIED = (
    "a worker process stopped while computing this (out of memory, or killed), twice: "
    "the workers were restarted; try again, or with a shorter record"
)
#: Seconds between two looks of a waiting page at its task.
POLL_SECONDS = 0.25
#: Longest time a waiting page sends nothing: its text is sent when it changes, and
#: again after this long (a rerun asked meanwhile is honoured at the next send).
RESEND_SECONDS = 1.0


def machine_workers() -> int:
    """Workers for this machine: ``NOISEVAR_WORKERS`` if set, else the usable cores."""
    text = os.environ.get(WORKERS_ENV, "")
    if text.strip().isdigit():
        return min(int(text), 64)
    try:
        return max(1, len(os.sched_getaffinity(0)))
    except AttributeError:  # pragma: no cover - not Linux
        return max(1, os.cpu_count() or 1)


#: Worker processes of the pool (0: computations run on the script thread).
WORKERS = machine_workers()


def _die_with_parent() -> None:
    """Worker initializer: run below the script threads (:data:`WORKER_NICE`), and exit
    when the parent (the fork server, which exits with the server) goes."""
    parent = os.getppid()
    try:
        os.nice(WORKER_NICE)  # below the script threads (WORKER_NICE)
    except OSError:  # pragma: no cover - a niceness already at its limit
        pass
    try:
        ctypes.CDLL("libc.so.6", use_errno=True).prctl(1, signal.SIGKILL)  # PR_SET_PDEATHSIG
    except (OSError, AttributeError):  # pragma: no cover - not Linux
        pass

    def watch() -> None:
        while os.getppid() == parent:
            time.sleep(1.0)
        os._exit(1)

    threading.Thread(target=watch, daemon=True).start()


#: Dispatch ranks: what one interaction waits for (an estimate) goes before whole-page
#: batches (the Compare table, Monte Carlo chunks); FIFO within a rank.
FIRST, BATCH = 0, 1


class Pool:
    """A bounded process pool with queue positions and two ranks (one per server:
    :func:`pool`).

    The pool hands the executor at most one task per worker; the others wait here,
    ordered by rank, then by arrival (see the module's Notes).
    """

    def __init__(self, workers: int) -> None:
        self.workers = workers
        self._executor = self._new_executor()
        self._slots = threading.BoundedSemaphore(workers * QUEUE_PER_WORKER)
        self._lock = threading.Lock()
        self._tickets = itertools.count()
        self._waiting: list[tuple[int, int]] = []  # heap of (rank, ticket)
        self._jobs: dict[int, tuple[int, Callable[..., Any], tuple, dict, cf.Future]] = {}
        self._running: set[int] = set()

    def _new_executor(self) -> cf.ProcessPoolExecutor:
        method = "forkserver" if "forkserver" in mp.get_all_start_methods() else "spawn"
        context = mp.get_context(method)
        if method == "forkserver":
            context.set_forkserver_preload(["dashboard.worker_preload"])
        executor = cf.ProcessPoolExecutor(
            self.workers, mp_context=context, initializer=_die_with_parent
        )
        # every worker at once: the server reaches its working memory with its first
        # computation (a pool that grew a worker during a class looked like a leak)
        for _ in range(self.workers):
            executor.submit(time.sleep, START_PAUSE_S)
        return executor

    def _renew(self, broken: cf.ProcessPoolExecutor) -> None:
        """Replace ``broken`` (a worker died: killed for memory, or by hand) with a new
        executor, once however many of its tasks report it. A broken executor refuses
        every later task: every page failed until the server was restarted."""
        with self._lock:
            if self._executor is not broken:
                return
            self._executor = self._new_executor()
        LOG.warning("a worker process died: the pool was restarted")
        broken.shutdown(wait=False, cancel_futures=True)

    def submit(self, fn: Callable[..., T], *args: Any, **kwargs: Any) -> tuple[int, cf.Future]:
        """Queue ``fn(*args, **kwargs)`` as a batch (after every waiting first-rank task);
        returns its ticket and future."""
        return self._enqueue(BATCH, fn, args, kwargs)

    def submit_first(
        self, fn: Callable[..., T], *args: Any, **kwargs: Any
    ) -> tuple[int, cf.Future]:
        """Queue ``fn(*args, **kwargs)`` ahead of every waiting batch; returns its ticket
        and future."""
        return self._enqueue(FIRST, fn, args, kwargs)

    def _enqueue(self, rank: int, fn: Callable, args: tuple, kwargs: dict) -> tuple[int, cf.Future]:
        self._slots.acquire()
        future: cf.Future = cf.Future()
        with self._lock:
            ticket = next(self._tickets)
            heapq.heappush(self._waiting, (rank, ticket))
            self._jobs[ticket] = (rank, fn, args, kwargs, future)
        future.add_done_callback(lambda f: f.cancelled() and self._drop(ticket))
        self._dispatch()
        return ticket, future

    def _drop(self, ticket: int) -> None:
        """A waiting task cancelled: forget it, free its place in the queue."""
        with self._lock:
            if self._jobs.pop(ticket, None) is None:
                return
        self._slots.release()

    def _next(self) -> tuple[int, Callable, tuple, dict, cf.Future] | None:
        """The next task to hand the executor (marked running), or None."""
        with self._lock:
            while self._waiting and len(self._running) < self.workers:
                _, ticket = heapq.heappop(self._waiting)
                job = self._jobs.get(ticket)
                if job is None or not job[4].set_running_or_notify_cancel():
                    continue  # cancelled while waiting (its place freed by _drop)
                del self._jobs[ticket]
                self._running.add(ticket)
                return ticket, job[1], job[2], job[3], job[4]
        return None

    def _dispatch(self) -> None:
        while (job := self._next()) is not None:
            self._start(*job, tries=0)

    def _start(
        self, ticket: int, fn: Callable, args: tuple, kwargs: dict, future: cf.Future, tries: int
    ) -> None:
        """Hand one task to the executor; a task whose executor broke is tried again once
        on a new one (:meth:`_renew`), then fails with :data:`WORKER_DIED`."""
        executor = self._executor
        try:
            inner = executor.submit(fn, *args, **kwargs)
        except cf.process.BrokenProcessPool:
            self._retry_or_fail(executor, (ticket, fn, args, kwargs, future), tries)
            return
        except BaseException as exc:  # noqa: BLE001 - handed to the waiting caller
            future.set_exception(exc)
            self._finished(ticket)
            return
        job = (ticket, fn, args, kwargs, future)
        inner.add_done_callback(functools.partial(self._relay, job, executor, tries))

    def _retry_or_fail(self, executor: cf.ProcessPoolExecutor, job: tuple, tries: int) -> None:
        self._renew(executor)
        if tries == 0:
            self._start(*job, tries=1)
            return
        job[4].set_exception(NoisevarError(WORKER_DIED))
        self._finished(job[0])

    def _finished(self, ticket: int) -> None:
        with self._lock:
            self._running.discard(ticket)
        self._slots.release()

    def _relay(
        self, job: tuple, executor: cf.ProcessPoolExecutor, tries: int, inner: cf.Future
    ) -> None:
        """The executor finished a task: pass its outcome on, start the next one."""
        ticket, future = job[0], job[4]
        exc = None if inner.cancelled() else inner.exception()
        if isinstance(exc, cf.process.BrokenProcessPool):
            self._retry_or_fail(executor, job, tries)  # started again, or failed and finished
        else:
            if inner.cancelled():
                future.set_exception(cf.CancelledError())
            elif exc is not None:
                future.set_exception(exc)
            else:
                future.set_result(inner.result())
            self._finished(ticket)
        self._dispatch()

    def ahead(self, ticket: int) -> int:
        """Tasks a waiting ``ticket`` waits for: those dispatched before it, plus one for
        the busy workers (0: it is computing, or done)."""
        with self._lock:
            job = self._jobs.get(ticket)
            if job is None:
                return 0
            key = (job[0], ticket)
            return 1 + sum(1 for r, t in self._waiting if (r, t) < key and t in self._jobs)

    def busy(self) -> bool:
        """True when every worker is computing."""
        with self._lock:
            return len(self._running) >= self.workers

    def queued(self) -> int:
        """Tasks waiting or computing."""
        with self._lock:
            return len(self._jobs) + len(self._running)

    def shutdown(self) -> None:
        with self._lock:
            waiting = [job[4] for job in self._jobs.values()]
        for future in waiting:
            future.cancel()
        self._executor.shutdown(wait=False, cancel_futures=True)


_POOL: Pool | None = None
_POOL_LOCK = threading.Lock()


def pool() -> Pool | None:
    """The server's pool (started on first use), or None when ``NOISEVAR_WORKERS=0``."""
    global _POOL
    if WORKERS <= 0:
        return None
    with _POOL_LOCK:
        if _POOL is None:
            _POOL = Pool(WORKERS)
            atexit.register(_POOL.shutdown)
        return _POOL


def _queue_text(ahead: int) -> str:
    return f"Queued: {ahead} computation{'s' * (ahead != 1)} of other sessions ahead"


def status(ticket: int) -> str:
    """What a task waits for: its queue position, or that it is computing."""
    p = pool()
    ahead = p.ahead(ticket) if p is not None else 0
    return _queue_text(ahead) if ahead else "Computing on a worker process..."


def wait(ticket: int, future: cf.Future, show: Callable[[str], None] | None = None) -> Any:
    """The future's result; meanwhile ``show`` gets the queue position when it waits.

    ``show`` is called when the text changes, and at least every :data:`RESEND_SECONDS`
    (a script run honours a rerun asked meanwhile only when it sends something).
    """
    shown, sent = None, 0.0
    while True:
        try:
            return future.result(timeout=POLL_SECONDS)
        except cf.TimeoutError:
            p = pool()
            ahead = p.ahead(ticket) if p is not None else 0
            if show is not None and (ahead or shown is not None):
                text = _queue_text(ahead) if ahead else "Computing on a worker process..."
                if text != shown or time.monotonic() - sent >= RESEND_SECONDS:
                    show(text)
                    shown, sent = text, time.monotonic()


@dataclass(frozen=True)
class Started:
    """A batch task started on the pool (:func:`start_batch`): its ticket and future."""

    ticket: int
    future: cf.Future

    def done(self) -> bool:
        """True once its result (or error) is there."""
        return self.future.done()

    def result(self) -> Any:
        """Its value (waits for it); a NoisevarError of the task is raised as itself."""
        return _unwrap(self.future.result())

    def status(self) -> str:
        """Its queue position, or that it is computing."""
        return status(self.ticket)


def start_batch(fn: Callable[..., Any], *args: Any, **kwargs: Any) -> Started:
    """Queue ``fn(*args, **kwargs)`` as a batch and return at once (without a pool: run
    it now). A full queue blocks here, as :func:`call_batch`."""
    p = pool()
    if p is None:
        future: cf.Future = cf.Future()
        future.set_result(_carried(fn, *args, **kwargs))
        return Started(-1, future)
    with trace.pool_wait():
        return Started(*p.submit(_carried, fn, *args, **kwargs))


def wait_any(started: list[Started], seconds: float) -> None:
    """Return when one of ``started`` is done, or after ``seconds``."""
    with trace.pool_wait():
        cf.wait([s.future for s in started], seconds, cf.FIRST_COMPLETED)


def call(fn: Callable[..., T], *args: Any, **kwargs: Any) -> T:
    """``fn(*args, **kwargs)`` on a worker process, ahead of the waiting batches: what one
    interaction waits for (an estimate). On the caller's thread when there is no pool, or
    when every worker is computing and the input is small (:data:`INLINE_MAX_SAMPLES`: a
    Compare table takes seconds, waiting for it cost more than the GIL this call takes).

    While it waits for a worker, the page shows the queue position in a placeholder
    that is removed afterwards. ``fn`` and its arguments must be picklable (a module-level
    function, arrays, plain values).
    """
    return _call(FIRST, fn, *args, **kwargs)


def call_batch(fn: Callable[..., T], *args: Any, **kwargs: Any) -> T:
    """:func:`call` for a whole-page batch (every method at once): queued after the
    waiting first-rank tasks."""
    return _call(BATCH, fn, *args, **kwargs)


def _small(args: tuple, kwargs: dict) -> bool:
    """True when the arrays among the arguments hold at most :data:`INLINE_MAX_SAMPLES`."""
    values = (*args, *kwargs.values())
    return sum(v.size for v in values if isinstance(v, np.ndarray)) <= INLINE_MAX_SAMPLES


def _call(rank: int, fn: Callable[..., T], *args: Any, **kwargs: Any) -> T:
    p = pool()
    if p is None or (rank == FIRST and p.busy() and _small(args, kwargs)):
        return fn(*args, **kwargs)
    submit = p.submit_first if rank == FIRST else p.submit
    with trace.pool_wait():  # a full queue blocks here
        ticket, future = submit(_carried, fn, *args, **kwargs)
    slot = None

    def show(text: str) -> None:
        nonlocal slot
        import streamlit as st

        if slot is None:
            slot = st.empty()
        slot.caption(text)

    try:
        with trace.pool_wait():
            return _unwrap(wait(ticket, future, show if _in_script() else None))
    finally:
        if slot is not None:
            slot.empty()


def _carried(fn: Callable[..., T], *args: Any, **kwargs: Any) -> tuple[bool, Any]:
    """On a worker: ``(True, value)``, or ``(False, (type, message, attributes))`` for a
    NoisevarError (pickle rebuilds an exception from its message alone: a
    ``NoWindowKept``'s summary and diagnosis would be lost)."""
    try:
        return True, fn(*args, **kwargs)
    except NoisevarError as exc:
        return False, (type(exc), str(exc), dict(vars(exc)))


def _unwrap(result: tuple[bool, Any]) -> Any:
    ok, value = result
    if ok:
        return value
    cls, message, attributes = value
    exc = cls.__new__(cls)
    Exception.__init__(exc, message)
    exc.__dict__.update(attributes)
    raise exc


def _in_script() -> bool:
    from streamlit.runtime.scriptrunner_utils.script_run_context import get_script_run_ctx

    return get_script_run_ctx() is not None


def _chunk(kwargs: dict[str, Any], first: int, runs: int) -> MonteCarloResult:
    """Runs ``first`` to ``first + runs - 1`` of a Monte Carlo, to the end (on a worker)."""
    return run_monte_carlo(**{**kwargs, "runs": runs, "seed": int(kwargs["seed"]) + first})


def chunk_sizes(runs: int, workers: int) -> list[int]:
    """Consecutive chunks of a Monte Carlo: about ten, at least one run each."""
    size = max(1, -(-runs // max(10, 2 * workers)))
    return [min(size, runs - start) for start in range(0, runs, size)]


def _merge(total: MonteCarloResult | None, part: MonteCarloResult, runs: int) -> MonteCarloResult:
    if total is None:
        return replace(part, runs_requested=runs)
    scale = part.true_variance / total.true_variance  # 1: the noise level does not draw
    errors = {
        m: np.concatenate([total.relative_errors[m], (part.relative_errors[m] + 1) * scale - 1])
        for m in total.methods
    }
    return replace(
        total,
        runs_done=total.runs_done + part.runs_done,
        relative_errors=errors,
        failures={m: total.failures[m] + part.failures[m] for m in total.methods},
        seconds={m: total.seconds[m] + part.seconds[m] for m in total.methods},
        first_error={**part.first_error, **total.first_error},
    )


def monte_carlo_chunks(
    show: Callable[[str], None] | None = None, **kwargs: Any
) -> Iterator[MonteCarloResult]:
    """:func:`~noisevar.estimators.compare.monte_carlo` on the pool, a snapshot per chunk.

    Same arguments (by keyword) and the same final result; ``show`` receives the queue
    position while the next chunk waits. Closing the generator cancels the chunks not
    started. Without a pool, the runs are yielded one by one on this thread.
    """
    p = pool()
    if p is None:
        yield from monte_carlo(**kwargs)
        return
    runs = int(kwargs.get("runs", 100))
    if not 1 <= runs <= 100_000:  # monte_carlo's own error, on this thread
        yield from monte_carlo(**kwargs)
        return
    starts = list(itertools.accumulate([0, *chunk_sizes(runs, p.workers)]))
    todo = list(zip(starts[:-1], np.diff(starts).tolist(), strict=True))
    flying: list[tuple[int, cf.Future]] = []
    total = None
    try:
        while todo or flying:
            while todo and len(flying) < CHUNKS_IN_FLIGHT:
                first, size = todo.pop(0)
                with trace.pool_wait():
                    flying.append(p.submit(_carried, _chunk, kwargs, first, size))
            ticket, future = flying.pop(0)
            with trace.pool_wait():
                part = _unwrap(wait(ticket, future, show))
            total = _merge(total, part, runs)
            yield total
    finally:
        for _, future in flying:
            future.cancel()

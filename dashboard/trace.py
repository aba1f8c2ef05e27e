"""Where a script run's time goes, for the load benchmark (``NOISEVAR_TRACE``; off by default).

With ``NOISEVAR_TRACE`` set to a file path, every script run of every session appends one
JSON line to that file: the session, the page, its start and end (wall clock), the script
thread's own CPU time, the time it waited for the worker pool (queue and computation,
:func:`pool_wait`), the process's garbage-collection pauses during the run, and how it
ended. Every collection pause of at least :data:`GC_PAUSE_S` is also a line of its own.
``wall - cpu - pool`` is then time the thread was runnable or blocked but not computing:
waiting for the GIL (other sessions' scripts, the server's event loop, the memory guard)
or for I/O. The benchmark (``benchmarks/load.py --trace``) reads the file.

Notes
-----
Unset, :func:`script_run` is a ``nullcontext`` and :func:`pool_wait` costs a thread-local
lookup: nothing is measured or written. The garbage-collection pauses are process-wide
(``gc.callbacks``): a pause inside a run counts in every run it overlaps.
"""

from __future__ import annotations

import contextlib
import gc
import json
import os
import threading
import time
from collections.abc import Iterator

#: Environment variable naming the trace file (JSON lines); unset: no trace.
TRACE_ENV = "NOISEVAR_TRACE"

_LOCAL = threading.local()
_WRITE = threading.Lock()
_GC = {"seconds": 0.0, "count": 0, "started": 0.0}


def enabled() -> bool:
    """True when ``NOISEVAR_TRACE`` names a file."""
    return bool(os.environ.get(TRACE_ENV))


#: Shortest garbage-collection pause written to the trace as a line of its own (s).
GC_PAUSE_S = 0.01


def _gc_callback(phase: str, info: dict) -> None:
    if phase == "start":
        _GC["started"] = time.perf_counter()
    elif _GC["started"]:
        pause = time.perf_counter() - _GC["started"]
        _GC["seconds"] += pause
        _GC["count"] += 1
        _GC["started"] = 0.0
        if pause >= GC_PAUSE_S:
            write({"gc": time.time(), "seconds": pause, "generation": info.get("generation")})


def write(record: dict) -> None:
    """Append ``record`` as one JSON line to the trace file (nothing when tracing is off)."""
    path = os.environ.get(TRACE_ENV)
    if not path:
        return
    line = json.dumps(record, default=str) + "\n"
    with _WRITE, open(path, "a", encoding="utf-8") as out:
        out.write(line)


@contextlib.contextmanager
def pool_wait() -> Iterator[None]:
    """Count the enclosed time as this script run's wait for the worker pool."""
    if getattr(_LOCAL, "run", None) is None:
        yield
        return
    t0 = time.perf_counter()
    try:
        yield
    finally:
        _LOCAL.run["pool"] += time.perf_counter() - t0


@contextlib.contextmanager
def _traced(page: str) -> Iterator[None]:
    if _gc_callback not in gc.callbacks:
        gc.callbacks.append(_gc_callback)
    from streamlit.runtime.scriptrunner_utils.script_run_context import get_script_run_ctx

    ctx = get_script_run_ctx()
    run = {"pool": 0.0}
    _LOCAL.run = run
    start, cpu0, gc0 = time.time(), time.thread_time(), dict(_GC)
    outcome = "done"
    try:
        yield
    except BaseException as exc:  # Streamlit's rerun/stop exceptions end a run too
        outcome = type(exc).__name__
        raise
    finally:
        _LOCAL.run = None
        write(
            {
                "session": ctx.session_id if ctx is not None else None,
                "page": page,
                "start": start,
                "end": time.time(),
                "cpu": time.thread_time() - cpu0,
                "pool": run["pool"],
                "gc_s": _GC["seconds"] - gc0["seconds"],
                "gc_n": _GC["count"] - gc0["count"],
                "outcome": outcome,
            }
        )


def script_run(page: str) -> contextlib.AbstractContextManager[None]:
    """Trace the enclosed script run of ``page`` (a no-op unless ``NOISEVAR_TRACE`` is set,
    and inside a traced run: a fragment that runs with its page is part of the page's run)."""
    if enabled() and getattr(_LOCAL, "run", None) is None:
        return _traced(page)
    return contextlib.nullcontext()

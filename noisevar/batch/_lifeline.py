"""Worker processes that die with the batch that started them.

``batch(jobs=N)`` runs its tasks in worker processes forked from a fork server. Each
worker holds the fork server's liveness pipe and the resource tracker's, so a worker left
running keeps both alive too. Every process of the pool therefore watches its parent:

- the fork server (its parent: the batch) asks the kernel for SIGKILL when its parent dies
  (Linux ``prctl(PR_SET_PDEATHSIG)``), and so does each worker (its parent: the fork
  server): killing the batch, even by SIGKILL, kills the fork server, then the workers;
  the resource tracker then reads the end of its pipe and exits;
- each worker also polls the batch's process (:data:`POLL_S`), where ``prctl`` does not
  exist, and exits once it is gone.
"""

from __future__ import annotations

import contextlib
import os
import signal
import sys
import threading
import time

#: Seconds between a worker's checks that its batch is still running.
POLL_S = 0.5
#: Environment variable naming the batch process to the fork server it starts.
BATCH_PID_ENV = "NOISEVAR_BATCH_PID"
_PR_SET_PDEATHSIG = 1


def _death_signal() -> None:
    """SIGKILL this process when its parent thread ends (Linux; elsewhere nothing)."""
    if not sys.platform.startswith("linux"):
        return
    import ctypes

    with contextlib.suppress(OSError, AttributeError):
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGKILL, 0, 0, 0)


def alive(pid: int) -> bool:
    """Whether process ``pid`` runs (a zombie, dead but not yet reaped, does not)."""
    try:
        with open(f"/proc/{pid}/stat", "rb") as fh:
            state = fh.read().rsplit(b")", 1)[-1].split()[0]
        return state not in (b"Z", b"X")
    except (OSError, IndexError):
        pass
    if os.path.isdir("/proc"):
        return False
    try:  # pragma: no cover - no /proc (macOS): the signal-0 probe
        os.kill(pid, 0)
    except ProcessLookupError:  # pragma: no cover
        return False
    except PermissionError:  # pragma: no cover
        return True
    return True  # pragma: no cover


def announce() -> int:
    """In the batch, before its pool starts: name this process to the fork server; its pid."""
    os.environ[BATCH_PID_ENV] = str(os.getpid())
    return os.getpid()


def follow_parent() -> None:
    """In the fork server: die with the batch process that started it (:func:`announce`).

    Nothing in any other process (the variable names another process than its parent).
    """
    parent = os.getppid()
    if os.environ.get(BATCH_PID_ENV) != str(parent):
        return
    _death_signal()
    if not alive(parent) or os.getppid() != parent:  # died before the request took effect
        os._exit(1)


def follow_batch(batch_pid: int) -> None:
    """A pool worker's initializer: die with the fork server and with the batch ``batch_pid``."""
    _death_signal()
    if not alive(batch_pid):
        os._exit(1)

    def watch() -> None:
        while alive(batch_pid):
            time.sleep(POLL_S)
        os._exit(1)

    threading.Thread(target=watch, name="noisevar-batch-lifeline", daemon=True).start()

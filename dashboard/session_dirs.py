"""Temporary folders that live as long as their session.

Streamlit has no session-end hook. A page's folder is owned by a :class:`SessionFolder`
kept in ``st.session_state``: when Streamlit drops the session (its tab closed, then
``server.disconnectedSessionTTL``), the object is freed and ``weakref.finalize`` removes
the folder; the server's exit removes every remaining one. As a backstop, each new
folder sweeps the folders of this server's sessions that the runtime no longer knows,
and those of servers no longer running (a server killed without its exit handlers
leaves them). A folder's name holds its server's process id and its session id, so
several app processes behind a proxy never remove each other's folders.

A closed tab's session is kept for ``server.disconnectedSessionTTL`` in case it
reconnects. Streamlit's session storage then only *hides* it: the session stays in
memory, and is never shut down (its uploads, its dataframes sent to the browser), until a
later write to the storage reaps it. :func:`live_session_ids` first reaps and shuts down
the expired ones (:func:`shut_down_expired`, on the server's event loop, as Streamlit
closes a session).
"""

from __future__ import annotations

import logging
import os
import shutil
import tempfile
import threading
import weakref
from pathlib import Path

LOG = logging.getLogger("noisevar.dashboard")

#: Name prefix of every session folder (the session id follows).
PREFIX = "noisevar-fleet-"


class SessionFolder:
    """A temporary folder removed when this object is freed (or at the server's exit).

    Parameters
    ----------
    session_id : str
        The owning session's id (part of the folder's name, for :func:`sweep`).
    """

    def __init__(self, session_id: str) -> None:
        safe = "".join(c for c in session_id if c.isalnum() or c == "-")[:64] or "none"
        self.path = Path(tempfile.mkdtemp(prefix=f"{PREFIX}{os.getpid()}-{safe}."))
        self._finalizer = weakref.finalize(self, shutil.rmtree, str(self.path), True)

    def remove(self) -> None:
        """Remove the folder now."""
        self._finalizer()


def _owner(folder: Path) -> tuple[int, str]:
    """The server's process id and the session id in a folder's name (-1 if unreadable)."""
    pid, _, session = folder.name[len(PREFIX) :].split(".", 1)[0].partition("-")
    return (int(pid) if pid.isdigit() else -1), session


def _running(pid: int) -> bool:
    if pid <= 0:  # a name without a process id (another program's folder): leave it
        return True
    try:
        os.kill(pid, 0)
    except ProcessLookupError:
        return False
    except (PermissionError, OverflowError, ValueError):
        return pid > 0  # another user's process, or not a process id
    return True


def sweep(alive: set[str], root: Path | None = None) -> list[Path]:
    """Remove this server's folders under ``root`` whose session is not in ``alive``, and
    the folders of servers no longer running.

    Returns
    -------
    list of Path
        The folders removed.
    """
    base = Path(root or tempfile.gettempdir())
    gone = []
    for folder in base.glob(f"{PREFIX}*"):
        pid, session = _owner(folder)
        ours_and_ended = pid == os.getpid() and session not in alive
        if folder.is_dir() and (ours_and_ended or (pid != os.getpid() and not _running(pid))):
            shutil.rmtree(folder, ignore_errors=True)
            gone.append(folder)
    return gone


#: Seconds :func:`live_session_ids` waits for the event loop to reap expired sessions.
REAP_WAIT_S = 5.0


def shut_down_expired(storage: object) -> int:
    """Remove from Streamlit's session storage the sessions whose reconnect time has
    passed, and shut them down; returns how many (0 when the storage is not the one
    known)."""
    expire = getattr(getattr(storage, "_cache", None), "expire", None)
    if not callable(expire):
        return 0
    gone = expire()
    for _, info in gone:
        info.session.shutdown()
    return len(gone)


def _reap(runtime: object) -> None:
    """:func:`shut_down_expired` on the runtime's event loop (storage is only touched there)."""
    manager = runtime._session_mgr  # type: ignore[attr-defined]  # noqa: SLF001
    loop = runtime._get_async_objs().eventloop  # type: ignore[attr-defined]  # noqa: SLF001
    done = threading.Event()

    def reap() -> None:
        try:
            with manager._storage_lock:  # noqa: SLF001 - Streamlit's own lock of its storage
                shut_down_expired(manager._session_storage)  # noqa: SLF001
        finally:
            done.set()

    loop.call_soon_threadsafe(reap)
    done.wait(REAP_WAIT_S)


def live_session_ids() -> set[str] | None:
    """The ids of the runtime's sessions (after reaping the expired ones), or None when
    they cannot be read."""
    try:
        from streamlit.runtime import Runtime

        runtime = Runtime.instance()
        _reap(runtime)
        # no public list of sessions: Streamlit 1.67.0's Runtime offers lookups by id only
        # (get_app_session, is_active_session, get_client); checked for issue 29
        manager = runtime._session_mgr  # noqa: SLF001 - no public list of sessions
        return {s.session.id for s in manager.list_sessions()}
    except Exception:  # noqa: BLE001 - not in a server (tests), or Streamlit changed
        LOG.debug("could not list the sessions", exc_info=True)
        return None


def session_folder() -> SessionFolder:
    """A new folder for the current session, after sweeping those of ended sessions."""
    from streamlit.runtime.scriptrunner_utils.script_run_context import get_script_run_ctx

    ctx = get_script_run_ctx()
    session_id = ctx.session_id if ctx is not None else "none"
    alive = live_session_ids()
    if alive:
        sweep(alive | {session_id})
    return SessionFolder(session_id)

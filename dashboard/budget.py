"""The server's memory budget: one cache of computed results for all sessions, bounded in bytes.

Streamlit's ``st.cache_resource`` bounds a cache by its number of entries: 24 entries of
a 2e6-sample record's results are gigabytes, 24 of a short record's are kilobytes.
:class:`ByteCache` bounds the sum of its entries' sizes (:func:`nbytes`: NumPy arrays,
pandas frames, Plotly figures, dataclasses and containers, walked) by the server's
budget :data:`MEMORY_BUDGET`. It is one process-wide object, so an identical request
(the same record's content hash and parameters) is computed once for every session: a
session asking for a value another one is computing waits for it (one lock per key)
instead of computing it again.

Notes
-----
Eviction (when the sum exceeds the budget) drops the entry with the largest
``size × (seconds since last use + 1)``: the largest and oldest first, so a big record
nobody looks at goes before the small results of the one being tuned. A value larger
than a quarter of the budget is returned without being kept. The budget counts cached
results only: the server's own code (about 0.5 GB with plotly, pandas and scipy), each
session's loaded signal and one computation's working memory come on top.

A closed session's state (its loaded signal, its widgets) is a reference cycle inside
Streamlit: only the cyclic garbage collector frees it, and the app turns off Streamlit's
collection after every script run (``runner.postScriptGC``, a quarter of a second per
slider step). :class:`MemoryGuard` (one daemon thread per server) collects when a session
has ended or an entry was evicted since its last look, then asks the C allocator to
return the freed memory to the system (``malloc_trim``).

Python's own full collections scan every object of the server (about 190,000 with the
libraries loaded; 0.4 s holding the GIL, every session's script and the event loop
waiting), and they come more often as more sessions allocate. After each of its
collections (and once at its first look) the guard freezes what survived
(``gc.freeze``): the automatic collections then scan only what was made since. Before
collecting, it unfreezes, so an ended session's state frozen while it was alive is still
freed; at the latest every :data:`REFREEZE_SECONDS` it collects and refreezes anyway.
Outside a server (no session list: tests, scripts) it never freezes.
"""

from __future__ import annotations

import ctypes
import dataclasses
import functools
import gc
import inspect
import logging
import os
import sys
import threading
import time
from collections.abc import Callable, Hashable
from typing import Any, TypeVar

import numpy as np

from dashboard import trace
from dashboard.session_dirs import live_session_ids

LOG = logging.getLogger("noisevar.dashboard")

#: Environment variable overriding :data:`MEMORY_BUDGET` (megabytes).
BUDGET_ENV = "NOISEVAR_MEMORY_MB"
#: Default budget of the cached results, in megabytes.
DEFAULT_BUDGET_MB = 512
#: Largest fraction of the budget one kept value may take.
LARGEST_SHARE = 0.25
#: Seconds between two looks of the :class:`MemoryGuard`.
GUARD_SECONDS = 5.0
#: Longest time between two of the guard's collections (frozen garbage waits at most this).
REFREEZE_SECONDS = 120.0
#: Deepest nesting :func:`nbytes` walks (deeper objects count their ``sys.getsizeof``).
MAX_DEPTH = 12

T = TypeVar("T")


def budget_bytes() -> int:
    """The budget in bytes: ``NOISEVAR_MEMORY_MB`` if set to a positive number, else 512 MB."""
    text = os.environ.get(BUDGET_ENV, "")
    try:
        mb = float(text) if text else DEFAULT_BUDGET_MB
    except ValueError:
        mb = DEFAULT_BUDGET_MB
    if not 1 <= mb <= 1e7:
        mb = DEFAULT_BUDGET_MB
    return int(mb * 1024 * 1024)


#: The budget of every cached result of the server, in bytes (read once, at start).
MEMORY_BUDGET = budget_bytes()


def nbytes(obj: object) -> int:
    """Approximate bytes held by ``obj``: arrays, frames, figures and containers, walked once.

    An array that is a view counts its own extent (its base may be shared).
    """
    return _walk(obj, set(), 0)


def _walk(obj: object, seen: set[int], depth: int) -> int:
    if id(obj) in seen or obj is None or isinstance(obj, bool | int | float | complex):
        return 0 if id(obj) in seen or obj is None else 32
    seen.add(id(obj))
    if isinstance(obj, np.ndarray):
        extra = sum(_walk(x, seen, depth + 1) for x in obj.flat) if obj.dtype == object else 0
        return int(obj.nbytes) + 112 + extra
    if isinstance(obj, str | bytes | bytearray | memoryview):
        return sys.getsizeof(obj) if not isinstance(obj, memoryview) else obj.nbytes
    if depth >= MAX_DEPTH:
        return sys.getsizeof(obj)
    if hasattr(obj, "memory_usage") and hasattr(obj, "columns"):  # a pandas DataFrame
        return int(obj.memory_usage(deep=True).sum())  # type: ignore[attr-defined]
    if isinstance(obj, dict):
        items: Any = [*obj.keys(), *obj.values()]
    elif isinstance(obj, list | tuple | set | frozenset):
        items = obj
    elif dataclasses.is_dataclass(obj):
        items = [getattr(obj, f.name, None) for f in dataclasses.fields(obj)]
    elif hasattr(obj, "to_plotly_json"):  # a Plotly figure or trace
        items = [obj.to_plotly_json()]
    elif hasattr(obj, "__dict__"):
        items = list(vars(obj).values())
    else:
        return sys.getsizeof(obj)
    return sys.getsizeof(obj) + sum(_walk(x, seen, depth + 1) for x in items)


@dataclasses.dataclass
class _Entry:
    value: object
    size: int
    used: float


class ByteCache:
    """Computed values by key, bounded in total bytes, shared by every session.

    Parameters
    ----------
    budget : int
        Most bytes kept (:func:`nbytes` of the values).
    """

    def __init__(self, budget: int) -> None:
        self.budget = int(budget)
        self._entries: dict[Hashable, _Entry] = {}
        self._lock = threading.Lock()
        self._computing: dict[Hashable, threading.Lock] = {}
        self.total = 0
        self.evictions = 0

    def get(self, key: Hashable, compute: Callable[[], T]) -> T:
        """The value of ``key``: kept, being computed by another session, or ``compute()``.

        An exception of ``compute`` is raised and nothing is kept.
        """
        with self._lock:
            hit = self._hit(key)
            if hit is not None:
                return hit.value  # type: ignore[return-value]
            key_lock = self._computing.setdefault(key, threading.Lock())
        with key_lock:  # one computation per key: the others wait for its value
            with self._lock:
                hit = self._hit(key)
                if hit is not None:
                    return hit.value  # type: ignore[return-value]
            try:
                value = compute()
                self._put(key, value)
            finally:
                with self._lock:
                    self._computing.pop(key, None)
        return value

    def peek(self, key: Hashable) -> object | None:
        """The kept value of ``key`` (None when not kept), never computing it."""
        with self._lock:
            hit = self._hit(key)
        return None if hit is None else hit.value

    def forget(self, key: Hashable) -> None:
        """Drop ``key``'s entry, if kept."""
        with self._lock:
            old = self._entries.pop(key, None)
            self.total -= old.size if old else 0

    def _hit(self, key: Hashable) -> _Entry | None:
        entry = self._entries.get(key)
        if entry is not None:
            entry.used = time.monotonic()
        return entry

    def _put(self, key: Hashable, value: object) -> None:
        size = nbytes(value)
        if size > LARGEST_SHARE * self.budget:
            LOG.info("not caching a %.1f MB value (budget %.0f MB)", size / 1e6, self.budget / 1e6)
            return
        with self._lock:
            old = self._entries.pop(key, None)
            self.total -= old.size if old else 0
            self._entries[key] = _Entry(value, size, time.monotonic())
            self.total += size
            self._evict()

    def _evict(self) -> None:
        now = time.monotonic()
        while self.total > self.budget and len(self._entries) > 1:
            key = max(self._entries, key=lambda k: self._score(self._entries[k], now))
            self.total -= self._entries.pop(key).size
            self.evictions += 1

    @staticmethod
    def _score(entry: _Entry, now: float) -> float:
        return entry.size * (now - entry.used + 1.0)

    def clear(self) -> None:
        """Drop every entry."""
        with self._lock:
            self._entries.clear()
            self.total = 0

    def __len__(self) -> int:
        return len(self._entries)


#: The server's one cache of computed results.
CACHE = ByteCache(MEMORY_BUDGET)


def cached(func: Callable[..., T]) -> Callable[..., T]:
    """Cache ``func`` in :data:`CACHE`, keyed by its name and its arguments.

    Like ``st.cache_resource``, arguments whose name starts with ``_`` are not part of
    the key (the record's array: its content hash is passed beside it). The value is
    shared: do not modify it.
    """
    signature = inspect.signature(func)
    hashed = [name for name in signature.parameters if not name.startswith("_")]

    def key_of(*args: Any, **kwargs: Any) -> tuple:
        bound = signature.bind(*args, **kwargs)
        bound.apply_defaults()
        return (func.__module__, func.__qualname__, *(bound.arguments[n] for n in hashed))

    @functools.wraps(func)
    def wrapper(*args: Any, **kwargs: Any) -> T:
        GUARD.start()
        return CACHE.get(key_of(*args, **kwargs), functools.partial(func, *args, **kwargs))

    wrapper.clear = CACHE.clear  # type: ignore[attr-defined]
    # the kept value for these arguments (None: not kept), never computed
    wrapper.peek = lambda *a, **k: CACHE.peek(key_of(*a, **k))  # type: ignore[attr-defined]
    wrapper.forget = lambda *a, **k: CACHE.forget(key_of(*a, **k))  # type: ignore[attr-defined]
    return wrapper


def trim() -> bool:
    """Return the C heap's free memory to the system (glibc ``malloc_trim``); False if
    this C library has none."""
    try:
        return bool(ctypes.CDLL(None).malloc_trim(0))
    except (OSError, AttributeError):  # not glibc
        return False


class MemoryGuard:
    """Frees what ended sessions and evicted entries held (see the module's Notes).

    Parameters
    ----------
    sessions : callable
        The ids of the server's live sessions, or None when they cannot be read.
    cache : ByteCache
        The cache whose evictions also trigger a collection.
    """

    def __init__(self, sessions: Callable[[], set[str] | None], cache: ByteCache) -> None:
        self._sessions = sessions
        self._cache = cache
        self._seen: set[str] = set()
        self._evictions = cache.evictions
        self._thread: threading.Thread | None = None
        self._lock = threading.Lock()
        self._last: float | None = None  # monotonic time of the last collection
        self.collections = 0

    def tick(self) -> bool:
        """One look: collect and trim if a session ended or an entry was evicted; in a
        server (the sessions can be read), also on the first look and once
        :data:`REFREEZE_SECONDS` passed, and freeze the survivors."""
        live = self._sessions()
        ended = live is not None and bool(self._seen - live)
        self._seen = set(live or ())
        evicted = self._cache.evictions != self._evictions
        self._evictions = self._cache.evictions
        now = time.monotonic()
        serving = live is not None  # in a server (tests and scripts: no freezing)
        due = serving and (self._last is None or now - self._last >= REFREEZE_SECONDS)
        if not (ended or evicted or due):
            return False
        t0 = time.perf_counter()
        gc.unfreeze()
        gc.collect()
        if serving:
            gc.freeze()  # survivors: Python's automatic collections skip them from now on
        trim()
        self._last = now
        self.collections += 1
        trace.write({"guard": time.time(), "seconds": time.perf_counter() - t0})
        return True

    def start(self) -> None:
        """Start the guard's thread (once; later calls do nothing)."""
        with self._lock:
            if self._thread is not None:
                return
            self._thread = threading.Thread(target=self._run, name="noisevar-memory", daemon=True)
            self._thread.start()

    def _run(self) -> None:
        while True:
            time.sleep(GUARD_SECONDS)
            try:
                self.tick()
            except Exception:  # noqa: BLE001 - a guard's failure must not end the server
                LOG.warning("memory guard failed", exc_info=True)


#: The server's one memory guard (started by the first cached call).
GUARD = MemoryGuard(live_session_ids, CACHE)

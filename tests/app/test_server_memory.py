"""The server's memory: caches bounded in bytes, shared, and session folders removed (issue 29)."""

from __future__ import annotations

import gc
import io
import os
import sys
import threading
import time
from pathlib import Path

import numpy as np
import plotly.graph_objects as go
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from dashboard import budget  # noqa: E402
from dashboard.budget import ByteCache, budget_bytes, nbytes  # noqa: E402
from dashboard.session_dirs import PREFIX, SessionFolder, sweep  # noqa: E402

MB = 1024 * 1024


def test_nbytes_counts_arrays_inside_results():
    a = np.zeros(1_000_000)
    assert nbytes(a) >= a.nbytes
    assert nbytes({"x": (a, [a])}) < 2 * a.nbytes  # one array counted once
    fig = go.Figure(go.Scatter(x=np.arange(100_000.0), y=np.zeros(100_000)))
    assert nbytes(fig) >= 1.6e6


def test_the_cache_stays_within_its_budget_and_drops_the_largest_oldest_first():
    cache = ByteCache(40 * MB)
    for i in range(20):  # 20 distinct 8 MB results: 160 MB asked for
        cache.get(("big", i), lambda: np.zeros(MB))
        assert cache.total <= cache.budget
    small = cache.get("small", lambda: np.zeros(1000))
    for i in range(5):
        cache.get(("big", 100 + i), lambda: np.zeros(MB))
    assert cache.total <= cache.budget and cache.evictions >= 20
    assert cache.get("small", lambda: None) is small  # the small, recent entry stayed
    # a value over a quarter of the budget is returned and not kept
    huge = cache.get("huge", lambda: np.zeros(2 * MB))
    assert huge.size == 2 * MB and cache.get("huge", lambda: None) is None


def test_identical_requests_from_many_sessions_compute_once():
    cache = ByteCache(10 * MB)
    calls = []

    def slow() -> np.ndarray:
        calls.append(1)
        time.sleep(0.2)
        return np.ones(10)

    out = []
    threads = [threading.Thread(target=lambda: out.append(cache.get("k", slow))) for _ in range(8)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(calls) == 1 and len(out) == 8 and all(o is out[0] for o in out)


def test_an_error_is_raised_and_not_kept():
    cache = ByteCache(MB)
    with pytest.raises(ValueError):
        cache.get("k", lambda: (_ for _ in ()).throw(ValueError("bad")))
    assert cache.get("k", lambda: 3) == 3


def test_the_budget_is_one_documented_setting(monkeypatch):
    monkeypatch.setenv(budget.BUDGET_ENV, "64")
    assert budget_bytes() == 64 * MB
    for bad in ("0", "-5", "nan", "1e999", "lots"):
        monkeypatch.setenv(budget.BUDGET_ENV, bad)
        assert budget_bytes() == budget.DEFAULT_BUDGET_MB * MB
    monkeypatch.delenv(budget.BUDGET_ENV)
    assert budget_bytes() == budget.DEFAULT_BUDGET_MB * MB


def test_the_dashboard_caches_share_one_bounded_cache(monkeypatch):
    from dashboard import cache, workers

    monkeypatch.setattr(workers, "WORKERS", 0)  # the cache, not the pool (test_workers.py)

    budget.CACHE.clear()
    z = np.random.default_rng(1).normal(size=4000)
    a = cache._estimate_cached("digest-a", "auto", "{}", 0, z.size, z, None)
    b = cache._estimate_cached("digest-a", "auto", "{}", 0, z.size, z.copy(), None)  # another
    assert a is b and 0 < budget.CACHE.total <= budget.CACHE.budget


def test_a_session_folder_goes_with_its_session(tmp_path):
    owner = SessionFolder("abc123")
    path = owner.path
    (path / "uploads").mkdir()
    (path / "uploads" / "a.csv").write_text("x\n1\n")
    assert path.is_dir() and path.name.startswith(f"{PREFIX}{os.getpid()}-abc123.")
    del owner  # Streamlit drops the session's state
    gc.collect()
    assert not path.exists()


def test_the_sweep_removes_ended_sessions_and_dead_servers_only(tmp_path):
    mine_alive = tmp_path / f"{PREFIX}{os.getpid()}-alive.x"
    mine_gone = tmp_path / f"{PREFIX}{os.getpid()}-gone.x"
    other_server = tmp_path / f"{PREFIX}1-s.x"  # pid 1 runs: another server's session
    dead_server = tmp_path / f"{PREFIX}999999999-s.x"
    for p in (mine_alive, mine_gone, other_server, dead_server):
        p.mkdir()
    gone = sweep({"alive"}, tmp_path)
    assert sorted(gone) == sorted([mine_gone, dead_server])
    assert mine_alive.is_dir() and other_server.is_dir()


def test_an_upload_is_read_without_a_whole_file_copy():
    from streamlit.runtime.uploaded_file_manager import UploadedFile, UploadedFileRec

    data = bytes(8 * MB)
    up = UploadedFile(UploadedFileRec("id", "big.csv", "text/csv", data), None)  # type: ignore[arg-type]
    up.read(10)
    assert up.getvalue() is data  # what dashboard/loading.py passes on: the upload's own bytes
    assert isinstance(up, io.BytesIO)


class _Cyclic:
    """A result in a reference cycle (as a Plotly figure and its traces are)."""

    def __init__(self) -> None:
        self.data = np.zeros(MB // 8)
        self.me = self


def test_a_closed_sessions_signal_is_freed_by_the_memory_guard(unfrozen):
    """A closed session's state is a reference cycle: without a collection its loaded
    signal stays (the server turns off Streamlit's collection after each run); the guard
    collects once it sees the session gone."""
    import weakref

    from streamlit.testing.v1 import AppTest

    from dashboard.state import SIGNAL_KEY

    live = {"a", "b"}
    guard = budget.MemoryGuard(lambda: set(live), ByteCache(MB))
    assert guard.tick()  # sees the sessions; its first look collects and freezes
    app_file = str(Path(__file__).resolve().parents[2] / "app.py")
    gc.disable()
    try:
        refs = []
        for seed in (1, 2):
            app = AppTest.from_file(app_file, default_timeout=60)
            app.query_params["sig"] = f"gen:fast-slow;n=30000;seed={seed}"
            app.switch_page("app_pages/Signal.py").run()
            assert not app.exception
            refs.append(weakref.ref(app.session_state[SIGNAL_KEY]))
            del app
        assert all(r() is not None for r in refs)  # the cycle holds them
        assert not guard.tick()  # no session ended: nothing to do
        live.clear()  # Streamlit dropped both sessions
        assert guard.tick() and guard.collections == 2
        assert all(r() is None for r in refs)
    finally:
        gc.enable()


def test_an_evicted_entry_in_a_cycle_is_freed_by_the_memory_guard(unfrozen):
    cache = ByteCache(6 * MB)
    guard = budget.MemoryGuard(lambda: None, cache)
    gc.disable()
    try:
        first = cache.get("a", _Cyclic)
        ref = __import__("weakref").ref(first)
        del first
        for key in "bcdefghij":
            cache.get(key, _Cyclic)
        assert cache.evictions and ref() is not None
        assert guard.tick()
        assert ref() is None
        assert not guard.tick()  # nothing new
    finally:
        gc.enable()


@pytest.fixture
def unfrozen():
    """The guard freezes the survivors of its collections: thaw them after the test."""
    yield
    gc.unfreeze()


def test_the_guards_collection_freezes_the_survivors_and_thaws_them_for_the_next(
    unfrozen, monkeypatch
):
    """Python's automatic full collections skip what survived the guard's last one (they
    scanned every object of the server, holding the GIL); a session's state frozen while
    it was alive is still freed by the guard once the session ends."""
    live = {"a"}
    guard = budget.MemoryGuard(lambda: set(live), ByteCache(MB))
    state = _Cyclic()  # the live session's state, a cycle
    ref = __import__("weakref").ref(state)
    gc.disable()
    try:
        assert guard.tick() and gc.get_freeze_count() > 1000
        del state
        gc.collect()  # an automatic collection: the frozen cycle is not even looked at
        assert ref() is not None
        assert not guard.tick()  # nothing ended, not due
        live.clear()  # the session ended
        assert guard.tick() and ref() is None and gc.get_freeze_count() > 1000
        monkeypatch.setattr(budget, "REFREEZE_SECONDS", 0.0)
        assert guard.tick()  # due: collects and refreezes even with nothing ended
    finally:
        gc.enable()


def test_a_session_past_its_reconnect_time_is_shut_down_and_freed():
    """Streamlit's session storage hides an expired session but keeps it (and never shuts
    it down: its uploads stay) until a later write; the reaper removes and shuts it down."""
    import weakref

    from streamlit.runtime.memory_session_storage import MemorySessionStorage
    from streamlit.runtime.session_manager import SessionInfo

    from dashboard.session_dirs import shut_down_expired

    shut: list[str] = []

    class Session:
        def __init__(self, sid: str) -> None:
            self.id = sid
            self.signal = np.zeros(MB)

        def shutdown(self) -> None:
            shut.append(self.id)

    storage = MemorySessionStorage(ttl_seconds=0.05)
    session = Session("closed-tab")
    ref = weakref.ref(session)
    storage.save(SessionInfo(client=None, session=session, script_run_count=1))  # type: ignore[arg-type]
    del session
    time.sleep(0.1)
    assert storage.list() == [] and ref() is not None  # hidden, still held
    assert shut_down_expired(storage) == 1
    assert shut == ["closed-tab"] and ref() is None
    assert shut_down_expired(storage) == 0 and shut_down_expired(object()) == 0

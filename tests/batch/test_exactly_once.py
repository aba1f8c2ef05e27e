"""Batch faults (issue 29): a kill at each step of the commit sequence, two batches on one
output, random SIGKILLs of the command; no row lost or doubled, no process left behind."""

from __future__ import annotations

import json
import os
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

import numpy as np
import pandas as pd
import pytest

import noisevar as nv
from noisevar.batch import _output, check_jobs, machine_jobs, read_table
from noisevar.cli import main
from noisevar.errors import NoisevarError

BATCH = sys.modules["noisevar.batch"]
N = 1200
COLS = ["file", "channel", "variance", "ci95_low", "ci95_high", "n_total", "hash", "error"]


def _save(path: Path, seed: int) -> None:
    rng = np.random.default_rng(seed)
    np.save(path, np.cumsum(rng.normal(0, 0.05, (N, 2)), axis=0) + rng.normal(0, 1, (N, 2)))


def _fleet(root: Path, n: int = 6) -> list[str]:
    root.mkdir(parents=True, exist_ok=True)
    for i in range(n):
        _save(root / f"u{i}.npy", i)
    (root / "broken.csv").write_text("x,y\n1.0,oops\n")
    return sorted(str(p) for p in root.iterdir())


def _table(frame: pd.DataFrame) -> pd.DataFrame:
    return frame[COLS].sort_values(["file", "channel"]).reset_index(drop=True)


def _assert_exact(frame: pd.DataFrame, files: list[str]) -> None:
    """Each given file's rows once (two channels, or one error row), no other file."""
    assert sorted(frame["file"].unique()) == sorted(files)
    assert not frame.duplicated(["file", "channel"]).any()
    for f, rows in frame.groupby("file"):
        assert len(rows) == (1 if f.endswith(".csv") else 2)


class Killed(BaseException):
    """A kill: nothing after it runs (the process is gone)."""


def _kill_at(monkeypatch, step: str, nth: int) -> None:
    """Every commit point from the ``nth`` ``step`` on raises: the process died there."""
    seen = {"n": 0, "dead": False}

    def point(name: str) -> None:
        if name == step:
            seen["n"] += 1
        if seen["dead"] or (name == step and seen["n"] == nth):
            seen["dead"] = True
            raise Killed(name)

    monkeypatch.setattr(_output, "commit_point", point)


KILLS = [(s, 1) for s in _output.COMMIT_STEPS] + [("journalled", 3)]


@pytest.mark.parametrize(("step", "nth"), KILLS)
def test_a_kill_at_each_commit_step_loses_and_doubles_nothing(tmp_path, monkeypatch, step, nth):
    root = tmp_path / "logs"
    files = _fleet(root)
    out = tmp_path / "noise.parquet"
    nv.batch(files[:5], out=out, method="diff2", progress=False)  # a table from an earlier run
    _save(root / "u1.npy", 99)  # changed: redone; u5 and broken.csv new; u0 no longer given
    given = files[1:]
    _kill_at(monkeypatch, step, nth)
    with pytest.raises(Killed):
        nv.batch(given, out=out, method="diff2", progress=False)
    monkeypatch.undo()
    rerun = nv.batch(given, out=out, method="diff2", progress=False)
    _assert_exact(rerun, given)
    clean = nv.batch(given, method="diff2", progress=False)
    pd.testing.assert_frame_equal(_table(rerun), _table(clean), check_dtype=False)
    pd.testing.assert_frame_equal(_table(read_table(out)), _table(clean), check_dtype=False)
    assert not _output.journal_path(out).exists()
    assert not list(tmp_path.glob(".noise.parquet.tmp-*"))  # a killed run's temporary: removed


def test_a_doubled_table_and_a_cut_journal_line_are_healed(tmp_path):
    root = tmp_path / "logs"
    files = _fleet(root, 3)
    out = tmp_path / "noise.csv"
    first = nv.batch(files, out=out, method="diff2", progress=False)
    pd.concat([first, first]).to_csv(out, index=False)  # what the old commit left (issue 29)
    journal = _output.journal_path(out)
    rows = json.loads(first[first["file"] == files[1]].to_json(orient="records"))
    line = json.dumps({"file": files[1], "rows": rows})
    journal.write_text(line + "\n" + line[: len(line) // 2])  # the last line cut by a kill
    again = nv.batch(files, out=out, method="diff2", progress=False)
    _assert_exact(again, files)
    pd.testing.assert_frame_equal(_table(again), _table(first), check_dtype=False)


def test_two_batches_on_one_output_the_second_is_refused(tmp_path, capsys):
    root = tmp_path / "logs"
    files = _fleet(root, 3)
    out = tmp_path / "noise.parquet"
    started, release = threading.Event(), threading.Event()
    result: dict = {}

    def slow(done: int, total: int) -> None:
        started.set()
        release.wait(30)

    def first() -> None:
        result["frame"] = nv.batch(files, out=out, method="diff2", progress=slow)

    thread = threading.Thread(target=first)
    thread.start()
    assert started.wait(30)
    with pytest.raises(NoisevarError, match="another batch is writing noise.parquet"):
        nv.batch(files, out=out, method="diff2", progress=False)
    code = main(["batch", *files, "--out", str(out), "--method", "diff2", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "another batch is writing" in err
    release.set()
    thread.join(60)
    _assert_exact(result["frame"], files)
    _assert_exact(read_table(out), files)


def test_jobs_are_bounded_by_the_machine_and_a_bad_scheduler_is_one_line(
    tmp_path, capsys, monkeypatch
):
    bound = machine_jobs()
    assert bound == len(os.sched_getaffinity(0))
    assert check_jobs(bound) == (bound, None) and check_jobs(None) == (1, None)
    jobs, why = check_jobs(10**9)
    assert jobs == bound and f"using {bound}" in why
    with pytest.raises(NoisevarError, match="whole number"):
        check_jobs(0)
    files = _fleet(tmp_path / "logs", 2)
    monkeypatch.setattr(BATCH, "machine_jobs", lambda: 1)  # a one-CPU machine: no pool
    with pytest.warns(UserWarning, match="using 1"):
        nv.batch(files, method="diff2", jobs=3, progress=False)
    code = main(["batch", *files, "--jobs", "1000000000", "--method", "diff2", "--quiet"])
    captured = capsys.readouterr()
    assert code == 0 and "jobs 1000000000 is more than the 1 CPUs" in captured.err
    code = main(["batch", *files, "--scheduler", "not a url", "--quiet"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "'not a url' is not a scheduler address" in err


def _group(pgid: int) -> list[int]:
    """Live processes of the process group ``pgid`` (from /proc: no psutil)."""
    pids = []
    for d in os.listdir("/proc"):
        if not d.isdigit():
            continue
        try:
            with open(f"/proc/{d}/stat", "rb") as fh:
                fields = fh.read().rsplit(b")", 1)[1].split()
        except OSError:
            continue
        if int(fields[2]) == pgid and fields[0] not in (b"Z", b"X"):
            pids.append(int(d))
    return pids


def _size(journal: Path) -> int:
    try:
        return journal.stat().st_size
    except OSError:
        return 0


def _wait(cond, timeout: float) -> bool:
    end = time.monotonic() + timeout
    while time.monotonic() < end:
        if cond():
            return True
        time.sleep(0.05)
    return cond()


@pytest.mark.skipif(not sys.platform.startswith("linux"), reason="reads /proc")
def test_random_sigkills_of_the_command_lose_nothing_and_leave_no_process(tmp_path):
    """Five SIGKILLs at seeded moments, --jobs 1 and 2 in turn, a few files changed before
    each run; then a run to the end: the table equals a clean run, no process remains."""
    rng = np.random.default_rng(29)
    root = tmp_path / "logs"
    files = _fleet(root, 10)
    out = tmp_path / "noise.csv"
    journal = _output.journal_path(out)
    cmd = [sys.executable, "-m", "noisevar", "batch", str(root), "--out", str(out), "--quiet"]
    env = {**os.environ, "PYTHONWARNINGS": "ignore"}
    killed = 0
    for k in range(5):
        jobs = 1 + k % 2
        for i in rng.choice(10, 3, replace=False):
            _save(root / f"u{i}.npy", 1000 * (k + 1) + int(i))
        before = _size(journal)
        proc = subprocess.Popen(
            [*cmd, "--jobs", str(jobs)], start_new_session=True, env=env, stderr=subprocess.PIPE
        )
        # once work is under way (a row journalled, or the run done), a seeded moment later
        _wait(lambda p=proc, b=before: _size(journal) > b or p.poll() is not None, 60)
        time.sleep(rng.uniform(0.0, 0.2))
        if proc.poll() is None:  # on a fast machine the run may be done already
            os.kill(proc.pid, signal.SIGKILL)
            killed += 1
        proc.wait()
        assert _wait(lambda p=proc: not _group(p.pid), 10), f"left behind: {_group(proc.pid)}"
    assert killed >= 2, f"only {killed} of 5 runs were still going when killed"
    done = subprocess.run([*cmd, "--jobs", "2"], env=env, capture_output=True, text=True)
    assert done.returncode == 0, done.stderr
    table = read_table(out)
    _assert_exact(table, files)
    clean = nv.batch(files, progress=False)
    pd.testing.assert_frame_equal(_table(table), _table(clean), check_dtype=False)

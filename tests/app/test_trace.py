"""The load benchmark's script-run trace (dashboard/trace.py): off by default, one line per run."""

from __future__ import annotations

import json
import time

import pytest

from dashboard import trace


def test_a_traced_run_writes_its_pool_wait_and_outcome(tmp_path, monkeypatch) -> None:
    path = tmp_path / "trace.jsonl"
    monkeypatch.setenv(trace.TRACE_ENV, str(path))
    with trace.script_run("Compare"), trace.pool_wait():
        time.sleep(0.05)
    with pytest.raises(KeyError), trace.script_run("Estimator"):
        raise KeyError("a rerun")
    first, second = (json.loads(line) for line in path.read_text().splitlines())
    assert first["page"] == "Compare" and first["outcome"] == "done"
    assert 0.05 <= first["pool"] <= first["end"] - first["start"]
    assert first["cpu"] < 0.05  # sleeping is not CPU
    assert second["outcome"] == "KeyError" and second["pool"] == 0.0


def test_untraced_runs_write_nothing(tmp_path, monkeypatch) -> None:
    monkeypatch.delenv(trace.TRACE_ENV, raising=False)
    with trace.script_run("Compare"), trace.pool_wait():
        pass
    trace.write({"x": 1})
    assert not trace.enabled() and list(tmp_path.iterdir()) == []


def test_a_fragment_inside_a_traced_run_is_part_of_it(tmp_path, monkeypatch) -> None:
    path = tmp_path / "trace.jsonl"
    monkeypatch.setenv(trace.TRACE_ENV, str(path))
    with trace.script_run("Estimator"):
        with trace.script_run("Estimator (fragment)"), trace.pool_wait():
            time.sleep(0.02)
    (only,) = (json.loads(line) for line in path.read_text().splitlines())
    assert only["page"] == "Estimator" and only["pool"] >= 0.02

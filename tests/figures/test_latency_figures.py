"""Every latency figure built from a short simulated flight."""

from __future__ import annotations

import pytest
from figure_checks import axis_titles, log_axes_labelled, longest_trace, trace_names

from noisevar.figures.latency import cost_figure, delay_figure, records_figure
from noisevar.systems.latency import LatencyResult, LatencyScenario, run_latency, simulate_latency


@pytest.fixture(scope="module")
def result() -> LatencyResult:
    return run_latency(simulate_latency(LatencyScenario(duration_s=120.0), seed=0))


def test_result_follows_the_protocol(result: LatencyResult) -> None:
    assert result.runs == 1 and result.label == "latency"
    result.check_run(0)


def test_records_figure(result: LatencyResult) -> None:
    fig = records_figure(result)
    names = trace_names(fig)
    assert names[:2] == ["AHRS (on time)", "GPS (late)"] and names[2].startswith("GPS moved back")
    assert axis_titles(fig) == {"xaxis": "time (s)", "yaxis": "speed (m/s)"}
    assert longest_trace(fig) == result.record.reference.size
    assert longest_trace(records_figure(result, max_points=100)) <= 100


def test_cost_figure(result: LatencyResult) -> None:
    fig = cost_figure(result)
    names = trace_names(fig)
    assert names[-1] == "whole record"
    assert names[:-1] == ["segments (scaled)"] * len(result.segments.delay_s)
    assert axis_titles(fig)["xaxis"] == "delay tried (ms)"
    assert log_axes_labelled(fig) == []
    assert len(cost_figure(result, segments=False).data) == 1


def test_delay_figure(result: LatencyResult) -> None:
    fig = delay_figure(result)
    assert trace_names(fig) == [
        "coarse (±2σ)",
        "true",
        "measurable + filtered unknown",
        "fixed compensation",
        "measurable part",
    ]
    assert axis_titles(fig) == {"xaxis": "segment start (s)", "yaxis": "delay (ms)"}

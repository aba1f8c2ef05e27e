"""Every fusion figure built from a small seeded run."""

from __future__ import annotations

import pytest
from figure_checks import (
    axis_titles,
    log_axes_labelled,
    longest_trace,
    trace_length,
    trace_names,
)

from noisevar.errors import NoisevarError
from noisevar.figures.fusion import error_figure, isolation_figure, r_track_figure, track_figure
from noisevar.systems.fusion import FusionResult, FusionScenario, run_fusion, simulate_fusion

N = 120


@pytest.fixture(scope="module")
def results() -> list[FusionResult]:
    data = simulate_fusion(FusionScenario(n_steps=N, fault="noise-step"), seed=0, runs=2)
    return [run_fusion(data, local="vb"), run_fusion(data, local="vb", isolation=True)]


def test_results_follow_the_protocol(results: list[FusionResult]) -> None:
    assert [r.runs for r in results] == [2, 2]
    assert [r.label for r in results] == ["vb", "vb+isolation"]


def test_track_figure(results: list[FusionResult]) -> None:
    fig = track_figure(results)
    assert trace_names(fig) == ["truth", "vb", "vb+isolation"]
    assert axis_titles(fig) == {"xaxis": "east (m)", "yaxis": "north (m)"}
    assert longest_trace(fig) == N
    small = track_figure(results, max_points=40)
    assert trace_length(small, "vb") <= 40 and trace_length(small, "vb+isolation") <= 40


def test_error_figure(results: list[FusionResult]) -> None:
    fig = error_figure(results)
    names = trace_names(fig)
    assert len(names) == 2 and names[0].startswith("vb (RMSE")
    assert axis_titles(fig)["xaxis"] == "time (s)"
    assert "position error (m)" in axis_titles(fig)["yaxis"]
    assert longest_trace(error_figure(results, max_points=40)) <= 40
    assert len(error_figure(results, run=1).data) == 2


def test_r_track_figure(results: list[FusionResult]) -> None:
    fig = r_track_figure(results[0])
    assert trace_names(fig) == ["true R", "vb R̂"]
    assert axis_titles(fig) == {"xaxis": "time (s)", "yaxis": "variance"}
    assert log_axes_labelled(fig) == []
    assert longest_trace(r_track_figure(results[0], max_points=40)) <= 40


def test_isolation_figure(results: list[FusionResult]) -> None:
    fig = isolation_figure(results[1])
    names = trace_names(fig)
    assert names[0] == "position A" and "velocity" in names
    assert axis_titles(fig) == {"xaxis": "time (s)", "yaxis": "NIS"}
    assert log_axes_labelled(fig) == []
    assert longest_trace(isolation_figure(results[1], max_points=40)) <= 40


@pytest.mark.parametrize("run", [-1, 2])
def test_bad_run_is_refused(results: list[FusionResult], run: int) -> None:
    for build, arg in (
        (track_figure, results),
        (error_figure, results),
        (r_track_figure, results[0]),
        (isolation_figure, results[1]),
    ):
        with pytest.raises(NoisevarError, match="out of range"):
            build(arg, run=run)


def test_foreign_results_are_refused() -> None:
    with pytest.raises(NoisevarError, match="FusionResult"):
        track_figure([object()])

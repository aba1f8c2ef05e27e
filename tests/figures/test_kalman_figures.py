"""Every Kalman-filter figure built from a small seeded scenario."""

from __future__ import annotations

import pytest
from figure_checks import axis_titles, longest_trace, trace_length, trace_names

from noisevar.errors import NoisevarError
from noisevar.figures.kalman import (
    innovations_figure,
    r_estimates_figure,
    states_figure,
    track_figure,
)
from noisevar.kalman import FilterResult, FixedR
from noisevar.systems.scenarios import Scenario, noise_step


@pytest.fixture(scope="module")
def scenario() -> Scenario:
    return noise_step(runs=2, seed=0, n_steps=400)


@pytest.fixture(scope="module")
def result(scenario: Scenario) -> FilterResult:
    return scenario.run(FixedR())


def test_track_figure(scenario: Scenario, result: FilterResult) -> None:
    fig = track_figure(result, z=scenario.z)
    assert trace_names(fig) == ["measured", "truth", "fixed"]
    assert set(axis_titles(fig)) == {"xaxis", "yaxis"}
    assert trace_length(track_figure(result, z=scenario.z, max_points=50), "fixed") <= 50


def test_states_figure(result: FilterResult) -> None:
    fig = states_figure(result)
    assert trace_names(fig) == ["truth", "fixed"] * 4
    assert axis_titles(fig)["xaxis4"] == "time (s)"
    assert longest_trace(states_figure(result, max_points=50)) <= 50


def test_r_estimates_figure(scenario: Scenario, result: FilterResult) -> None:
    fig = r_estimates_figure(result, R_true=scenario.R_true[scenario.first_step :])
    assert trace_names(fig) == ["true R", "fixed"] * 2
    assert axis_titles(fig)["xaxis2"] == "time (s)"
    assert longest_trace(r_estimates_figure(result, max_points=50)) <= 50
    # a step in R under a decade: its 1-2-5 values labelled, not Plotly's bare 2 and 5
    for axis in (fig.layout.yaxis, fig.layout.yaxis2):
        assert axis.type == "log" and len(axis.tickvals or ()) >= 2 or axis.dtick == 1


def test_innovations_figure(result: FilterResult) -> None:
    fig = innovations_figure(result)
    names = trace_names(fig)
    assert names.count("innovation") == 2 and "mean NIS" in names
    assert axis_titles(fig)["xaxis3"] == "time (s)"
    assert longest_trace(innovations_figure(result, max_points=50)) <= 50


@pytest.mark.parametrize("build", [track_figure, states_figure, r_estimates_figure])
def test_bad_run_is_refused(result: FilterResult, build) -> None:
    with pytest.raises(NoisevarError, match="out of range"):
        build(result, run=2)


def test_foreign_results_are_refused() -> None:
    with pytest.raises(NoisevarError, match="FilterResult"):
        states_figure([])

"""Every robust-filter figure built from a small seeded run."""

from __future__ import annotations

import numpy as np
import pytest
from figure_checks import (
    axis_titles,
    log_axes_labelled,
    longest_trace,
    trace_length,
    trace_names,
)

from noisevar.errors import NoisevarError
from noisevar.figures.robust import (
    bearing_figure,
    error_figure,
    magvar_figure,
    measured_positions,
    track_figure,
)
from noisevar.systems.robust import RobustResult, RobustScenario, run_robust, simulate_robust

SCEN = RobustScenario(duration_s=120.0, turn_time_s=60.0, start_east_m=-6000.0)


@pytest.fixture(scope="module")
def result() -> RobustResult:
    return run_robust(simulate_robust(SCEN, seed=0, runs=2), skip=5)


def test_result_follows_the_protocol(result: RobustResult) -> None:
    assert result.runs == 2 == result.data.runs
    assert result.label == "ekf/no-bias/huber"


def test_track_figure(result: RobustResult) -> None:
    fig = track_figure(result)
    names = trace_names(fig)
    assert names[2:6] == [
        "truth",
        "EKF (magvar state)",
        "EKF ignoring magvar",
        "Huber EKF (magvar state)",
    ]
    assert names[-1] == "station"
    assert axis_titles(fig) == {"xaxis": "east (m)", "yaxis": "north (m)"}
    small = track_figure(result, max_points=30)
    assert all(trace_length(small, n) <= 30 for n in names[3:6])


def test_error_figure(result: RobustResult) -> None:
    fig = error_figure(result)
    assert len(fig.data) == 3 and trace_names(fig)[2].startswith("Huber EKF")
    assert axis_titles(fig) == {"xaxis": "time (s)", "yaxis": "error (m)"}
    assert log_axes_labelled(fig) == []
    assert longest_trace(error_figure(result, max_points=30)) <= 30


def test_magvar_figure(result: RobustResult) -> None:
    fig = magvar_figure(result)
    assert trace_names(fig) == ["EKF (magvar state)", "±2σ", "Huber EKF (magvar state)", "true"]
    assert axis_titles(fig) == {"xaxis": "time (s)", "yaxis": "magnetic variation (deg)"}


def test_bearing_figure(result: RobustResult) -> None:
    fig = bearing_figure(result)
    assert trace_names(fig) == ["bearing error", "outliers"]
    assert axis_titles(fig) == {"xaxis": "time (s)", "yaxis": "error (deg)"}


def test_measured_positions(result: RobustResult) -> None:
    pos = measured_positions(result, 1)
    assert pos.shape == (result.data.time.size, 2) and np.all(np.isfinite(pos))


@pytest.mark.parametrize(
    "build", [track_figure, error_figure, magvar_figure, bearing_figure, measured_positions]
)
def test_bad_run_is_refused(result: RobustResult, build) -> None:
    with pytest.raises(NoisevarError, match="out of range"):
        build(result, run=2)

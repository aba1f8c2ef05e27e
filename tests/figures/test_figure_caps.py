"""The browser budget: no figure carries more than 10,000 points or 2,000 shapes (2e6 samples)."""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go
import pytest

import noisevar
from noisevar.figures._common import (
    MAX_FIGURE_POINTS,
    MAX_FIGURE_SHAPES,
    capped,
    figure_size,
    log_axis,
)
from noisevar.figures._shapes import merge_runs, runs_of
from noisevar.figures.estimator import (
    envelope_figure,
    signal_figure,
    somd_figure,
    window_tests_figure,
    window_variance_figure,
)
from noisevar.figures.windows import MAX_RUNS
from noisevar.filters.envelope import detrend_windows, noise_amplitude

N = 2_000_000


@pytest.fixture(scope="module")
def big() -> tuple[np.ndarray, noisevar.VarianceEstimate]:
    rng = np.random.default_rng(16)
    z = np.cumsum(rng.normal(0.0, 0.01, N)) + rng.normal(0.0, 1.0, N)
    return z, noisevar.estimate(z, "somd")


def _within_budget(fig: go.Figure) -> None:
    points, shapes = figure_size(fig)
    assert 0 < points <= MAX_FIGURE_POINTS
    assert shapes <= MAX_FIGURE_SHAPES


def test_somd_figure_on_two_million_samples(big) -> None:
    z, est = big
    assert int(est.details.kept_windows.size) > 40_000  # far more windows than the budget
    fig = somd_figure(z, est, 0.1)
    _within_budget(fig)
    kept = next(t for t in fig.data if t.name == "kept windows")
    assert kept.fill == "toself" and np.isnan(kept.x).sum() <= MAX_RUNS  # merged into runs
    assert "shaded over" in fig.layout.annotations[-1].text


def test_window_figures_on_two_million_samples(big) -> None:
    z, est = big
    sel = est.details.selection
    _within_budget(window_tests_figure(sel, 0.5, 10.0, 0.1))
    _within_budget(window_variance_figure(est, 0.1))
    _within_budget(signal_figure(z, 0.1, clean=z))
    amp = noise_amplitude(z, 40)
    _within_budget(envelope_figure(amp, detrend_windows(z, 40).ravel(), amp, 0.1))


def test_capped_thins_points_with_their_hover_data_and_drops_extra_shapes() -> None:
    rng = np.random.default_rng(0)
    x = rng.uniform(0, 1, 30_000)
    y = rng.normal(size=30_000)
    y[123] = 50.0  # an extreme survives the thinning
    shapes = [{"type": "line", "x0": i, "x1": i, "y0": 0, "y1": 1} for i in range(2_500)]
    fig = go.Figure(
        [
            go.Scattergl(x=x, y=y, mode="markers", customdata=np.arange(x.size)),
            go.Scatter(x=[0, 1], y=[0, 0], name="short"),
        ],
        layout={"shapes": shapes},
    )
    capped(fig)
    points, n_shapes = figure_size(fig)
    assert points <= MAX_FIGURE_POINTS and n_shapes == MAX_FIGURE_SHAPES
    thinned = fig.data[0]
    assert 50.0 in thinned.y
    kept = np.asarray(thinned.customdata).astype(int)
    np.testing.assert_array_equal(np.asarray(thinned.y), y[kept])  # hover data still aligned
    assert len(fig.data[1].x) == 2  # short traces are kept whole
    assert "not drawn" in fig.layout.annotations[-1].text


def test_merge_runs_closes_the_narrowest_gaps_first() -> None:
    a, b = runs_of([1, 1, 0, 1, 0, 0, 0, 1, 1, 0, 0, 1])
    np.testing.assert_array_equal(a, [0, 3, 7, 11])
    np.testing.assert_array_equal(b, [2, 4, 9, 12])
    a2, b2, gap = merge_runs(a, b, 3)
    np.testing.assert_array_equal(a2, [0, 7, 11])
    np.testing.assert_array_equal(b2, [4, 9, 12])
    assert gap == 1
    a3, b3, _ = merge_runs(a, b, 10)
    assert a3.size == 4


def test_log_axis_labels_decades_only() -> None:
    axis = log_axis("h")
    assert axis["type"] == "log" and axis["dtick"] == 1

"""Parametric curves (tracks) are thinned along their own order, never re-sorted (issue 28)."""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go

from noisevar.figures._common import capped, curve_indices
from noisevar.figures.kalman import track_figure
from noisevar.kalman import STRATEGIES
from noisevar.kalman.strategies import make_strategy
from noisevar.systems.scenarios import SCENARIOS


def _median_step(x: np.ndarray, y: np.ndarray) -> float:
    return float(np.median(np.hypot(np.diff(x), np.diff(y))))


def test_curve_indices_keep_order_and_both_coordinates_extremes() -> None:
    t = np.linspace(0.0, 6 * np.pi, 30_000)
    x, y = 300 * np.cos(t), 300 * np.sin(t)
    idx = curve_indices(x, y, 1000)
    assert idx.size <= 1000
    assert np.all(np.diff(idx) > 0)
    assert np.isclose(x[idx].max(), x.max(), atol=1e-3)
    assert np.isclose(y[idx].min(), y.min(), atol=1e-3)


def test_a_circle_line_is_not_resorted_but_scattered_markers_may_be() -> None:
    t = np.linspace(0.0, 2 * np.pi, 20_000)
    x, y = 300 * np.cos(t), 300 * np.sin(t)
    fig = go.Figure([go.Scatter(x=x, y=y, mode="lines"), go.Scatter(x=x, y=y, mode="markers")])
    capped(fig, max_points=2000)
    line = fig.data[0]
    step = _median_step(np.asarray(line.x), np.asarray(line.y))
    true = _median_step(x, y) * x.size / len(line.x)
    assert 0.5 * true < step < 2.0 * true


def test_gps_circle_track_on_the_adaptive_filter_default_is_a_circle_not_a_disk() -> None:
    """The page's default: gps-circle, seed 0, its featured strategies, the capped track."""
    sc = SCENARIOS["gps-circle"](runs=1, seed=0)
    strategies = [s for s, spec in STRATEGIES.items() if spec.featured][:2]
    res = [
        sc.run(make_strategy(s, h_smooth=sc.h_smooth, R_true=sc.R_true[sc.first_step :]))
        for s in strategies
    ]
    fig = capped(track_figure(res, sc.z[:, sc.first_step :], states=(0, 1), channels=(0, 1)))
    truth = np.asarray(res[0].truth)[0]
    true_step = _median_step(truth[:, 0], truth[:, 1])
    assert 3.0 < true_step < 6.0
    lines = [d for d in fig.data if d.mode == "lines"]
    assert len(lines) == 1 + len(strategies)
    for d in lines:
        ratio = truth.shape[0] / len(d.x)
        step = _median_step(np.asarray(d.x), np.asarray(d.y))
        # close to the true step times the thinning ratio (was 376 m on this 300 m circle)
        assert 0.5 * true_step * ratio < step < 2.0 * true_step * ratio, (d.name, step, ratio)

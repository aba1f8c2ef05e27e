"""Figures of the robust DME/VOR filter (docs/algorithms.md §B3): they take a ``RobustResult``.

* :func:`track_figure` — the station, the true path, the positions the
  range/bearing measurements imply (outliers marked) and each filter's track.
* :func:`error_figure` — horizontal position error over time (RMS over runs
  or one run), the outlier zone shaded.
* :func:`magvar_figure` — the magnetic-variation estimate (±2σ) against the
  truth (paper Fig. 5).
* :func:`bearing_figure` — the bearing measurement error with the outliers.
"""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go

from noisevar.figures._common import (
    COLORS,
    MAX_POINTS,
    PALETTE,
    band,
    check_run,
    downsample_indices,
    layout,
    line_trace,
    log_axis,
    traces_y,
)
from noisevar.systems.robust import RobustResult

LABELS = {
    "ekf": "EKF (magvar state)",
    "no-bias": "EKF ignoring magvar",
    "huber": "Huber EKF (magvar state)",
}


def _zone_shapes(result: RobustResult) -> list[dict]:
    """The outlier zone (samples near the station) as a shaded time band."""
    near = result.data.near_station
    if not near.any():
        return []
    t = result.data.time[near]
    return [band(float(t[0]), float(t[-1]), axis="x", color="rgba(213,94,0,0.10)")]


def measured_positions(result: RobustResult, run: int = 0) -> np.ndarray:
    """Horizontal positions implied by range and bearing, taking the bearing as true (m).

    Parameters
    ----------
    result : RobustResult
        From :func:`~noisevar.systems.robust.run_robust`.
    run : int
        Monte Carlo run.

    Returns
    -------
    ndarray, shape (N, 2)
        ``[east, north]`` of each sample of run ``run``.
    """
    check_run(result, run)
    z = result.data.z[run]
    h = result.data.scenario.height_m
    horiz = np.sqrt(np.maximum(z[:, 0] ** 2 - h * h, 0.0))
    return np.stack([horiz * np.sin(z[:, 1]), horiz * np.cos(z[:, 1])], axis=-1)


def track_figure(
    result: RobustResult,
    run: int = 0,
    max_points: int = MAX_POINTS,
    title: str | None = "Fly-over: truth, measurements, filters",
    height: int = 520,
) -> go.Figure:
    """Plan view of one run.

    Parameters
    ----------
    result : RobustResult
    run : int
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    meas = measured_positions(result, run)
    out = result.data.outlier[run]
    truth = result.data.truth
    traces = [
        go.Scatter(
            x=meas[~out, 0],
            y=meas[~out, 1],
            mode="markers",
            name="range + magnetic bearing (as if true)",
            marker={"color": COLORS["raw"], "size": 3},
        ),
        go.Scatter(
            x=meas[out, 0],
            y=meas[out, 1],
            mode="markers",
            name="bearing outliers",
            marker={"color": PALETTE[1], "size": 5, "symbol": "x"},
        ),
        go.Scatter(
            x=truth[:, 0],
            y=truth[:, 1],
            mode="lines",
            name="truth",
            line={"color": COLORS["truth"], "width": 2},
        ),
    ]
    for i, (name, res) in enumerate(result.filters.items()):
        x = res.x[run]
        idx = downsample_indices(x[:, 0], max_points)
        traces.append(
            go.Scatter(
                x=x[idx, 0],
                y=x[idx, 1],
                mode="lines",
                name=LABELS.get(name, name),
                line={"color": PALETTE[(i + 2) % len(PALETTE)], "width": 1.3},
            )
        )
    traces.append(
        go.Scatter(
            x=[0.0],
            y=[0.0],
            mode="markers",
            name="station",
            marker={"symbol": "triangle-up", "size": 14, "color": "#000"},
        )
    )
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis={"title": "east (m)"},
            yaxis={"title": "north (m)", "scaleanchor": "x"},
        ),
    )


def error_figure(
    result: RobustResult,
    run: int | None = None,
    log: bool = True,
    max_points: int = MAX_POINTS,
    title: str | None = "Horizontal position error",
    height: int = 420,
) -> go.Figure:
    """Position error of each filter over time.

    Parameters
    ----------
    result : RobustResult
    run : int, optional
        One run; default the RMS over runs.
    log : bool
        Logarithmic error axis.
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    if run is not None:
        check_run(result, run)
    dt = result.data.scenario.dt
    traces = []
    for i, name in enumerate(result.filters):
        e = result.position_error(name)
        y = np.sqrt(np.mean(e**2, axis=0)) if run is None else e[run]
        trace, _ = line_trace(
            y,
            f"{LABELS.get(name, name)} (RMSE {result.rmse_position[name]:.0f} m)",
            dt,
            max_points,
            line={"color": PALETTE[(i + 2) % len(PALETTE)], "width": 1.3},
        )
        traces.append(trace)
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis={"title": "time (s)"},
            yaxis=log_axis("error (m)", traces_y(traces)) if log else {"title": "error (m)"},
            shapes=_zone_shapes(result),
        ),
    )


def magvar_figure(
    result: RobustResult,
    run: int = 0,
    title: str | None = "Magnetic variation estimate",
    height: int = 380,
) -> go.Figure:
    """``α̂`` (deg) of the filters that carry it, ±2σ for the Huber filter.

    Parameters
    ----------
    result : RobustResult
    run : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    check_run(result, run)
    t = result.data.time
    traces = []
    for i, name in enumerate(result.filters):
        res = result.filters[name]
        if res.x.shape[-1] < 5:
            continue
        est = np.rad2deg(res.x[run, :, 4])
        color = PALETTE[(i + 2) % len(PALETTE)]
        if res.P is not None and name == "huber":
            sd = 2 * np.rad2deg(np.sqrt(np.maximum(res.P[run, :, 4, 4], 0.0)))
            traces.append(
                go.Scatter(
                    x=np.concatenate([t, t[::-1]]),
                    y=np.concatenate([est + sd, (est - sd)[::-1]]),
                    fill="toself",
                    fillcolor="rgba(0,114,178,0.12)",
                    line={"width": 0},
                    name="±2σ",
                    hoverinfo="skip",
                )
            )
        traces.append(
            go.Scatter(x=t, y=est, mode="lines", name=LABELS.get(name, name), line={"color": color})
        )
    true = result.data.scenario.magvar_deg
    traces.append(
        go.Scatter(
            x=[t[0], t[-1]],
            y=[true, true],
            mode="lines",
            name="true",
            line={"color": COLORS["truth"], "dash": "dash"},
        )
    )
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis={"title": "time (s)"},
            yaxis={"title": "magnetic variation (deg)", "range": [true - 5, true + 5]},
        ),
    )


def bearing_figure(
    result: RobustResult,
    run: int = 0,
    title: str | None = "Bearing measurement error",
    height: int = 360,
) -> go.Figure:
    """Measured magnetic bearing minus the true one (deg), outliers marked.

    Parameters
    ----------
    result : RobustResult
    run : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    check_run(result, run)
    data = result.data
    true_bearing = np.arctan2(data.truth[:, 0], data.truth[:, 1]) - data.truth[:, 4]
    err = np.rad2deg(np.angle(np.exp(1j * (data.z[run, :, 1] - true_bearing))))
    out = data.outlier[run]
    t = data.time
    return go.Figure(
        [
            go.Scatter(
                x=t[~out],
                y=err[~out],
                mode="markers",
                name="bearing error",
                marker={"color": COLORS["raw"], "size": 3},
            ),
            go.Scatter(
                x=t[out],
                y=err[out],
                mode="markers",
                name="outliers",
                marker={"color": PALETTE[1], "size": 5, "symbol": "x"},
            ),
        ],
        layout(
            title,
            height,
            xaxis={"title": "time (s)"},
            yaxis={"title": "error (deg)"},
            shapes=_zone_shapes(result),
        ),
    )


__all__ = ["bearing_figure", "error_figure", "magvar_figure", "measured_positions", "track_figure"]

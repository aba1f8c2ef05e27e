"""Figures of distributed fusion (docs/algorithms.md §B2): they take ``FusionResult`` objects.

* :func:`track_figure` — one run's true path and the fused estimates.
* :func:`error_figure` — position error over time (RMS over runs) of several
  fused filters, the fault interval shaded.
* :func:`r_track_figure` — the VB estimate of a sensor's variance against the
  truth (paper Figs. 3, 5).
* :func:`isolation_figure` — each sensor's chi-square statistic against its
  threshold, and when it was isolated.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import plotly.graph_objects as go
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.figures._common import (
    COLORS,
    MAX_POINTS,
    PALETTE,
    as_list,
    band,
    check_run,
    downsample_indices,
    layout,
    line_trace,
)
from noisevar.figures.budget import log_axis, traces_y
from noisevar.systems.fusion import FusionResult

Results = FusionResult | Sequence[FusionResult]


def _fault_band(result: FusionResult) -> list[dict]:
    """The fault interval as a shaded time band (none when it covers nothing or everything)."""
    mask = result.fault_mask
    if not mask.any() or mask.all():
        return []
    t = result.time[mask]
    return [band(float(t[0]), float(t[-1]), axis="x", color="rgba(213,94,0,0.10)")]


def track_figure(
    results: Results,
    run: int = 0,
    max_points: int = MAX_POINTS,
    title: str | None = "Track: truth and fused estimates",
    height: int = 480,
) -> go.Figure:
    """One run's true path and each result's fused position.

    Parameters
    ----------
    results : FusionResult or list of FusionResult
    run : int
        Monte Carlo run to draw.
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    res = as_list(results, FusionResult)
    check_run(res[0], run)
    truth = res[0].truth[run]
    traces = [
        go.Scatter(
            x=truth[:, 0],
            y=truth[:, 1],
            mode="lines",
            name="truth",
            line={"color": COLORS["truth"], "width": 2},
        )
    ]
    for i, r in enumerate(res):
        x = r.x[run]
        idx = downsample_indices(x[:, 0], max_points)
        traces.append(
            go.Scatter(
                x=x[idx, 0],
                y=x[idx, 1],
                mode="lines",
                name=r.label,
                line={"color": PALETTE[i % len(PALETTE)], "width": 1.2},
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
    results: Results,
    run: int | None = None,
    log: bool = True,
    max_points: int = MAX_POINTS,
    title: str | None = "Position error",
    height: int = 420,
) -> go.Figure:
    """Horizontal position error over time, RMS over runs (or one run).

    Parameters
    ----------
    results : FusionResult or list of FusionResult
    run : int, optional
        Draw this run's error instead of the RMS over runs.
    log : bool
        Logarithmic error axis (a failing sensor's error dwarfs the others).
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    res = as_list(results, FusionResult)
    traces = []
    dt = float(res[0].time[1] - res[0].time[0]) if res[0].time.size > 1 else 1.0
    for i, r in enumerate(res):
        e = r.position_error()
        if run is None:
            y = np.sqrt(np.mean(e**2, axis=0))
        else:
            check_run(r, run)
            y = e[run]
        trace, _ = line_trace(
            y,
            f"{r.label} (RMSE {r.rmse():.2f} m)",
            dt,
            max_points,
            line={"color": PALETTE[i % len(PALETTE)], "width": 1.3},
        )
        traces.append(trace)
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis={"title": "time (s)"},
            yaxis=log_axis(
                "position error (m)" + (" RMS over runs" if run is None else ""),
                np.concatenate([np.ravel(t.y) for t in traces if t.y is not None]),
            )
            if log
            else {"title": "position error (m)" + (" RMS over runs" if run is None else "")},
            shapes=_fault_band(res[0]),
        ),
    )


def r_track_figure(
    result: FusionResult,
    sensor: int = 0,
    channel: int = 0,
    run: int | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = None,
    height: int = 400,
) -> go.Figure:
    """A local filter's ``R`` (the VB estimate) against the true variance.

    Parameters
    ----------
    result : FusionResult
    sensor, channel : int
        Which sensor and measured component.
    run : int, optional
        One run; default the mean over runs (NaN where isolated are skipped).
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    if not 0 <= sensor < len(result.R_track):
        raise NoisevarError(f"sensor {sensor} out of range ({len(result.R_track)} sensors)")
    track: NDArray = result.R_track[sensor][..., channel]
    if run is None:
        with np.errstate(all="ignore"):
            est = np.nanmean(track, axis=0) if np.isfinite(track).any() else track[0]
    else:
        check_run(result, run)
        est = track[run]
    dt = float(result.time[1] - result.time[0]) if result.time.size > 1 else 1.0
    t_est, _ = line_trace(
        est, f"{result.label} R̂", dt, max_points, line={"color": PALETTE[0], "width": 1.5}
    )
    t_true, _ = line_trace(
        result.true_R[sensor][:, channel],
        "true R",
        dt,
        max_points,
        line={"color": COLORS["truth"], "dash": "dash"},
    )
    name = result.sensor_names[sensor]
    return go.Figure(
        [t_true, t_est],
        layout(
            title or f"R of {name}, component {channel}",
            height,
            xaxis={"title": "time (s)"},
            yaxis=log_axis("variance", traces_y([t_true, t_est])),
            shapes=_fault_band(result),
        ),
    )


def isolation_figure(
    result: FusionResult,
    run: int = 0,
    max_points: int = MAX_POINTS,
    title: str | None = "Fault isolation: normalised innovation squared",
    height: int = 420,
) -> go.Figure:
    """Each sensor's chi-square statistic with its threshold; isolated steps marked.

    Parameters
    ----------
    result : FusionResult
    run : int
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    check_run(result, run)
    dt = float(result.time[1] - result.time[0]) if result.time.size > 1 else 1.0
    traces = []
    shapes = _fault_band(result)
    for i, name in enumerate(result.sensor_names):
        color = PALETTE[i % len(PALETTE)]
        nis = np.maximum(result.nis[run, :, i], 1e-6)
        trace, _ = line_trace(nis, name, dt, max_points, line={"color": color, "width": 1})
        traces.append(trace)
        iso = result.isolated[run, :, i]
        if iso.any():
            traces.append(
                go.Scatter(
                    x=result.time[iso],
                    y=nis[iso],
                    mode="markers",
                    marker={"color": color, "symbol": "x", "size": 5},
                    name=f"{name} isolated",
                )
            )
        thr = result.threshold[i]
        if np.isfinite(thr):
            shapes.append(
                {
                    "type": "line",
                    "xref": "paper",
                    "x0": 0,
                    "x1": 1,
                    "y0": thr,
                    "y1": thr,
                    "line": {"color": color, "dash": "dash", "width": 1},
                }
            )
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis={"title": "time (s)"},
            yaxis=log_axis("NIS", traces_y(traces)),
            shapes=shapes,
        ),
    )


__all__ = ["error_figure", "isolation_figure", "r_track_figure", "track_figure"]

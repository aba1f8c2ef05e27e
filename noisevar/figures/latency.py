"""Figures of the GPS latency method (docs/algorithms.md §C): they take a ``LatencyResult``.

* :func:`records_figure` — the on-time (AHRS) and late (GPS) speeds, and the
  GPS speed moved back by the estimated delay (paper Figs. 4, 6, 8).
* :func:`cost_figure` — the least-squares cost against the shift with the
  refined minimum (paper Figs. 5, 7, 9), and each segment's curve faintly.
* :func:`delay_figure` — per-segment coarse delays with ±2σ, the filtered
  total delay (measurable + Kalman estimate of the unknown part), the fixed
  compensation and the truth.
"""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go

from noisevar.figures._common import (
    COLORS,
    MAX_POINTS,
    PALETTE,
    layout,
    line_trace,
    log_axis,
    traces_y,
)
from noisevar.systems.latency import LatencyResult, align_signals


def records_figure(
    result: LatencyResult,
    window_s: tuple[float, float] | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = "AHRS (attitude and heading reference) and GPS speed",
    height: int = 420,
) -> go.Figure:
    """The two speed records (m/s, as the noise settings), and the GPS record realigned.

    Parameters
    ----------
    result : LatencyResult
    window_s : (float, float), optional
        Time range to draw (s); default the whole record.
    max_points : int
        Points drawn per trace.
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    rec = result.record
    T = rec.sample_period
    ref_kn = rec.reference
    late_kn = rec.delayed
    _, aligned = align_signals(rec.reference, rec.delayed, result.coarse.delay_s, T)
    aligned_kn = np.full(rec.reference.size, np.nan)
    aligned_kn[: aligned.size] = aligned
    sl = slice(None)
    if window_s is not None:
        lo, hi = sorted(window_s)
        sl = slice(max(int(lo / T), 0), int(hi / T) + 1)
    t0 = float(rec.time[sl][0]) if rec.time[sl].size else 0.0
    traces = []
    for y, name, color in (
        (ref_kn[sl], "AHRS (on time)", COLORS["truth"]),
        (late_kn[sl], "GPS (late)", PALETTE[1]),
        (aligned_kn[sl], f"GPS moved back {result.coarse.delay_s * 1e3:.0f} ms", PALETTE[0]),
    ):
        trace, _ = line_trace(y, name, T, max_points, line={"color": color, "width": 1.2})
        trace.x = np.asarray(trace.x) + t0
        traces.append(trace)
    return go.Figure(
        traces,
        layout(title, height, xaxis={"title": "time (s)"}, yaxis={"title": "speed (m/s)"}),
    )


def cost_figure(  # long: one figure, built trace by trace in drawing order
    result: LatencyResult,
    segments: bool = True,
    title: str | None = "Least-squares cost against the shift",
    height: int = 420,
) -> go.Figure:
    """Mean squared difference against the delay tried, with the refined minimum.

    Parameters
    ----------
    result : LatencyResult
    segments : bool
        Also draw each segment's cost curve (faint, scaled to its own minimum).
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    coarse = result.coarse
    delays_ms = coarse.shifts * coarse.sample_period * 1e3
    traces: list[go.Scatter] = []
    if segments:
        for j, c in enumerate(result.segments.costs):
            if not np.all(np.isfinite(c)):
                continue
            traces.append(
                go.Scatter(
                    x=delays_ms,
                    y=c / max(float(np.min(c)), 1e-300) * float(np.min(coarse.costs)),
                    mode="lines",
                    line={"color": "rgba(120,120,120,0.25)", "width": 1},
                    name="segments (scaled)",
                    legendgroup="seg",
                    showlegend=j == 0,
                    hoverinfo="skip",
                )
            )
    traces.append(
        go.Scatter(
            x=delays_ms,
            y=coarse.costs,
            mode="lines+markers",
            name="whole record",
            line={"color": PALETTE[0], "width": 2},
            marker={"size": 5},
        )
    )
    est = coarse.delay_s * 1e3
    shape = {
        "type": "line",
        "yref": "paper",
        "y0": 0,
        "y1": 1,
        "x0": est,
        "x1": est,
        "line": {"color": PALETTE[1], "dash": "dash"},
    }
    truth = result.true_delay_s * 1e3
    shape_true = {
        **shape,
        "x0": truth,
        "x1": truth,
        "line": {"color": COLORS["truth"], "dash": "dot"},
    }
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis={"title": "delay tried (ms)"},
            yaxis=log_axis("mean squared difference ((m/s)²)", traces_y(traces)),
            shapes=[shape, shape_true],
            annotations=[
                {
                    "x": est,
                    "y": 1.0,
                    "yref": "paper",
                    "text": f"estimate {est:.1f} ms (true {truth:.1f})",
                    "showarrow": False,
                    "xanchor": "left",
                    "yanchor": "top",
                }
            ],
        ),
    )


def delay_figure(
    result: LatencyResult,
    title: str | None = "Delay per segment: coarse, filtered, fixed, true",
    height: int = 420,
) -> go.Figure:
    """Per-segment delays (ms) over time.

    Parameters
    ----------
    result : LatencyResult
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    t = result.segment_time
    coarse = result.segments.delay_s * 1e3
    err = 2e3 * np.sqrt(result.segments.variance_s2)
    finite = np.isfinite(err) & (err < 1e4)
    filt_sd = 2e3 * np.sqrt(result.unknown_filtered_var)
    traces = [
        go.Scatter(
            x=t[finite],
            y=coarse[finite],
            error_y={"type": "data", "array": err[finite], "visible": True, "thickness": 1},
            mode="markers",
            name="coarse (±2σ)",
            marker={"color": COLORS["raw"], "size": 7},
        ),
        go.Scatter(
            x=t,
            y=result.segment_true_delay_s * 1e3,
            mode="lines",
            line={"color": COLORS["truth"], "shape": "hv", "width": 2},
            name="true",
        ),
        go.Scatter(
            x=t,
            y=result.total_filtered_s * 1e3,
            error_y={"type": "data", "array": filt_sd, "visible": True, "thickness": 1},
            mode="lines+markers",
            line={"color": PALETTE[0], "shape": "hv"},
            name="measurable + filtered unknown",
        ),
        go.Scatter(
            x=[t[0], t[-1]],
            y=[result.coarse.delay_s * 1e3] * 2,
            mode="lines",
            line={"color": PALETTE[1], "dash": "dash"},
            name="fixed compensation",
        ),
        go.Scatter(
            x=t,
            y=result.segment_measurable_s * 1e3,
            mode="lines",
            line={"color": PALETTE[2], "shape": "hv", "dash": "dot"},
            name="measurable part",
        ),
    ]
    lo = float(np.nanmin(result.segment_measurable_s)) * 1e3 - 50
    hi = float(np.nanmax(result.segment_true_delay_s)) * 1e3 + 150
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis={"title": "segment start (s)"},
            yaxis={"title": "delay (ms)", "range": [lo, hi]},
        ),
    )


__all__ = ["cost_figure", "delay_figure", "records_figure"]

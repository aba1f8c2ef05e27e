"""Fleet figures: the noise of every sensor per channel, the sensors flagged, and the channels
of one record side by side."""

from __future__ import annotations

import os

import numpy as np
import plotly.graph_objects as go

from noisevar.batch.fleet import FleetReport
from noisevar.estimators.results import VarianceEstimates
from noisevar.figures._common import COLORS, PALETTE, base_layout
from noisevar.figures.budget import log_axis

FLAG_COLOR = "#D55E00"


def fleet_distribution(report: FleetReport) -> go.Figure:
    """Noise standard deviation of every sensor, one column per channel (log axis).

    Each point is a sensor (hover: its file and robust z); flagged sensors are drawn
    in orange, and a band shows each channel's normal range. A point's ``customdata``
    is ``[file, channel]`` (for click selection).

    Parameters
    ----------
    report : FleetReport
        :func:`noisevar.batch.fleet.fleet_report`.

    Returns
    -------
    plotly.graph_objects.Figure
    """
    fig = go.Figure()
    names = [c.channel for c in report.channels]
    for i, spread in enumerate(report.channels):
        fig.add_shape(
            type="rect",
            x0=i - 0.4,
            x1=i + 0.4,
            y0=spread.low,
            y1=spread.high,
            fillcolor=COLORS["band"],
            line_width=0,
            layer="below",
        )
        fig.add_shape(
            type="line",
            x0=i - 0.4,
            x1=i + 0.4,
            y0=spread.median_std,
            y1=spread.median_std,
            line={"color": COLORS["estimate"], "width": 2},
        )
    for flagged, colour, label in ((False, PALETTE[0], "sensor"), (True, FLAG_COLOR, "flagged")):
        pts = [s for s in report.sensors if s.flagged == flagged and s.channel in names]
        if not pts:
            continue
        jitter = np.random.default_rng(0).uniform(-0.25, 0.25, len(pts))
        fig.add_trace(
            go.Scatter(
                x=[names.index(s.channel) + j for s, j in zip(pts, jitter, strict=True)],
                y=[s.std for s in pts],
                mode="markers",
                name=label,
                marker={
                    "color": colour,
                    "size": 11 if flagged else 7,
                    "symbol": "diamond" if flagged else "circle",
                },
                customdata=[[s.file, s.channel] for s in pts],
                text=[f"{os.path.basename(s.file)}<br>z = {s.z:+.1f}" for s in pts],
                hovertemplate="%{text}<br>std %{y:.4g}<extra></extra>",
            )
        )
    fig.update_layout(
        title="Noise of each sensor, per channel (band: the fleet's normal range)",
        xaxis={
            "tickmode": "array",
            "tickvals": list(range(len(names))),
            "ticktext": names,
            "title": "channel",
        },
        yaxis=log_axis(
            "noise standard deviation",
            [s.std for s in report.sensors if s.channel in names]
            + [v for c in report.channels for v in (c.low, c.high)],
        ),
        height=420,
        margin={"t": 60, "b": 40},
        clickmode="event+select",
    )
    return fig


def flagged_sensors(report: FleetReport, top: int = 20) -> go.Figure:
    """Robust z-scores of the most unusual sensors, flagged ones in orange.

    Parameters
    ----------
    report : FleetReport
        The fleet report.
    top : int
        Sensors shown (most unusual first).

    Returns
    -------
    plotly.graph_objects.Figure
    """
    shown = [s for s in report.sensors if s.z is not None][:top][::-1]
    labels = [f"{os.path.basename(s.file)} · {s.channel}" for s in shown]
    fig = go.Figure(
        go.Bar(
            x=[s.z for s in shown],
            y=labels,
            orientation="h",
            marker_color=[FLAG_COLOR if s.flagged else PALETTE[0] for s in shown],
            customdata=[[s.file, s.channel] for s in shown],
            hovertemplate="%{y}: z = %{x:+.2f}<extra></extra>",
        )
    )
    for x in (-report.threshold, report.threshold):
        fig.add_vline(x=x, line_dash="dash", line_color=COLORS["truth"])
    fig.update_layout(
        title=f"Most unusual sensors (robust z of log std; flagged beyond ±{report.threshold:g})",
        xaxis_title="robust z-score",
        height=max(260, 22 * len(shown) + 100),
        # full names, never cut: the left margin fits the longest label (and grows with it)
        margin={"t": 60, "b": 40, "l": 20 + 7 * max((len(t) for t in labels), default=0)},
        yaxis={"automargin": True, "title": {"text": "file · channel"}},
    )
    return fig


def channels_figure(estimates: VarianceEstimates, names: list[str]) -> go.Figure:
    """Noise standard deviation of each channel of one record, with its 95 % interval.

    Parameters
    ----------
    estimates : VarianceEstimates
        ``noisevar.estimate(Z, axis=...)`` on the channels.
    names : list of str
        Channel names, in the order of ``estimates``.

    Returns
    -------
    plotly.graph_objects.Figure
    """
    std = np.asarray(estimates.std, dtype=float).ravel()
    ci = np.sqrt(np.asarray(estimates.ci95, dtype=float).reshape(-1, 2))
    fig = go.Figure(
        go.Scatter(
            x=list(names),
            y=std,
            mode="markers",
            marker={"size": 11, "color": COLORS["estimate"]},
            error_y={
                "type": "data",
                "symmetric": False,
                "array": ci[:, 1] - std,
                "arrayminus": std - ci[:, 0],
            },
            hovertemplate="%{x}: std %{y:.4g}<extra></extra>",
            name="noise std",
        )
    )
    # the shared layout: its title stays clear of Plotly's toolbar on a phone
    base_layout(fig, f"Noise of each channel (method {estimates.method}; bars: 95 %)", 360)
    fig.update_layout(
        yaxis=log_axis("noise std (each channel's unit)", np.concatenate([std, ci.ravel()])),
        xaxis_title="channel",
        showlegend=False,
    )
    return fig

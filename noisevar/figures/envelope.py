"""Figures of the SOMD envelopes, the h scan and the per-window variances.

* :func:`envelope_figure` - upper and lower envelopes and ``|V|`` per window (eq. [13]).
* :func:`scan_figure` - the ratio-vs-``h`` curve with the ``[1/20, 1/10]`` band (eq. [14]).
* :func:`window_variance_figure` - per-window variances and the final estimate
  with its 95 % CI.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from typing import Any

import numpy as np
import plotly.graph_objects as go
from numpy.typing import ArrayLike

from noisevar.estimators.results import VarianceEstimate
from noisevar.figures._common import (
    COLORS,
    MAX_FIGURE_MARKERS,
    MAX_POINTS,
    band,
    capped,
    downsample_note,
    layout,
    line_trace,
    log_axis,
    stacked_axes,
    step_xy,
    vline,
    x_axis,
    x_title,
)
from noisevar.figures.windows import _fmt
from noisevar.filters.envelope import HScan, WindowAmplitude


# -------------------------------------------------------------------- envelopes
def envelope_figure(
    raw: WindowAmplitude,
    detrended: ArrayLike,
    smooth: WindowAmplitude | None = None,
    sample_period: float | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = None,
    height: int = 580,
) -> go.Figure:
    """Envelopes of the window-detrended record and ``|V|`` per window (eq. [13]).

    Top: the raw record with each window's least-squares line removed, its
    upper envelope (through the local maxima) and lower envelope (through
    the local minima). Bottom: ``|V| = Σ(U - L) / 2m`` per window for the raw
    record and, when given, for the smooth output: their ratio is the
    quantity of eq. [14].

    Parameters
    ----------
    raw : WindowAmplitude
        :func:`noisevar.filters.envelope.noise_amplitude` of the raw record.
    detrended : array_like, shape (n_windows * m,)
        The window-detrended raw record
        (:func:`noisevar.filters.envelope.detrend_windows`, flattened).
    smooth : WindowAmplitude, optional
        The same for the smooth output.
    sample_period : float, optional
        Seconds per sample.
    max_points : int
        Largest number of points drawn per trace.
    title : str, optional
        Figure title.
    height : int
        Pixel height.

    Returns
    -------
    go.Figure
    """
    det = np.ravel(np.asarray(detrended, dtype=float))
    data = [
        line_trace(
            det,
            "detrended raw",
            sample_period,
            max_points,
            line={"color": COLORS["raw"], "width": 1},
        )[0]
    ]
    for arr, label, color in (
        (raw.upper, "upper envelope U", COLORS["track"]),
        (raw.lower, "lower envelope L", COLORS["smooth"]),
    ):
        data.append(
            line_trace(arr, label, sample_period, max_points, line={"color": color, "width": 1})[0]
        )
    m = raw.window
    edges = x_axis(np.arange(raw.amplitude.size + 1) * m, sample_period)
    x, y = step_xy(edges, raw.amplitude)
    data.append(
        go.Scatter(
            x=x,
            y=y,
            yaxis="y2",
            mode="lines",
            name="|V| raw",
            line={"color": COLORS["track"], "width": 1.2},
        )
    )
    if smooth is not None:
        k = min(smooth.amplitude.size, raw.amplitude.size)
        x, y = step_xy(edges[: k + 1], smooth.amplitude[:k])
        data.append(
            go.Scatter(
                x=x,
                y=y,
                yaxis="y2",
                mode="lines",
                name="|V| smooth output",
                line={"color": COLORS["smooth"], "width": 1.2},
            )
        )
    axes = stacked_axes(
        [0.6, 0.4],
        titles=(
            "window-detrended raw record and its envelopes",
            "|V| per window: mean envelope gap / 2",
        ),
    )
    axes["yaxis2"].update(log_axis("|V|"))
    axes["xaxis"]["title"] = {"text": x_title(sample_period)}
    anns = axes.pop("annotations")
    lay = layout(title, height, annotations=anns, **axes)
    _note_under_title(lay, downsample_note(det.size, max_points))
    return capped(go.Figure(data=data, layout=lay))


def _note_under_title(lay: dict, note: dict | None) -> None:
    """The downsampling note on a line of its own under the top panel's title (on the
    title's line, right-aligned, the two overlapped)."""
    if not note:
        return
    small = note["font"]
    first = lay["annotations"][0]
    first["align"] = "left"
    first["text"] += (
        f"<br><span style='font-size:{small['size']}px;color:{small['color']}'>"
        f"{note['text']}</span>"
    )
    lay["margin"] = {**lay["margin"], "t": lay["margin"]["t"] + 2 * small["size"]}


def scan_figure(
    scan: HScan,
    h_selected: Sequence[float] = (),
    h_track: float | None = None,
    title: str | None = None,
    height: int = 440,
) -> go.Figure:
    """The ratio ``|V1|/|V2|`` against ``h`` with the band of eq. [14] and the chosen ``h``.

    Parameters
    ----------
    scan : HScan
        :func:`noisevar.filters.envelope.scan_h` result.
    h_selected : sequence of float
        The smoothing ``h`` in use (drawn as vertical lines).
    h_track : float, optional
        The tracking ``h_T`` in use.
    title : str, optional
        Figure title.
    height : int
        Pixel height.

    Returns
    -------
    go.Figure
    """
    lo, hi = scan.band
    shapes = [band(lo, hi, axis="y")]
    anns: list[dict[str, Any]] = [
        {
            "text": "band [1/20, 1/10]",
            "xref": "paper",
            "x": 1.0,
            "yref": "y",
            "y": math.log10(lo),
            "xanchor": "right",
            "yanchor": "top",
            "showarrow": False,
            "font": {"size": 11, "color": COLORS["smooth"]},
        }
    ]
    if math.isfinite(scan.h_min) and math.isfinite(scan.h_max):
        shapes.append(band(scan.h_min, scan.h_max, axis="x", color="rgba(0,158,115,0.12)"))
    data = [
        go.Scatter(
            x=scan.h,
            y=scan.ratio,
            mode="lines+markers",
            name="|V1| / |V2|",
            line={"color": COLORS["smooth"]},
            hovertemplate="h = %{x:.3g}<br>ratio = %{y:.3g}<extra></extra>",
        )
    ]
    j = int(np.argmin(np.abs(np.log(scan.h / scan.h_chosen))))
    data.append(
        go.Scatter(
            x=[scan.h_chosen],
            y=[scan.ratio[j]],
            mode="markers",
            marker={"size": 13, "color": COLORS["kept_line"], "symbol": "star"},
            name=f"chosen h = {scan.h_chosen:.3g}",
        )
    )
    for k, h in enumerate(h_selected):
        shp, ann = vline(h, COLORS["smooth"], text="h_S in use" if k == 0 else None)
        shapes.append(shp)
        if ann:
            ann["x"] = math.log10(h)
            anns.append(ann)
    if h_track is not None:
        shp, ann = vline(h_track, COLORS["track"], dash="dot", text="h_T")
        shapes.append(shp)
        assert ann is not None
        ann["x"] = math.log10(h_track)
        anns.append(ann)
    lay = layout(
        title,
        height,
        xaxis=log_axis("h = q / r"),
        yaxis=log_axis("noise amplitude ratio |V1| / |V2|"),
        shapes=shapes,
        annotations=anns,
    )
    return go.Figure(data=data, layout=lay)


def window_variance_figure(
    est: VarianceEstimate,
    sample_period: float | None = None,
    true_variance: float | None = None,
    title: str | None = None,
    height: int = 420,
) -> go.Figure:
    """Per-window variance estimates with the final estimate and its 95 % interval.

    Parameters
    ----------
    est : VarianceEstimate
        A SOMD estimate (per-window values in ``est.details``); for other
        methods only the final estimate is drawn.
    sample_period : float, optional
        Seconds per sample.
    true_variance : float, optional
        Known variance (generated signals).
    title : str, optional
        Figure title.
    height : int
        Pixel height.

    Returns
    -------
    go.Figure
    """
    shapes: list[dict[str, Any]] = []
    anns: list[dict[str, Any]] = []
    data: list[Any] = []
    lo, hi = est.ci95
    if math.isfinite(lo) and math.isfinite(hi):
        shapes.append(band(lo, hi, axis="y"))
    d = est.details
    if d is not None:
        m = int(est.params.get("window", 40))
        wv = d.window_variance
        idx = np.flatnonzero(np.isfinite(wv))
        centre = x_axis(idx * m + m / 2.0, sample_period)
        data.append(
            go.Scatter(
                x=centre,
                y=wv[idx],
                mode="markers",
                marker={"size": 5, "color": COLORS["kept_line"], "opacity": 0.7},
                name=f"window variance ({idx.size} kept windows)",
                hovertemplate="window centre %{x:.4g}<br>variance %{y:.4g}<extra></extra>",
            )
        )
    # the estimate and the truth are legend entries, not labels lost in the scatter
    span = x_axis([0, max(est.n_total - 1, 1)], sample_period)
    data.append(
        go.Scatter(
            x=span,
            y=[est.variance, est.variance],
            mode="lines",
            line={"color": COLORS["estimate"], "width": 2.5},
            name=f"estimate {_fmt(est.variance)} (95 % CI {_fmt(lo)} to {_fmt(hi)})",
        )
    )
    if true_variance is not None and math.isfinite(true_variance):
        data.append(
            go.Scatter(
                x=span,
                y=[true_variance, true_variance],
                mode="lines",
                line={"color": COLORS["truth"], "width": 1.5, "dash": "dash"},
                name=f"true variance {_fmt(true_variance)}",
            )
        )
    lay = layout(
        title,
        height,
        xaxis={"title": {"text": x_title(sample_period)}},
        yaxis={"title": {"text": "noise variance"}, "rangemode": "tozero"},
        shapes=shapes,
        annotations=anns,
    )
    return capped(go.Figure(data=data, layout=lay), max_points=MAX_FIGURE_MARKERS)

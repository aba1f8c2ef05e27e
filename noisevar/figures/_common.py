"""Plotly figure builders: they take noisevar results and return ``plotly.graph_objects.Figure``.

Usable from a notebook as well as from the dashboard (no Streamlit here).
Submodules: :mod:`noisevar.figures.estimator` (signal, tables; re-exports
``windows``: SOMD steps and window tests, ``envelope``: envelopes, h scan and
window variances, ``compare``: methods side by side and redundant sensors) and
the filter families (``kalman``, ``fusion``, ``robust``, ``carrier``,
``latency``). Line, band and axis shapes live in ``_shapes`` (re-exported).

This package module holds the shared tooling:

* :func:`line_trace` draws long records without sending every sample to the
  browser: above ``max_points`` samples the trace is reduced with the
  MinMax-LTTB algorithm of the ``tsdownsample`` package (a min-max
  pre-selection followed by largest-triangle-three-buckets; peaks and noise
  bands survive) and drawn as SVG (``Scatter``: at a few thousand points SVG
  lines draw several times faster than WebGL, above all without a GPU, where
  WebGL runs in software). Computation is always
  on every sample; only the drawing is reduced, and
  :func:`note_downsampled` says so on the figure.
* the abscissa helpers (:func:`x_axis`, :func:`x_title`...) live in the public
  :mod:`noisevar.figures.axes`, the browser budget (:func:`capped`) in
  :mod:`noisevar.figures.budget`, and the exports (HTML, PNG) in
  :mod:`noisevar.figures.export`; this module re-exports the first two for the figures.
* :func:`as_list` and :func:`check_run` are the one result/run check every
  figure module uses (the :class:`~noisevar.systems.base.RunResult` protocol).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import plotly.graph_objects as go
from numpy.typing import ArrayLike

from noisevar.figures._shapes import band, hline, stacked_axes, step_xy, vline
from noisevar.figures.axes import Timing, has_time, unit_name, x_axis, x_title
from noisevar.figures.budget import (
    MAX_FIGURE_MARKERS,
    MAX_FIGURE_POINTS,
    MAX_FIGURE_SHAPES,
    MAX_POINTS,
    capped,
    curve_indices,
    downsample_indices,
    figure_size,
    log_axis,
    traces_y,
)
from noisevar.format import wrap_words
from noisevar.kalman.result import FilterResult
from noisevar.systems.base import RunResult, as_list, check_run_index

#: Colours shared by the figures (colour-blind-safe Okabe-Ito order).
COLORS = {
    "raw": "#9aa5b1",
    "clean": "#222222",
    "smooth": "#0072B2",
    "track": "#D55E00",
    "kept": "rgba(0, 158, 115, 0.13)",
    "kept_line": "#009E73",
    "amp": "#E69F00",
    "angle": "#CC79A7",
    "both": "#D55E00",
    "transient": "#999999",
    "estimate": "#0072B2",
    "truth": "#222222",
    "band": "rgba(0, 114, 178, 0.15)",
    "stretch": "rgba(230, 159, 0, 0.18)",
}
#: A cycle of distinct colours for several series (methods, sensors, h values).
PALETTE = (
    "#0072B2",
    "#D55E00",
    "#009E73",
    "#CC79A7",
    "#E69F00",
    "#56B4E9",
    "#F0E442",
    "#000000",
    "#8C564B",
    "#7F7F7F",
    "#17BECF",
    "#BCBD22",
    "#1F77B4",
)


def check_run(result: RunResult | FilterResult, run: int) -> None:
    """Refuse a Monte Carlo run index that ``result`` does not hold.

    Parameters
    ----------
    result : RunResult or FilterResult
        A system result (:class:`~noisevar.systems.base.RunResult`) or a
        Kalman filter result (one run unless batched).
    run : int
        Requested run.

    Raises
    ------
    NoisevarError
        When ``run`` is outside ``0 .. runs - 1``.
    """
    if isinstance(result, RunResult):
        result.check_run(run)
        return
    check_run_index(run, int(result.x.shape[0]) if result.batched else 1)


def line_trace(
    y: ArrayLike,
    name: str,
    sample_period: Timing = None,
    max_points: int = MAX_POINTS,
    mode: str = "lines",
    **kwargs: Any,
) -> tuple[go.Scatter | go.Scatter, bool]:
    """A line trace of a long record, downsampled for drawing when needed.

    Parameters
    ----------
    y : array_like, shape (n,)
        Samples (computed on all of them elsewhere; only the drawing is reduced).
    name : str
        Legend name.
    sample_period : float, optional
        Seconds per sample (abscissa in seconds), else the sample index.
    max_points : int
        Largest number of points drawn.
    mode : str
        Plotly scatter mode.
    **kwargs
        Passed to the trace (``line``, ``opacity``, ``legendgroup``...).

    Returns
    -------
    trace : go.Scatter or go.Scatter
        A ``Scatter`` (SVG) trace.
    downsampled : bool
        Whether points were dropped for drawing.
    """
    y = np.asarray(y, dtype=float)
    idx = downsample_indices(y, max_points)
    reduced = idx.size < y.size
    x = x_axis(idx, sample_period)
    trace = go.Scatter(x=x, y=y[idx], name=name, mode=mode, **kwargs)
    return trace, reduced


def note_downsampled(fig: go.Figure, n_total: int, max_points: int = MAX_POINTS) -> go.Figure:
    """Say on the figure that long traces are drawn downsampled (and that computing is not).

    Parameters
    ----------
    fig : go.Figure
        Figure to annotate (modified in place and returned).
    n_total : int
        Samples in the record.
    max_points : int
        Points drawn per trace.

    Returns
    -------
    go.Figure
    """
    ann = downsample_note(n_total, max_points)
    if ann is not None:
        fig.add_annotation(**ann)
    return fig


#: Bottom margin under the plot: the x tick labels and a one-line axis title. The x axis
#: grows it for a longer title (``automargin``), and a legend reserves its own rows under
#: that (it is placed in the figure's pixels, ``yref="container"``, see :func:`layout`).
BOTTOM_PX = 60
#: Pixels at the top of a figure kept for Plotly's toolbar (mode bar): the title is drawn
#: under it, not beneath it (on a phone a title spans the figure's width).
MODEBAR_PX = 34
#: Pixels of a title's line, and of the line under it kept for the downsampling note.
TITLE_LINE_PX = 20
NOTE_LINE_PX = 22


def layout(title: str | None = None, height: int = 420, **extra: Any) -> dict[str, Any]:
    """Common layout as a plain dict (legend under the plot, compact margins).

    No template is set: building a figure with one costs ~20 ms in plotly,
    a large part of a redraw budget; the dashboard styles figures with its
    own theme, and exports use plotly's default template.

    The legend sits under the plot (horizontal), the title at the top left under
    Plotly's toolbar, broken into lines of at most
    :data:`~noisevar.format.LINE_CHARS` characters (so it fits a phone's width).

    Parameters
    ----------
    title : str, optional
        Figure title.
    height : int
        Pixel height (the plot area is about ``height - 140`` pixels, less the
        legend's rows).
    **extra
        More layout keys (merged on top).

    Returns
    -------
    dict
    """
    text = wrap_words(title) if title else ""
    lines = text.count("<br>") + 1 if text else 0
    # Plotly centres a title of several lines on its anchor: each line after the first
    # lifts it by half a line, so it is padded down as much
    pad = MODEBAR_PX + TITLE_LINE_PX // 2 * max(lines - 1, 0)
    top = pad + TITLE_LINE_PX * lines + NOTE_LINE_PX
    out: dict[str, Any] = {
        "height": height,
        # wide enough for most tick labels: a margin plotly must widen costs a second draw
        "margin": {"l": 80, "r": 20, "t": top, "b": BOTTOM_PX},
        # below the plot (on top it collides with the title and the mode bar), at the
        # figure's bottom edge in pixels: Plotly then reserves the legend's height, however
        # many rows its entries wrap to, under the x axis's own room (its automargin). A
        # legend placed in plot fractions rose onto the axis title once its rows had
        # shrunk the plot (four two-line entries on a phone).
        "legend": {
            "orientation": "h",
            "yref": "container",
            "yanchor": "bottom",
            "y": 0.0,
            "x": 0.0,
        },
        "hovermode": "closest",
    }
    if title:
        # under the toolbar, broken at word boundaries (Plotly does not wrap a title)
        out["title"] = {
            "text": text,
            "x": 0.0,
            "xanchor": "left",
            "yref": "container",
            "y": 1.0,
            "yanchor": "top",
            "pad": {"t": pad},
            "font": {"size": 15},
        }
    out.update(extra)
    out["xaxis"] = {"automargin": True, **out.get("xaxis", {})}
    return out


def base_layout(fig: go.Figure, title: str | None = None, height: int = 420) -> go.Figure:
    """Apply :func:`layout` to an existing figure (in place) and return it.

    Parameters
    ----------
    fig : plotly.graph_objects.Figure
        The figure to style.
    title : str, optional
        Figure title.
    height : int
        Height in pixels.

    Returns
    -------
    plotly.graph_objects.Figure
        ``fig`` itself.
    """
    fig.update_layout(**layout(title, height))
    fig.update_xaxes(automargin=True)  # every subplot's x axis makes room under it
    return fig


def downsample_note(n_total: int, max_points: int = MAX_POINTS) -> dict[str, Any] | None:
    """The annotation dict of :func:`note_downsampled`.

    Parameters
    ----------
    n_total : int
        Samples in the record.
    max_points : int
        Points drawn per trace.

    Returns
    -------
    dict or None
        For ``layout.annotations``; None when nothing is dropped.
    """
    if n_total <= max_points:
        return None
    return {
        # short enough for one line on a phone (the method, MinMax-LTTB, is in the docs)
        "text": f"drawn downsampled: {max_points:,} of {n_total:,} samples; computed on all",
        "xref": "paper",
        "yref": "paper",
        "x": 1.0,
        "y": 1.0,
        "yanchor": "bottom",
        "xanchor": "right",
        "align": "right",
        "showarrow": False,
        "font": {"size": 11, "color": "#666"},
    }


__all__ = [
    "COLORS",
    "MAX_POINTS",
    "PALETTE",
    "as_list",
    "band",
    "check_run",
    "base_layout",
    "Timing",
    "capped",
    "curve_indices",
    "has_time",
    "figure_size",
    "log_axis",
    "traces_y",
    "MAX_FIGURE_MARKERS",
    "MAX_FIGURE_POINTS",
    "MAX_FIGURE_SHAPES",
    "downsample_indices",
    "downsample_note",
    "hline",
    "layout",
    "stacked_axes",
    "vline",
    "line_trace",
    "note_downsampled",
    "step_xy",
    "unit_name",
    "x_axis",
    "x_title",
]

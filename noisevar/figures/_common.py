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
* :func:`x_axis` gives the abscissa (seconds or sample index) of chosen
  sample indices; :func:`range_to_slice` turns a box selection back into a
  sample slice.
* :func:`to_html` / :func:`to_png` export a figure (PNG through ``kaleido``).
* :func:`as_list` and :func:`check_run` are the one result/run check every
  figure module uses (the :class:`~noisevar.systems.base.RunResult` protocol).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import plotly.graph_objects as go
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.figures._budget import (
    MAX_FIGURE_MARKERS,
    MAX_FIGURE_POINTS,
    MAX_FIGURE_SHAPES,
    MAX_POINTS,
    capped,
    downsample_indices,
    figure_size,
    log_axis,
)
from noisevar.figures._shapes import band, hline, stacked_axes, step_xy, vline
from noisevar.kalman.result import FilterResult
from noisevar.systems.base import RunResult, as_list, check_run_index

#: Seconds per sample (float), the samples' own times (array, seconds) or None (sample index).
Timing = float | NDArray | None


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


def x_axis(idx: ArrayLike, sample_period: Timing = None, t0: float = 0.0) -> NDArray:
    """Abscissa of sample indices: seconds when a sample period is known, else the index.

    ``sample_period`` may also be the record's own time stamps (an array of
    seconds, one per sample): records with gaps are then drawn against real time.

    Parameters
    ----------
    idx : array_like of int
        Sample indices.
    sample_period : float, optional
        Seconds per sample.
    t0 : float
        Time of sample 0.

    Returns
    -------
    ndarray of float
    """
    idx = np.asarray(idx, dtype=float)
    if isinstance(sample_period, np.ndarray):  # the samples' own times: gaps stay gaps
        return np.interp(idx, np.arange(sample_period.size), sample_period)
    return t0 + idx * sample_period if sample_period else idx


def unit_name(units: str | None, name: str) -> str:
    """An axis or legend title with its units: ``"signal (m)"``, or ``name`` without units.

    Parameters
    ----------
    units : str or None
        Units of the quantity (empty for none).
    name : str
        The quantity.

    Returns
    -------
    str
    """
    return f"{name} ({units})" if units else name


def has_time(sample_period: Timing) -> bool:
    """Whether ``sample_period`` (a period or the samples' times) gives seconds."""
    return isinstance(sample_period, np.ndarray) or bool(sample_period)


def x_title(sample_period: Timing) -> str:
    """Axis title matching :func:`x_axis`.

    Parameters
    ----------
    sample_period : float or None
        Seconds per sample; ``None`` or 0 for a sample-index axis.

    Returns
    -------
    str
        ``"time (s)"`` or ``"sample"``.
    """
    return "time (s)" if has_time(sample_period) else "sample"


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


def range_to_slice(
    x0: float, x1: float, n: int, sample_period: Timing = None, t0: float = 0.0
) -> slice:
    """Sample slice covered by an abscissa range (a box selection on a figure).

    Parameters
    ----------
    x0, x1 : float
        Range on the abscissa of :func:`x_axis` (either order).
    n : int
        Samples in the record.
    sample_period : float, optional
        Seconds per sample, as used for the figure.
    t0 : float
        Time of sample 0.

    Returns
    -------
    slice
        ``slice(start, stop)`` clipped to ``[0, n]``.
    """
    lo, hi = sorted((float(x0), float(x1)))
    if isinstance(sample_period, np.ndarray):  # the samples' own times
        start = int(np.searchsorted(sample_period, lo, side="left"))
        stop = int(np.searchsorted(sample_period, hi, side="right"))
        return slice(min(start, n), max(min(start, n), min(stop, n)))
    if sample_period:
        lo, hi = (lo - t0) / sample_period, (hi - t0) / sample_period
    start = int(np.clip(np.ceil(lo), 0, n))
    stop = int(np.clip(np.floor(hi) + 1, 0, n))
    return slice(start, max(start, stop))


def layout(title: str | None = None, height: int = 420, **extra: Any) -> dict[str, Any]:
    """Common layout as a plain dict (legend on top, compact margins).

    No template is set: building a figure with one costs ~20 ms in plotly,
    a large part of a redraw budget; the dashboard styles figures with its
    own theme, and exports use plotly's default template.

    The legend sits under the plot (horizontal), the title at the top left.

    Parameters
    ----------
    title : str, optional
        Figure title.
    height : int
        Pixel height (the plot area is about ``height - 170`` pixels).
    **extra
        More layout keys (merged on top).

    Returns
    -------
    dict
    """
    out: dict[str, Any] = {
        "height": height,
        # wide enough for most tick labels: a margin plotly must widen costs a second draw
        "margin": {"l": 80, "r": 20, "t": 56 if title else 36, "b": 110},
        # below the plot: a legend on top collides with the title and the mode bar
        "legend": {"orientation": "h", "yanchor": "top", "y": -0.2, "x": 0.0},
        "hovermode": "closest",
    }
    if title:
        out["title"] = {"text": title, "x": 0.0, "xanchor": "left"}
    out.update(extra)
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
        "text": (
            f"drawn downsampled: {max_points:,} of {n_total:,} samples per trace "
            "(MinMax-LTTB); computed on all samples"
        ),
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


def _styled(fig: go.Figure) -> go.Figure:
    """``fig``, or a copy with plotly's template when it has none (a dashboard's figure)."""
    if fig.layout.template.to_plotly_json():
        return fig
    return go.Figure(fig).update_layout(template="plotly")


def to_html(fig: go.Figure, self_contained: bool = True) -> str:
    """A figure as a standalone interactive HTML page.

    Parameters
    ----------
    fig : go.Figure
        The figure.
    self_contained : bool
        Embed plotly.js (works offline, ~4 MB) instead of loading it from a CDN.

    Returns
    -------
    str
    """
    return _styled(fig).to_html(include_plotlyjs=True if self_contained else "cdn", full_html=True)


def to_png(fig: go.Figure, width: int = 1200, height: int | None = None, scale: float = 2) -> bytes:
    """A figure as PNG bytes (through ``kaleido``, which drives a headless Chromium).

    Parameters
    ----------
    fig : go.Figure
        The figure.
    width, height : int
        Pixel size (height defaults to the figure's).
    scale : float
        Resolution multiplier.

    Returns
    -------
    bytes

    Raises
    ------
    NoisevarError
        When kaleido or a Chromium browser is not available.
    """
    try:
        return _styled(fig).to_image(
            format="png", width=width, height=height or fig.layout.height or 500, scale=scale
        )
    except Exception as exc:  # noqa: BLE001 - kaleido raises many types when no browser is found
        raise NoisevarError(
            f"PNG export needs kaleido and a Chromium browser ({type(exc).__name__}: {exc}); "
            "export HTML instead"
        ) from None


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
    "has_time",
    "figure_size",
    "log_axis",
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
    "range_to_slice",
    "step_xy",
    "to_html",
    "to_png",
    "unit_name",
    "x_axis",
    "x_title",
]

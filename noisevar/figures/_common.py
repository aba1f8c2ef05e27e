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
from noisevar.figures._shapes import band, hline, stacked_axes, step_xy, vline
from noisevar.kalman.result import FilterResult
from noisevar.systems.base import RunResult, as_list, check_run_index

#: Seconds per sample (float), the samples' own times (array, seconds) or None (sample index).
Timing = float | NDArray | None

#: Default number of points drawn per trace of a long record.
MAX_POINTS = 4000
#: Most points (summed over traces) one figure sends to the browser; see :func:`capped`.
MAX_FIGURE_POINTS = 10_000
#: Most points of a figure of markers (SVG draws each marker as an element); see :func:`capped`.
MAX_FIGURE_MARKERS = 2_500
#: Most layout shapes one figure sends to the browser; see :func:`capped`.
MAX_FIGURE_SHAPES = 2_000
#: Per-point trace attributes thinned together with ``x`` and ``y``.
_PER_POINT = ("customdata", "text", "hovertext")

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
        When ``run`` is outside ``0 .. n_runs - 1``.
    """
    if isinstance(result, RunResult):
        result.check_run(run)
        return
    check_run_index(run, int(result.x.shape[0]) if result.batched else 1)


def downsample_indices(y: ArrayLike, max_points: int = MAX_POINTS) -> NDArray:
    """Indices of at most ``max_points`` samples that keep the look of ``y``.

    MinMax-LTTB (``tsdownsample``) when the record is longer than
    ``max_points``; every index otherwise. Non-finite samples fall back to
    a plain min-max reduction over the finite ones.

    Parameters
    ----------
    y : array_like, shape (n,)
        Samples.
    max_points : int
        Number of points to keep (at least 10).

    Returns
    -------
    ndarray of int
        Sorted indices into ``y``.
    """
    y = np.asarray(y, dtype=float)
    n = y.size
    max_points = max(int(max_points), 10)
    if n <= max_points:
        return np.arange(n)
    finite = np.isfinite(y)
    if not finite.all():
        idx = np.flatnonzero(finite)
        if idx.size <= max_points:
            return idx
        sub = downsample_indices(y[idx], max_points)
        return idx[sub]
    try:
        from tsdownsample import MinMaxLTTBDownsampler

        idx = MinMaxLTTBDownsampler().downsample(np.ascontiguousarray(y), n_out=max_points)
        return np.asarray(idx, dtype=np.int64)
    except ImportError:  # pragma: no cover - tsdownsample is in the app extra
        n_bins = max_points // 2
        edges = np.linspace(0, n, n_bins + 1).astype(int)
        out = []
        for a, b in zip(edges[:-1], edges[1:], strict=True):
            seg = y[a:b]
            out.extend(sorted({a + int(np.argmin(seg)), a + int(np.argmax(seg))}))
        return np.asarray(out, dtype=np.int64)


def _n_points(trace: Any) -> int:
    x, y = getattr(trace, "x", None), getattr(trace, "y", None)
    arr = x if x is not None else y
    return 0 if arr is None else len(arr)


def figure_size(fig: go.Figure) -> tuple[int, int]:
    """Points (summed over the traces) and layout shapes a figure sends to the browser.

    Parameters
    ----------
    fig : go.Figure
        A figure.

    Returns
    -------
    points, shapes : int
    """
    return sum(_n_points(tr) for tr in fig.data), len(fig.layout.shapes or ())


def _thin_trace(trace: Any, budget: int) -> None:
    """Reduce one trace to at most ``budget`` points in place (extremes kept, in ``x`` order)."""
    x = np.asarray(trace.x, dtype=float) if trace.x is not None else None
    y = np.asarray(trace.y, dtype=float) if trace.y is not None else None
    key = y if y is not None else x
    order = np.arange(key.size)
    if x is not None and y is not None and np.any(np.diff(x) < 0):
        order = np.argsort(x, kind="stable")  # a scatter: thin along x, keep y's extremes
    idx = order[downsample_indices(key[order], budget)]
    upd: dict[str, Any] = {}
    if x is not None:
        upd["x"] = x[idx]
    if y is not None:
        upd["y"] = y[idx]
    for attr in _PER_POINT:
        val = getattr(trace, attr, None)
        if val is not None and not isinstance(val, str) and len(val) == key.size:
            upd[attr] = np.asarray(val)[idx]
    marker = getattr(trace, "marker", None)
    for attr in ("color", "size"):
        val = getattr(marker, attr, None) if marker is not None else None
        if val is not None and not isinstance(val, (str, int, float)) and len(val) == key.size:
            upd[f"marker.{attr}"] = np.asarray(val)[idx]
    trace.update({k: v for k, v in upd.items() if "." not in k})
    for k, v in upd.items():
        if "." in k:
            trace.marker[k.split(".")[1]] = v


def capped(
    fig: go.Figure, max_points: int = MAX_FIGURE_POINTS, max_shapes: int = MAX_FIGURE_SHAPES
) -> go.Figure:
    """Hold a figure to the browser budget: at most ``max_points`` points and ``max_shapes`` shapes.

    The one place the budget is enforced. Builders already draw long records
    reduced (:func:`line_trace`, merged window runs); this guard thins what is
    left, trace by trace in proportion to its length (extremes kept,
    :func:`downsample_indices`), and drops shapes past ``max_shapes`` with a
    note. Filled polygons (``fill="toself"``) are kept whole and their points
    come off the other traces' budget.

    Parameters
    ----------
    fig : go.Figure
        The figure (modified in place and returned).
    max_points, max_shapes : int
        The budget.

    Returns
    -------
    go.Figure
    """
    points, n_shapes = figure_size(fig)
    if points > max_points:
        fixed = [tr for tr in fig.data if getattr(tr, "fill", None) == "toself"]
        free = [tr for tr in fig.data if tr not in fixed and _n_points(tr) > 0]
        room = max(max_points - sum(_n_points(tr) for tr in fixed), 10 * len(free))
        total = sum(_n_points(tr) for tr in free)
        for tr in sorted(free, key=_n_points):  # short traces first: they are kept whole
            n_i = _n_points(tr)
            # budget_i = room_left * n_i / (points left)
            budget = max(int(room * n_i / total), min(n_i, 50), 10)
            if n_i > budget:
                _thin_trace(tr, budget)
            room -= min(n_i, budget)
            total -= n_i
    if n_shapes > max_shapes:
        fig.layout.shapes = fig.layout.shapes[:max_shapes]
        fig.add_annotation(
            text=f"{n_shapes - max_shapes:,} of {n_shapes:,} shapes not drawn",
            xref="paper",
            yref="paper",
            x=0.0,
            y=1.0,
            yanchor="bottom",
            xanchor="left",
            showarrow=False,
            font={"size": 11, "color": "#666"},
        )
    return fig


def log_axis(title: str, **extra: Any) -> dict[str, Any]:
    """A logarithmic axis with a label on every decade (``10⁻³, 10⁻², ...``) and minor ticks.

    Plotly's default labels the 2 and 5 of short log ranges, which reads as
    ``2, 100, 5, 2, 10``; here only decades carry labels.

    Parameters
    ----------
    title : str
        Axis title (with units).
    **extra
        More axis keys.

    Returns
    -------
    dict
    """
    out: dict[str, Any] = {
        "type": "log",
        "title": {"text": title},
        "dtick": 1,
        "exponentformat": "power",
        "minor": {"ticks": "outside", "dtick": "D1", "showgrid": True},
    }
    out.update(extra)
    return out


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
        "margin": {"l": 60, "r": 20, "t": 56 if title else 36, "b": 110},
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
        "showarrow": False,
        "font": {"size": 11, "color": "#666"},
    }


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
    return fig.to_html(include_plotlyjs=True if self_contained else "cdn", full_html=True)


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
        return fig.to_image(
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

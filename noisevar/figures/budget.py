"""The browser budget of a figure: the one place it is enforced (:func:`capped`).

No figure sends more than :data:`MAX_FIGURE_POINTS` points or
:data:`MAX_FIGURE_SHAPES` layout shapes to the browser; figures of markers
(each an SVG element) stay under :data:`MAX_FIGURE_MARKERS`. Long records are
reduced with MinMax-LTTB (:func:`downsample_indices`), which keeps peaks and
the noise band.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import plotly.graph_objects as go
from numpy.typing import ArrayLike, NDArray

#: Most points (summed over traces) one figure sends to the browser; see :func:`capped`.
MAX_FIGURE_POINTS = 10_000
#: Most points of a figure of markers (SVG draws each marker as an element); see :func:`capped`.
MAX_FIGURE_MARKERS = 800
#: Most layout shapes one figure sends to the browser; see :func:`capped`.
MAX_FIGURE_SHAPES = 2_000
#: Per-point trace attributes thinned together with ``x`` and ``y``.
_PER_POINT = ("customdata", "text", "hovertext")
#: Default number of points drawn per trace of a long record.
MAX_POINTS = 4000


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


def curve_indices(x: ArrayLike, y: ArrayLike, max_points: int = MAX_POINTS) -> NDArray:
    """Indices of at most ``max_points`` samples that keep the shape of a parametric curve.

    A curve drawn in its own order (a track, a phase portrait) is thinned along
    that order, never re-sorted: MinMax-LTTB of each coordinate against the
    sample index, half the budget each, and the union of the two index sets, so
    both coordinates keep their turns and extremes.

    Parameters
    ----------
    x, y : array_like, shape (n,)
        The curve's coordinates, in drawing order.
    max_points : int
        Number of points to keep at most (at least 10).

    Returns
    -------
    ndarray of int
        Sorted indices (the curve's own order).
    """
    x = np.asarray(x, dtype=float)
    y = np.asarray(y, dtype=float)
    max_points = max(int(max_points), 10)
    if x.size <= max_points:
        return np.arange(x.size)
    half = max_points // 2
    return np.union1d(downsample_indices(x, half), downsample_indices(y, max_points - half))


def _is_line(trace: Any) -> bool:
    """Whether a trace is drawn joined in its own order (lines), not as loose markers."""
    mode = getattr(trace, "mode", None)
    return mode is None or "lines" in str(mode)


#: Below this many decades of data, a log axis labels 1-2-5 values instead of decades only
#: (one decade or less would otherwise carry a single label).
SHORT_LOG_SPAN = 1.5


def log_axis(title: str, values: Any = None, **extra: Any) -> dict[str, Any]:
    """A logarithmic axis with a label on every decade (``10⁻³, 10⁻², ...``) and minor ticks.

    Plotly's default labels the 2 and 5 of short log ranges, which reads as
    ``2, 100, 5, 2, 10``; here only decades carry labels, unless the data (``values``)
    span less than :data:`SHORT_LOG_SPAN` decades: then the 1-2-5 values inside the data's
    range are labelled in full (``0.02, 0.05, 0.1``), so that the axis has more than one
    label.

    Parameters
    ----------
    title : str
        Axis title (with units).
    values : array_like, optional
        The values drawn on the axis (positive ones count).
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
    ticks = _short_log_ticks(values)
    if ticks:
        out.pop("dtick")
        out.update(tickmode="array", tickvals=ticks, ticktext=[f"{t:g}" for t in ticks])
        out.update(_holding(ticks, values))
    out.update(extra)
    return out


def traces_y(traces: Any) -> NDArray:
    """The y values drawn by ``traces`` (a figure's ``data`` or a list), for :func:`log_axis`.

    Parameters
    ----------
    traces : sequence of plotly traces

    Returns
    -------
    ndarray
        Every trace's y values, concatenated (empty when none).
    """
    ys = [np.asarray(t.y, dtype=float).ravel() for t in traces if getattr(t, "y", None) is not None]
    return np.concatenate(ys) if ys else np.empty(0)


def _positive(values: Any) -> NDArray:
    """The finite positive values (those a log axis draws), flattened."""
    v = np.asarray(values, dtype=float).ravel()
    return v[np.isfinite(v) & (v > 0)]


def _holding(ticks: list[float], values: Any) -> dict[str, Any]:
    """A range holding the labels around the data when some lie outside it (one value, or
    values between two 1-2-5 labels: Plotly's own range showed none of them)."""
    v = _positive(values)
    if min(ticks) >= v.min() and max(ticks) <= v.max():
        return {}
    pad = 0.05  # decades beyond the outer labels
    return {"range": [math.log10(min(ticks)) - pad, math.log10(max(ticks)) + pad]}


def _short_log_ticks(values: Any) -> list[float]:
    """1-2-5 values inside the positive values' range when it spans few decades, else []."""
    if values is None:
        return []
    v = _positive(values)
    if v.size == 0:
        return []
    lo, hi = float(v.min()), float(v.max())
    if math.log10(hi / lo) >= SHORT_LOG_SPAN:
        return []
    ticks = [
        m * 10.0**e
        for e in range(math.floor(math.log10(lo)) - 1, math.ceil(math.log10(hi)) + 1)
        for m in (1, 2, 5)
    ]
    inside = [float(f"{t:.12g}") for t in ticks if lo / 1.2 <= t <= hi * 1.2]
    if len(inside) >= 2:
        return inside
    below = [t for t in ticks if t < lo][-1:]
    above = [t for t in ticks if t > hi][:1]
    return sorted({float(f"{t:.12g}") for t in below + inside + above})


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
    """Reduce one trace to at most ``budget`` points in place (extremes kept).

    A line whose ``x`` goes backwards is a parametric curve (a track): it is
    thinned along its own order (:func:`curve_indices`). Loose markers whose
    ``x`` goes backwards are thinned along ``x`` (their order is not drawn).
    """
    x = np.asarray(trace.x, dtype=float) if trace.x is not None else None
    y = np.asarray(trace.y, dtype=float) if trace.y is not None else None
    key = y if y is not None else x
    backwards = x is not None and y is not None and bool(np.any(np.diff(x) < 0))
    if backwards and _is_line(trace):
        idx = curve_indices(x, y, budget)
    else:
        order = np.argsort(x, kind="stable") if backwards else np.arange(key.size)
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

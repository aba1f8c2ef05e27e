"""Layout shapes shared by the figures: lines, bands, stacked axes and step curves."""

from __future__ import annotations

from collections.abc import Sequence
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray


def hline(
    y: float, color: str = "#444", dash: str = "dash", text: str | None = None, yref: str = "y"
) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """A horizontal line across the plot as ``(shape, annotation)`` layout dicts.

    Parameters
    ----------
    y : float
        Height of the line in data units.
    color, dash : str
        Line colour and dash style.
    text : str, optional
        Label drawn at the left end of the line.
    yref : str
        The y axis the line refers to (``"y"``, ``"y2"``, ...).

    Returns
    -------
    shape : dict
        For ``layout.shapes``.
    annotation : dict or None
        For ``layout.annotations`` (None without ``text``).

    Notes
    -----
    Cheaper than ``fig.add_hline``.
    """
    shape = {
        "type": "line",
        "xref": "paper",
        "x0": 0,
        "x1": 1,
        "yref": yref,
        "y0": y,
        "y1": y,
        "line": {"color": color, "dash": dash, "width": 1.5},
    }
    ann = None
    if text:
        ann = {
            "xref": "paper",
            "x": 0.0,
            "yref": yref,
            "y": y,
            "text": text,
            "showarrow": False,
            "xanchor": "left",
            "yanchor": "bottom",
            "font": {"size": 11, "color": color},
        }
    return shape, ann


def vline(
    x: float, color: str = "#444", dash: str = "dash", text: str | None = None, xref: str = "x"
) -> tuple[dict[str, Any], dict[str, Any] | None]:
    """A vertical line across the plot as ``(shape, annotation)`` layout dicts.

    Parameters
    ----------
    x : float
        Position of the line in data units.
    color, dash : str
        Line colour and dash style.
    text : str, optional
        Label drawn at the top of the line.
    xref : str
        The x axis the line refers to (``"x"``, ``"x2"``, ...).

    Returns
    -------
    shape : dict
        For ``layout.shapes``.
    annotation : dict or None
        For ``layout.annotations`` (None without ``text``).
    """
    shape = {
        "type": "line",
        "yref": "paper",
        "y0": 0,
        "y1": 1,
        "xref": xref,
        "x0": x,
        "x1": x,
        "line": {"color": color, "dash": dash, "width": 1.5},
    }
    ann = None
    if text:
        ann = {
            "yref": "paper",
            "y": 1.0,
            "xref": xref,
            "x": x,
            "text": text,
            "showarrow": False,
            "xanchor": "left",
            "yanchor": "top",
            "font": {"size": 11, "color": color},
        }
    return shape, ann


def band(
    lo: float,
    hi: float,
    axis: str = "y",
    color: str = "rgba(0,114,178,0.15)",
    ref: str | None = None,
) -> dict[str, Any]:
    """A shaded band between ``lo`` and ``hi`` on one axis, spanning the other.

    Parameters
    ----------
    lo, hi : float
        Ends of the band in data units.
    axis : {"y", "x"}
        The axis ``lo`` and ``hi`` are on.
    color : str
        Fill colour.
    ref : str, optional
        Axis reference (default ``axis`` itself).

    Returns
    -------
    dict
        A rectangle for ``layout.shapes``, drawn below the traces.
    """
    if axis == "y":
        return {
            "type": "rect",
            "xref": "paper",
            "x0": 0,
            "x1": 1,
            "yref": ref or "y",
            "y0": lo,
            "y1": hi,
            "fillcolor": color,
            "line": {"width": 0},
            "layer": "below",
        }
    return {
        "type": "rect",
        "yref": "paper",
        "y0": 0,
        "y1": 1,
        "xref": ref or "x",
        "x0": lo,
        "x1": hi,
        "fillcolor": color,
        "line": {"width": 0},
        "layer": "below",
    }


def stacked_axes(
    row_heights: Sequence[float], gap: float = 0.08, titles: Sequence[str] | None = None
) -> dict[str, Any]:
    """Layout keys for panels stacked vertically on one shared x axis.

    Traces of panel ``i`` (0 = top) use ``yaxis="y"`` for the top panel and
    ``"y2"``, ``"y3"``... below. Cheaper than ``make_subplots``.

    Parameters
    ----------
    row_heights : sequence of float
        Relative panel heights, top first.
    gap : float
        Vertical gap between panels (fraction of the plot height).
    titles : sequence of str, optional
        Panel titles.

    Returns
    -------
    dict
        ``xaxis``, ``yaxis``, ``yaxis2``... and ``annotations`` (the titles).
    """
    k = len(row_heights)
    total = float(sum(row_heights))
    usable = 1.0 - gap * (k - 1)
    top = 1.0
    out: dict[str, Any] = {}
    anns = []
    for i, h in enumerate(row_heights):
        frac = usable * h / total
        lo = max(0.0, top - frac)
        name = "yaxis" if i == 0 else f"yaxis{i + 1}"
        out[name] = {"domain": [lo, top], "anchor": "x"}
        if titles and i < len(titles) and titles[i]:
            anns.append(
                {
                    "text": titles[i],
                    "xref": "paper",
                    "yref": "paper",
                    "x": 0.0,
                    "y": top,
                    "xanchor": "left",
                    "yanchor": "bottom",
                    "showarrow": False,
                    "font": {"size": 12},
                }
            )
        top = lo - gap
    bottom = "y" if k == 1 else f"y{k}"
    out["xaxis"] = {"anchor": bottom}
    out["annotations"] = anns
    return out


def step_xy(edges: Sequence[float] | NDArray, values: ArrayLike) -> tuple[NDArray, NDArray]:
    """Piecewise-constant line through ``values`` on intervals ``edges[i]..edges[i+1]``.

    Parameters
    ----------
    edges : array_like, shape (k + 1,)
        Interval boundaries.
    values : array_like, shape (k,)
        Value on each interval.

    Returns
    -------
    x, y : ndarray, shape (2 k,)
    """
    e = np.asarray(edges, dtype=float)
    v = np.asarray(values, dtype=float)
    x = np.column_stack([e[:-1], e[1:]]).ravel()
    y = np.repeat(v, 2)
    return x, y


def runs_of(mask: ArrayLike) -> tuple[NDArray, NDArray]:
    """Start and stop (exclusive) of each run of True in a boolean mask.

    Parameters
    ----------
    mask : array_like of bool, shape (n,)

    Returns
    -------
    starts, stops : ndarray of int
    """
    m = np.concatenate([[False], np.asarray(mask, dtype=bool), [False]])
    d = np.diff(m.astype(np.int8))
    return np.flatnonzero(d == 1), np.flatnonzero(d == -1)


def merge_runs(starts: ArrayLike, stops: ArrayLike, max_runs: int) -> tuple[NDArray, NDArray, int]:
    """Merge neighbouring runs across their narrowest gaps until at most ``max_runs`` remain.

    Parameters
    ----------
    starts, stops : array_like of int
        Sorted, non-overlapping runs ``[start, stop)``.
    max_runs : int
        Most runs to keep (at least 1).

    Returns
    -------
    starts, stops : ndarray of int
        The merged runs.
    widest_gap : int
        The widest gap that was closed (0 when nothing was merged).

    Notes
    -----
    Gaps no wider than the ``(k - max_runs)``-th narrowest are closed at once,
    so ties may leave fewer than ``max_runs`` runs.
    """
    a = np.asarray(starts, dtype=np.int64)
    b = np.asarray(stops, dtype=np.int64)
    max_runs = max(int(max_runs), 1)
    if a.size <= max_runs:
        return a, b, 0
    gaps = a[1:] - b[:-1]
    thr = int(np.sort(gaps)[a.size - max_runs - 1])
    open_gap = gaps > thr
    keep_start = np.concatenate([[True], open_gap])
    keep_stop = np.concatenate([open_gap, [True]])
    return a[keep_start], b[keep_stop], thr

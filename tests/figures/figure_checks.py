"""What the figure tests read off a figure: trace names, axis titles, trace lengths."""

from __future__ import annotations

import plotly.graph_objects as go


def trace_names(fig: go.Figure) -> list[str | None]:
    """Names of the figure's traces, in drawing order."""
    return [t.name for t in fig.data]


def axis_titles(fig: go.Figure) -> dict[str, str | None]:
    """Title text of every x/y axis of the layout, by axis name."""
    lay = fig.layout
    keys = [k for k in lay.to_plotly_json() if k.startswith(("xaxis", "yaxis"))]
    return {k: getattr(lay, k).title.text for k in keys}


def longest_trace(fig: go.Figure) -> int:
    """Points of the longest trace (``x`` or ``y``)."""
    sizes = [
        len(v)
        for t in fig.data
        for v in (getattr(t, "x", None), getattr(t, "y", None))
        if v is not None
    ]
    return max(sizes, default=0)


def trace_length(fig: go.Figure, name: str) -> int:
    """Points of the first trace called ``name``."""
    trace = next(t for t in fig.data if t.name == name)
    return len(trace.x)


def log_axes_labelled(fig: go.Figure) -> list[str]:
    """Log axes of the figure labelled as ``figures.budget.log_axis`` labels them.

    Returns the names of the log axes that are not: each must label its decades as powers
    (``dtick`` 1) or carry at least two 1-2-5 labels, never Plotly's default ``2, 5, 10``.
    """
    lay = fig.layout
    keys = [k for k in lay.to_plotly_json() if k.startswith(("xaxis", "yaxis"))]
    logs = [k for k in keys if getattr(lay, k).type == "log"]
    assert logs, "the figure has no log axis"
    return [
        k
        for k in logs
        if getattr(lay, k).exponentformat != "power"
        or not (getattr(lay, k).dtick == 1 or len(getattr(lay, k).tickvals or ()) >= 2)
    ]

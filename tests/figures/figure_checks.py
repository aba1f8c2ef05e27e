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

"""Exporting a figure: a standalone interactive HTML page, or PNG bytes (``kaleido``).

A figure drawn without a template (the dashboard draws its own colours on the page)
gets plotly's default template in the export, so that it reads on its own.
"""

from __future__ import annotations

import plotly.graph_objects as go

from noisevar.errors import NoisevarError


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

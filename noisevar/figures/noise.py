"""Figures of the Noise panel (docs/algorithms.md §E1-§E3): they take a ``NoisePanelData``.

* :func:`residual_histogram` — standardised residuals with a unit normal and the fitted
  Student-t.
* :func:`qq_plot` — sorted residuals against normal quantiles, with the fitted t's curve.
* :func:`acf_plot` — the residual's autocorrelation, its white-noise null and 95 % band.
* :func:`level_profile_plot` — the noise level per block with its interval, the quiet
  blocks marked and the quiet level.
"""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go
from numpy.typing import NDArray

from noisevar.diagnostics.panel import NoisePanelData
from noisevar.figures._common import COLORS, layout
from noisevar.figures.budget import log_axis
from noisevar.format import pvalue

#: Colour of the fitted Student-t.
T_COLOR = "#D55E00"
#: Colour of the quiet blocks.
QUIET_COLOR = "#009E73"


def residual_histogram(
    data: NoisePanelData,
    log_y: bool = False,
    title: str | None = "Residual distribution",
    height: int = 380,
) -> go.Figure:
    """Histogram (density) of every standardised residual, normal and fitted t overlaid.

    Parameters
    ----------
    data : NoisePanelData
    log_y : bool
        Logarithmic density axis (shows the tails).
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    centres = 0.5 * (data.bin_edges[:-1] + data.bin_edges[1:])
    fig = go.Figure(
        [
            go.Bar(
                x=centres,
                y=data.density,
                width=float(np.diff(data.bin_edges)[0]),
                name=f"residuals ({data.n_residuals:,})",
                marker={"color": COLORS["raw"]},
            ),
            go.Scatter(
                x=data.pdf_x,
                y=data.normal_pdf,
                name="normal",
                mode="lines",
                line={"color": COLORS["estimate"]},
            ),
            go.Scatter(
                x=data.pdf_x,
                y=data.t_pdf,
                name=f"Student-t ({_dof(data.t_dof)} dof)",
                mode="lines",
                line={"color": T_COLOR, "dash": "dash"},
            ),
        ]
    )
    extra = f"; {data.outside} beyond the axis" if data.outside else ""
    fig.update_layout(
        **layout(title, height, bargap=0),
        xaxis_title=f"residual / its standard deviation{extra}",
        yaxis_title="density",
    )
    if log_y:  # down to a tenth of the rarest bin, not to the normal's far tail
        low = float(np.min(data.density[data.density > 0], initial=1e-3)) / 10.0
        fig.update_layout(
            yaxis=log_axis("density", range=[np.log10(low), np.log10(1.5 * _top(data))])
        )
    return fig


def _top(data: NoisePanelData) -> float:
    return float(max(np.max(data.density), np.max(data.normal_pdf), np.max(data.t_pdf)))


def _dof(dof: float) -> str:
    return f"{dof:.1f}" if dof < 100 else "> 100"


def qq_plot(
    data: NoisePanelData, title: str | None = "QQ plot against the normal", height: int = 380
) -> go.Figure:
    """Sorted residuals against normal quantiles; a straight line for Gaussian noise.

    Parameters
    ----------
    data : NoisePanelData
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    q = data.qq_normal
    ends = [float(q[0]), float(q[-1])]
    fig = go.Figure(
        [
            go.Scatter(
                x=q,
                y=data.qq_sample,
                name="residuals",
                mode="markers",
                marker={"color": COLORS["raw"], "size": 4},
            ),
            go.Scatter(
                x=ends, y=ends, name="normal", mode="lines", line={"color": COLORS["estimate"]}
            ),
            go.Scatter(
                x=q,
                y=data.qq_t,
                name=f"Student-t ({_dof(data.t_dof)} dof)",
                mode="lines",
                line={"color": T_COLOR, "dash": "dash"},
            ),
        ]
    )
    fig.update_layout(
        **layout(title, height),
        xaxis_title="normal quantile",
        yaxis_title="residual quantile",
    )
    return fig


def acf_plot(
    data: NoisePanelData, title: str | None = "Autocorrelation of the residual", height: int = 380
) -> go.Figure:
    """The residual's autocorrelation at lags ``1..K`` against white noise's, with its band.

    Parameters
    ----------
    data : NoisePanelData
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
        The band is the null's 95 % interval per lag; the test itself weighs all lags.
    """
    lags = data.lags
    lo, hi = data.acf_expected - data.acf_band, data.acf_expected + data.acf_band
    verdict = "white" if data.white else "not white"
    fig = go.Figure(
        [
            go.Scatter(
                x=np.r_[lags, lags[::-1]],
                y=np.r_[hi, lo[::-1]],
                fill="toself",
                fillcolor=COLORS["band"],
                line={"width": 0},
                name="95 % band for white noise",
                hoverinfo="skip",
            ),
            go.Scatter(
                x=lags,
                y=data.acf_expected,
                name="white noise (the smoother's own)",
                mode="lines",
                line={"color": COLORS["estimate"], "dash": "dash"},
            ),
            go.Scatter(
                x=lags,
                y=data.acf,
                name=f"residual ({verdict}, {pvalue(data.p_value)})",
                mode="markers+lines",
                line={"color": COLORS["clean"]},
            ),
        ]
    )
    fig.update_layout(**layout(title, height), xaxis_title="lag", yaxis_title="autocorrelation")
    return fig


def _drawn_levels(data: NoisePanelData) -> NDArray:
    """Every level the profile draws: the blocks, their intervals' ends and the quiet level
    (an axis over less than a decade labels its 1-2-5 values: ``figures.budget.log_axis``)."""
    quiet = [] if data.quiet_variance is None else [data.quiet_variance]
    return np.r_[data.variance, data.lo, data.hi, quiet]


def level_profile_plot(
    data: NoisePanelData, title: str | None = "Noise level along the record", height: int = 400
) -> go.Figure:
    """Block levels with 95 % intervals, quiet blocks marked, the quiet level, and the
    stretches that moved too fast to measure shaded.

    The blocks are read through the diagnostics' fixed-span residual, the quiet level
    through R's (docs/algorithms.md §E1 *The quiet level*): where a smooth signal leaks
    through the former, the line lies below the blocks.

    Parameters
    ----------
    data : NoisePanelData
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
        Logarithmic level axis (motion can be orders of magnitude above the noise).
    """
    traces = []
    for mask, name, color in (
        (data.quiet, "quiet blocks", QUIET_COLOR),
        (~data.quiet, "other blocks", COLORS["raw"]),
    ):
        if not mask.any():
            continue
        v = data.variance[mask]
        traces.append(
            go.Scatter(
                x=data.block_x[mask],
                y=v,
                name=name,
                mode="markers",
                marker={"color": color, "size": 6},
                error_x={"type": "data", "array": data.block_half[mask], "width": 0},
                error_y={
                    "type": "data",
                    "symmetric": False,
                    "array": data.hi[mask] - v,
                    "arrayminus": v - data.lo[mask],
                    "width": 0,
                },
            )
        )
    x0 = float(data.block_x[0] - data.block_half[0])
    x1 = float(data.block_x[-1] + data.block_half[-1])
    if data.quiet_variance is not None:  # none: the record has no quiet level on R's residual
        traces.append(
            go.Scatter(
                x=[x0, x1],
                y=[data.quiet_variance] * 2,
                name=f"quiet level {data.quiet_variance:.4g} (on R's residual)",
                mode="lines",
                line={"color": QUIET_COLOR, "dash": "dash"},
            )
        )
    fig = go.Figure(traces)
    for lo, hi in data.unmeasured_x:  # left out around level jumps: no level to draw
        fig.add_vrect(
            x0=lo, x1=hi, fillcolor=COLORS["raw"], opacity=0.12, line_width=0,
            annotation_text="moving too fast to measure", annotation_position="top left",
        )  # fmt: skip
    fig.update_layout(
        **layout(title, height),
        xaxis_title=data.x_title,
        yaxis=log_axis("noise variance (signal units²)", _drawn_levels(data)),
    )
    return fig


__all__ = ["acf_plot", "level_profile_plot", "qq_plot", "residual_histogram"]

"""Noise-model figures: the Allan deviation with its interval, slope guides and fitted terms.

docs/algorithms.md §E4.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import plotly.graph_objects as go

from noisevar.figures._common import COLORS, PALETTE, layout, log_axis, traces_y
from noisevar.noise_model.allan import AllanResult
from noisevar.noise_model.datasheet import DatasheetTerms
from noisevar.noise_model.inertial import TERMS, InertialNoise
from noisevar.noise_model.temperature import TemperatureModel

#: Log-log slopes of the guides, with their labels (quantisation ... rate ramp).
SLOPES = ((-1.0, "τ⁻¹"), (-0.5, "τ⁻¹ᐟ²"), (0.0, "τ⁰"), (0.5, "τ¹ᐟ²"), (1.0, "τ¹"))
_LABELS = {"oadev": "overlapping ADEV", "mdev": "MDEV", "hdev": "overlapping HDEV"}


def _guides(res: AllanResult) -> list[go.Scatter]:
    """Dotted lines of slope -1, -1/2, 0, 1/2, 1 through the curve's middle point."""
    t = res.taus
    mid = t.size // 2
    t0, d0 = t[mid], res.deviation[mid]
    ends = np.array([t[0], t[-1]])
    out = []
    for i, (slope, label) in enumerate(SLOPES):
        y = d0 * (ends / t0) ** slope
        out.append(
            go.Scatter(
                x=ends,
                y=y,
                mode="lines+text",
                text=["", label],
                textposition="middle right",
                line={"color": COLORS["raw"], "dash": "dot", "width": 1},
                name="slope guides",
                legendgroup="guides",
                showlegend=i == 0,
                hoverinfo="skip",
            )
        )
    return out


def _data_traces(res: AllanResult, name: str, color: str) -> list[go.Scatter]:
    """The interval as a band and the deviation with its noise type in the hover."""
    lo, hi = res.interval
    kinds = [k or "not identified" for k in res.noise_type]
    return [
        go.Scatter(
            x=np.concatenate([res.taus, res.taus[::-1]]),
            y=np.concatenate([hi, lo[::-1]]),
            fill="toself",
            fillcolor=COLORS["band"],
            line={"width": 0},
            name=f"{name}: {res.ci:.0%} interval",
            hoverinfo="skip",
        ),
        go.Scatter(
            x=res.taus,
            y=res.deviation,
            customdata=np.column_stack([lo, hi, res.slope]),
            text=kinds,
            mode="lines+markers",
            marker={"color": color, "size": 6},
            line={"color": color},
            name=name,
            hovertemplate="τ %{x:.4g} s<br>σ %{y:.4g} [%{customdata[0]:.3g}, "
            "%{customdata[1]:.3g}]<br>slope %{customdata[2]:.2f}, %{text}<extra></extra>",
        ),
    ]


def _fit_traces(fit: InertialNoise) -> list[go.Scatter]:
    """Each non-zero term's deviation (dashed) and that of their sum."""
    t = np.geomspace(fit.allan.taus[0], fit.allan.taus[-1], 200)
    parts, total = fit.model(t)
    out = []
    for i, spec in enumerate(TERMS):
        term = fit.term(spec.name)
        if term.value <= 0:
            continue
        out.append(
            go.Scatter(
                x=t,
                y=parts[spec.name],
                mode="lines",
                line={"color": PALETTE[(i + 1) % len(PALETTE)], "dash": "dash"},
                name=f"{spec.symbol} = {term.value:.3g} {term.unit}",
            )
        )
    out.append(
        go.Scatter(
            x=t, y=total, mode="lines", line={"color": COLORS["truth"], "width": 2}, name="sum"
        )
    )
    return out


def allan_figure(
    result: AllanResult,
    fit: InertialNoise | None = None,
    simulated: AllanResult | None = None,
    title: str | None = "Allan deviation",
    height: int = 520,
    unit: str = "",
) -> go.Figure:
    """Allan deviation on log-log axes: interval band, slope guides, fitted terms and sum.

    Parameters
    ----------
    result : AllanResult
        The data's deviation.
    fit : InertialNoise, optional
        Fitted IEEE-952 terms to draw (each term and their sum).
    simulated : AllanResult, optional
        The deviation of noise simulated from the fit, overlaid.
    title : str, optional
    height : int
    unit : str
        Unit of the rate data, for the y axis title.

    Returns
    -------
    go.Figure
    """
    name = _LABELS.get(result.kind, result.kind)
    traces = _guides(result) + _data_traces(result, name, PALETTE[0])
    if fit is not None:
        traces += _fit_traces(fit)
    if simulated is not None:
        traces += _data_traces(simulated, "simulated from the fit", PALETTE[1])[1:]
    y_title = f"σ(τ) ({unit})" if unit else "σ(τ)"
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis=log_axis("τ (s)", result.taus),
            yaxis=log_axis(y_title, traces_y(traces)),  # guides and terms drawn too
        ),
    )


def datasheet_figure(
    result: AllanResult,
    sheet: DatasheetTerms,
    fit: InertialNoise | None = None,
    unit: str = "",
    height: int = 520,
) -> go.Figure:
    """The data's Allan deviation (and fit) with the datasheet's deviation overlaid.

    Parameters
    ----------
    result : AllanResult
    sheet : DatasheetTerms
        The datasheet's N and B in the data's unit.
    fit : InertialNoise, optional
    unit : str
    height : int

    Returns
    -------
    go.Figure
    """
    fig = allan_figure(
        result, fit=fit, title="Allan deviation against the datasheet", height=height, unit=unit
    )
    t = np.geomspace(result.taus[0], result.taus[-1], 200)
    fig.add_trace(
        go.Scatter(
            x=t,
            y=sheet.deviation(t),
            mode="lines",
            line={"color": "#000000", "dash": "longdash", "width": 2},
            name=f"datasheet: {sheet.quoted}",
        )
    )
    return fig


def bias_temperature_figure(model: TemperatureModel, height: int = 420) -> go.Figure:
    """Block means of the data (warm-up removed) against T, the fitted bias(T) and its band.

    Parameters
    ----------
    model : TemperatureModel
    height : int

    Returns
    -------
    go.Figure
    """
    t, value, lo, hi = model.curve
    u = model.unit
    traces = [
        go.Scattergl(
            x=model.temperature,
            y=model.settled(),
            mode="markers",
            marker={"color": COLORS["raw"], "size": 3},
            name=f"block means ({model.block:.3g} s)"
            + (", warm-up removed" if model.warmup else ""),
        ),
        go.Scatter(
            x=np.concatenate([t, t[::-1]]),
            y=np.concatenate([hi, lo[::-1]]),
            fill="toself",
            fillcolor=COLORS["band"],
            line={"width": 0},
            name=f"{model.ci:.0%} band",
            hoverinfo="skip",
        ),
        go.Scatter(
            x=t,
            y=value,
            mode="lines",
            line={"color": PALETTE[1], "width": 2},
            name=f"bias(T), order {model.order}",
        ),
    ]
    return go.Figure(
        traces,
        layout(
            "Bias against temperature",
            height,
            xaxis={"title": "T (°C)"},
            yaxis={"title": f"bias ({u})" if u else "bias"},
        ),
    )


def warmup_figure(model: TemperatureModel, height: int = 420) -> go.Figure:
    """The data minus bias(T) against time since power-on, and the fitted warm-up.

    Parameters
    ----------
    model : TemperatureModel
    height : int

    Returns
    -------
    go.Figure
    """
    rest = model.data - model.bias(model.temperature)
    traces = [
        go.Scattergl(
            x=model.time,
            y=rest,
            mode="markers",
            marker={"color": COLORS["raw"], "size": 3},
            name="data - bias(T)",
        ),
    ]
    w = model.warmup
    title = "Warm-up: none found"
    if w is not None:
        traces.append(
            go.Scatter(
                x=model.time,
                y=w.at(model.time),
                mode="lines",
                line={"color": PALETTE[1], "width": 2},
                name=f"A exp(-t/τ): A {w.amplitude:.3g}, τ {w.time_constant:.3g} s",
            )
        )
        title = f"Warm-up: τ {w.time_constant:.3g} s, within 1 % after {w.settled_after:.3g} s"
    u = model.unit
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis={"title": "time since power-on (s)"},
            yaxis={"title": f"bias - bias(T) ({u})" if u else "bias - bias(T)"},
        ),
    )


def composite_figure(model: Any, unit: str = "", height: int = 520) -> go.Figure:
    """Haar wavelet variance with its interval, each fitted component and their sum.

    Parameters
    ----------
    model : ImuModel
        A composite model of :mod:`noisevar.noise_model.gmwm` (its ``scales``, ``wv``,
        ``wv_interval``, ``components()``, ``model_wv()`` and ``model`` are drawn).
    unit : str
        Unit of the rate data (the wavelet variance is in unit²).
    height : int

    Returns
    -------
    go.Figure
    """
    s = np.asarray(model.scales, dtype=float)
    lo, hi = model.wv_interval
    traces = [
        go.Scatter(
            x=np.concatenate([s, s[::-1]]),
            y=np.concatenate([hi, lo[::-1]]),
            fill="toself",
            fillcolor=COLORS["band"],
            line={"width": 0},
            name=f"{model.ci:.0%} interval",
            hoverinfo="skip",
        ),
        go.Scatter(
            x=s,
            y=model.wv,
            mode="markers",
            marker={"color": PALETTE[0], "size": 7},
            name="Haar wavelet variance" + (" (robust)" if model.robust else ""),
        ),
    ]
    t = np.geomspace(s[0], s[-1], 200)
    for i, (name, wv) in enumerate(model.components(t).items()):
        traces.append(
            go.Scatter(
                x=t,
                y=wv,
                mode="lines",
                name=name,
                line={"color": PALETTE[(i + 1) % len(PALETTE)], "dash": "dash"},
            )
        )
    traces.append(
        go.Scatter(
            x=t,
            y=model.model_wv(t),
            mode="lines",
            name=f"sum: {model.model}",
            line={"color": COLORS["truth"], "width": 2},
        )
    )
    y_title = f"ν(τ) ({unit}²)" if unit else "ν(τ)"
    return go.Figure(
        traces,
        layout(
            "Composite model: wavelet variance",
            height,
            xaxis=log_axis("τ (s)", s),
            yaxis=log_axis(y_title, np.r_[model.wv, lo, hi]),
        ),
    )


__all__ = [
    "allan_figure",
    "bias_temperature_figure",
    "composite_figure",
    "datasheet_figure",
    "warmup_figure",
]

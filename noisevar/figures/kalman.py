"""Figures of Kalman filter runs (:class:`noisevar.kalman.FilterResult`).

* :func:`track_figure` — 2-D track: truth, measurements, each filter's estimate.
* :func:`states_figure` — every state over time, estimates against truth.
* :func:`r_estimates_figure` — each filter's ``R̂`` per channel over time on
  a log axis, against the true value.
* :func:`innovations_figure` — innovations with their ``±2√S`` band, and the
  windowed mean NIS inside its chi-square band.

Every builder takes one result or a list of results (one per strategy) and,
for batched results, the Monte Carlo run to draw (``run``). Long records
are drawn downsampled (computing is always on every sample).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import plotly.graph_objects as go
from numpy.typing import ArrayLike, NDArray
from plotly.subplots import make_subplots

from noisevar.errors import NoisevarError
from noisevar.figures._common import (
    COLORS,
    MAX_POINTS,
    PALETTE,
    as_list,
    check_run,
    curve_indices,
    downsample_indices,
    layout,
    line_trace,
    log_axis,
)
from noisevar.kalman import nis_band
from noisevar.kalman.result import FilterResult, wrap_angle

Results = FilterResult | Sequence[FilterResult]


def _pick(a: NDArray | None, result: FilterResult, run: int) -> NDArray | None:
    """The arrays of one run of a (possibly batched) result."""
    if a is None:
        return None
    if not result.batched:
        return a
    check_run(result, run)
    return a[run]


def _color(i: int) -> str:
    """The ``i``-th colour of the palette, cycling."""
    return PALETTE[i % len(PALETTE)]


def _panel_layout(title: str | None, height: int) -> dict:
    """Layout of a multi-panel figure: legend on the right, clear of the panel titles."""
    return layout(
        title,
        height,
        legend={"orientation": "v", "x": 1.01, "y": 1.0, "xanchor": "left", "yanchor": "top"},
        margin={"l": 60, "r": 150, "t": 70 if title else 40, "b": 45},
    )


#: Axis titles of the systems' position states (their names are the equations' symbols).
STATE_LABELS = {"pE": "east position pE (m)", "pN": "north position pN (m)"}


def state_label(name: str) -> str:
    """An axis title for a state: the quantity and its unit when known, else the name."""
    return STATE_LABELS.get(name, name)


def track_figure(
    results: Results,
    z: ArrayLike | None = None,
    run: int = 0,
    states: tuple[int, int] = (0, 1),
    channels: tuple[int, int] | None = (0, 1),
    max_points: int = MAX_POINTS,
    title: str | None = "Track",
    height: int = 480,
) -> go.Figure:
    """2-D track: truth, measured positions and each filter's estimate.

    Parameters
    ----------
    results : FilterResult or list of FilterResult
        Runs to draw (one per strategy).
    z : array_like, shape ([B,] N, m), optional
        Measurements (the ones the filter processed).
    run : int
        Monte Carlo run to draw for batched results.
    states : (int, int)
        State indices of the horizontal and vertical coordinates.
    channels : (int, int), optional
        Measurement channels of the same coordinates.
    max_points : int
        Points drawn per trace.
    title : str, optional
        Figure title.
    height : int
        Pixel height.

    Returns
    -------
    go.Figure
    """
    res = as_list(results, FilterResult)
    i, j = states
    data: list[go.Scatter] = []
    first = res[0]
    truth = _pick(first.truth, first, run)
    if z is not None and channels is not None:
        zz = np.asarray(z, dtype=float)
        zz = zz[run] if zz.ndim == 3 else zz
        idx = downsample_indices(zz[:, channels[0]], max_points)
        data.append(
            go.Scatter(
                x=zz[idx, channels[0]],
                y=zz[idx, channels[1]],
                mode="markers",
                name="measured",
                marker={"color": COLORS["raw"], "size": 3},
            )
        )
    if truth is not None:
        data.append(
            go.Scatter(
                x=truth[:, i],
                y=truth[:, j],
                mode="lines",
                name="truth",
                line={"color": COLORS["truth"], "width": 2},
            )
        )
    for c, r in enumerate(res):
        x = _pick(r.x, r, run)
        idx = curve_indices(x[:, i], x[:, j], max_points)
        data.append(
            go.Scatter(
                x=x[idx, i],
                y=x[idx, j],
                mode="lines",
                name=r.strategy,
                line={"color": _color(c), "width": 1.2},
            )
        )
    names = first.state_names or ("x", "y")
    lay = layout(
        title,
        height,
        xaxis={"title": {"text": state_label(names[i])}},
        yaxis={"title": {"text": state_label(names[j])}, "scaleanchor": "x", "scaleratio": 1},
    )
    return go.Figure(data=data, layout=lay)


def states_figure(  # long: one figure, built trace by trace in drawing order
    results: Results,
    run: int = 0,
    states: Sequence[int] | None = None,
    errors: bool = False,
    max_points: int = MAX_POINTS,
    title: str | None = "States",
    height_per_state: int = 200,
) -> go.Figure:
    """Every state over time: each filter's estimate against the truth (or the error).

    Parameters
    ----------
    results : FilterResult or list of FilterResult
        Runs to draw.
    run : int
        Monte Carlo run for batched results.
    states : sequence of int, optional
        Which states (default all).
    errors : bool
        Draw the estimation error ``x̂ - x`` with its ``±2σ`` band (needs
        truth) instead of the estimates.
    max_points : int
        Points drawn per trace.
    title : str, optional
        Figure title.
    height_per_state : int
        Pixel height of each panel.

    Returns
    -------
    go.Figure
    """
    res = as_list(results, FilterResult)
    first = res[0]
    n = _pick(first.x, first, run).shape[1]
    states = list(range(n)) if states is None else list(states)
    names = first.state_names or tuple(f"x{i}" for i in range(n))
    fig = make_subplots(
        rows=len(states), cols=1, shared_xaxes=True, subplot_titles=[names[s] for s in states]
    )
    dt = float(first.time[1] - first.time[0]) if first.n_steps > 1 else 1.0
    truth = _pick(first.truth, first, run)
    if errors and truth is None:
        raise NoisevarError("errors=True needs results made with truth")
    for row, s in enumerate(states, start=1):
        if truth is not None and not errors:
            tr, _ = line_trace(
                truth[:, s],
                "truth",
                dt,
                max_points,
                line={"color": COLORS["truth"], "width": 1.5},
                legendgroup="truth",
                showlegend=row == 1,
            )
            fig.add_trace(tr, row=row, col=1)
        for c, r in enumerate(res):
            x = _pick(r.x, r, run)[:, s]
            if errors:
                e = x - _pick(r.truth, r, run)[:, s]
                if s in r.angle_states:
                    e = wrap_angle(e)
                sd = np.sqrt(_pick(r.P, r, run)[:, s, s])
                band, _ = line_trace(
                    2 * sd,
                    f"{r.strategy} ±2σ",
                    dt,
                    max_points,
                    line={"color": _color(c), "width": 0.8, "dash": "dot"},
                    legendgroup=r.strategy,
                    showlegend=False,
                )
                fig.add_trace(band, row=row, col=1)
                band_lo, _ = line_trace(
                    -2 * sd,
                    f"{r.strategy} ±2σ",
                    dt,
                    max_points,
                    line={"color": _color(c), "width": 0.8, "dash": "dot"},
                    legendgroup=r.strategy,
                    showlegend=False,
                )
                fig.add_trace(band_lo, row=row, col=1)
                x = e
            tr, _ = line_trace(
                x,
                r.strategy,
                dt,
                max_points,
                line={"color": _color(c), "width": 1},
                legendgroup=r.strategy,
                showlegend=row == 1,
            )
            fig.add_trace(tr, row=row, col=1)
    fig.update_layout(**_panel_layout(title, max(300, height_per_state * len(states) + 80)))
    fig.update_xaxes(title_text="time (s)", row=len(states), col=1)
    return fig


def r_estimates_figure(
    results: Results,
    R_true: ArrayLike | None = None,
    run: int = 0,
    channels: Sequence[int] | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = "Measurement-noise variance R̂ per channel",
    height_per_channel: int = 220,
    reference_name: str = "true R",
) -> go.Figure:
    """Each filter's ``R̂_jj`` over time on a log axis, one panel per channel.

    Parameters
    ----------
    results : FilterResult or list of FilterResult
        Runs to draw (one per strategy).
    R_true : array_like, optional
        True ``R``: ``(m, m)``, ``(N, m, m)`` per step, or variances ``(m,)``
        / ``(N, m)``; drawn as a black line.
    run : int
        Monte Carlo run for batched results.
    channels : sequence of int, optional
        Which channels (default all).
    max_points : int
        Points drawn per trace.
    title : str, optional
        Figure title.
    height_per_channel : int
        Pixel height of each panel.
    reference_name : str
        Legend name of ``R_true`` (say what it is: the truth, or a quick estimate).

    Returns
    -------
    go.Figure
    """
    res = as_list(results, FilterResult)
    first = res[0]
    R0 = _pick(first.R, first, run)
    N, m = R0.shape[0], R0.shape[1]
    channels = list(range(m)) if channels is None else list(channels)
    names = first.measurement_names or tuple(f"z{j}" for j in range(m))
    true_diag = None
    if R_true is not None:
        rt = np.asarray(R_true, dtype=float)
        if rt.ndim >= 2 and rt.shape[-1] == rt.shape[-2] == m:
            rt = np.diagonal(rt, axis1=-2, axis2=-1)
        true_diag = np.broadcast_to(rt, (N, m)) if rt.ndim == 1 else rt[-N:]
    fig = make_subplots(
        rows=len(channels),
        cols=1,
        shared_xaxes=True,
        subplot_titles=[names[j] for j in channels],
    )
    dt = float(first.time[1] - first.time[0]) if first.n_steps > 1 else 1.0
    for row, j in enumerate(channels, start=1):
        drawn = [] if true_diag is None else [true_diag[:, j]]
        if true_diag is not None:
            tr, _ = line_trace(
                true_diag[:, j],
                reference_name,
                dt,
                max_points,
                line={"color": COLORS["truth"], "width": 2, "dash": "dash"},
                legendgroup="true",
                showlegend=row == 1,
            )
            fig.add_trace(tr, row=row, col=1)
        for c, r in enumerate(res):
            rj = _pick(r.R, r, run)[:, j, j]
            rj = np.where(rj > 0, rj, np.nan)  # log axis
            drawn.append(rj)
            tr, _ = line_trace(
                rj,
                r.strategy,
                dt,
                max_points,
                line={"color": _color(c), "width": 1.2},
                legendgroup=r.strategy,
                showlegend=row == 1,
            )
            fig.add_trace(tr, row=row, col=1)
        fig.update_yaxes(log_axis("R", np.concatenate(drawn)), row=row, col=1)
    fig.update_layout(**_panel_layout(title, max(300, height_per_channel * len(channels) + 80)))
    fig.update_xaxes(title_text="time (s)", row=len(channels), col=1)
    return fig


def innovations_figure(  # long: one figure, built trace by trace in drawing order
    result: FilterResult,
    run: int = 0,
    nis_window: int = 50,
    coverage: float = 0.95,
    max_points: int = MAX_POINTS,
    title: str | None = None,
    height_per_channel: int = 180,
) -> go.Figure:
    """Innovations with their ``±2√S`` band per channel, and the windowed mean NIS.

    The bottom panel shows the NIS averaged over ``nis_window`` steps with
    its two-sided chi-square band (``coverage``): a consistent filter stays
    inside it most of the time.

    Parameters
    ----------
    result : FilterResult
        One filter run.
    run : int
        Monte Carlo run for a batched result.
    nis_window : int
        Window of the NIS average (steps).
    coverage : float
        Probability inside the chi-square band.
    max_points : int
        Points drawn per trace.
    title : str, optional
        Figure title (default names the strategy).
    height_per_channel : int
        Pixel height of each panel.

    Returns
    -------
    go.Figure
    """
    if not isinstance(result, FilterResult):
        raise NoisevarError("give one FilterResult")
    d = _pick(result.innovation, result, run)
    S = _pick(result.innovation_cov, result, run)
    nis = _pick(result.nis, result, run)
    N, m = d.shape
    names = result.measurement_names or tuple(f"z{j}" for j in range(m))
    w = int(max(1, min(nis_window, N)))
    fig = make_subplots(
        rows=m + 1,
        cols=1,
        shared_xaxes=True,
        subplot_titles=[f"innovation {names[j]}" for j in range(m)] + [f"NIS, mean over {w} steps"],
    )
    dt = float(result.time[1] - result.time[0]) if result.n_steps > 1 else 1.0
    for j in range(m):
        sd2 = 2.0 * np.sqrt(np.abs(S[:, j, j]))
        tr, _ = line_trace(
            d[:, j],
            "innovation",
            dt,
            max_points,
            line={"color": COLORS["smooth"], "width": 1},
            legendgroup="d",
            showlegend=j == 0,
        )
        fig.add_trace(tr, row=j + 1, col=1)
        for sign in (1.0, -1.0):
            band, _ = line_trace(
                sign * sd2,
                "±2√S",
                dt,
                max_points,
                line={"color": COLORS["track"], "width": 1, "dash": "dot"},
                legendgroup="band",
                showlegend=j == 0 and sign > 0,
            )
            fig.add_trace(band, row=j + 1, col=1)
    finite = np.where(np.isfinite(nis), nis, np.nan)
    c = np.nancumsum(np.concatenate([[0.0], finite]))
    mean_nis = np.full(N, np.nan)
    mean_nis[w - 1 :] = (c[w:] - c[:-w]) / w
    lo, hi = nis_band(m, w, coverage)
    tr, _ = line_trace(
        mean_nis, "mean NIS", dt, max_points, line={"color": COLORS["smooth"], "width": 1.2}
    )
    fig.add_trace(tr, row=m + 1, col=1)
    t_end = float(result.time[-1])
    for y, label in ((lo, f"{coverage:.0%} band"), (hi, None), (float(m), "chi-square mean")):
        fig.add_trace(
            go.Scatter(
                x=[0.0, t_end],
                y=[y, y],
                mode="lines",
                name=label or "",
                showlegend=label is not None,
                line={
                    "color": COLORS["truth"] if label == "chi-square mean" else COLORS["track"],
                    "width": 1,
                    "dash": "dash",
                },
            ),
            row=m + 1,
            col=1,
        )
    div = result.diverged if not result.batched else bool(np.atleast_1d(result.diverged)[run])
    reason = result.divergence_reason if not result.batched else result.divergence_reason[run]
    text = title or f"Innovations of {result.strategy}" + (
        f" — diverged ({reason.split(':')[0]})" if div else ""
    )
    fig.update_layout(**_panel_layout(text, max(360, height_per_channel * (m + 1) + 80)))
    fig.update_xaxes(title_text="time (s)", row=m + 1, col=1)
    return fig

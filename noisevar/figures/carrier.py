"""Figures of carrier tracking (docs/algorithms.md §B1): they take ``CarrierResult`` objects.

* :func:`phase_error_figure` — phase-error traces of the EKF and the AEKF
  (paper Figs. 2 and 3), one run.
* :func:`doppler_figure` — true and estimated Doppler, one run.
* :func:`adaptation_figure` — the ``R`` and ``Q[0,0]`` each filter used.
* :func:`iq_figure` — the prompt correlator outputs in the I/Q plane.
* :func:`sweep_figure` — RMS phase error and loss-of-lock fraction against
  C/N0 (:class:`noisevar.systems.carrier.CarrierSweep`).
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import plotly.graph_objects as go
from plotly.subplots import make_subplots

from noisevar.figures._common import (
    COLORS,
    MAX_POINTS,
    PALETTE,
    as_list,
    check_run,
    layout,
    line_trace,
    log_axis,
    traces_y,
)
from noisevar.systems.carrier import CarrierResult, CarrierSweep

Results = CarrierResult | Sequence[CarrierResult]
LABELS = {
    "ekf": "EKF (fixed R, Q)",
    "aekf": "AEKF",  # a sweep does not say which Q rule; results do (see result_label)
    "aekf_scaled": "AEKF (R from residuals, scaled Q)",
    "ekf_matched": "EKF, matched R, Q (reference)",
    "aekf_r_only": "AEKF (R from residuals only)",
    "aekf_paper_q": "AEKF (R and the paper's Q from innovations)",
}


def _rule_label(method: str, q_rule: str, default: str) -> str:
    """Legend label of a filter: the AEKF named by its ``Q`` rule."""
    if method == "aekf":  # name the Q rule the filter ran with
        rule = {"paper": "aekf_paper_q", "scaled": "aekf_scaled", "none": "aekf_r_only"}
        return LABELS[rule.get(q_rule, "aekf")]
    return LABELS.get(default, default)


def result_label(r: CarrierResult) -> str:
    """Legend label of a result (a nominal-design EKF says so); tables use the same name."""
    if r.method == "ekf" and r.measurement_variance != 1.0:
        return "EKF, nominal design (fixed R, Q)"
    return _rule_label(r.method, r.q_rule, r.method)


def phase_error_figure(
    results: Results,
    run: int = 0,
    max_points: int = MAX_POINTS,
    title: str | None = "Carrier phase tracking error",
    height: int = 420,
) -> go.Figure:
    """Phase error (rad, whole cycles removed) of each filter over time, one run.

    Parameters
    ----------
    results : CarrierResult or list of CarrierResult
    run : int
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    res = as_list(results, CarrierResult)
    traces = []
    for i, r in enumerate(res):
        check_run(r, run)
        slip = " — slipped" if r.slipped[run] else ""
        trace, _ = line_trace(
            r.phase_error[run],
            f"{result_label(r)} (RMS {r.rms_phase_error:.3f} rad over runs){slip}",
            r.scenario.integration_s,
            max_points,
            line={"color": PALETTE[i % len(PALETTE)], "width": 1},
        )
        traces.append(trace)
    return go.Figure(
        traces,
        layout(
            title,
            height,
            xaxis={"title": "time (s)"},
            yaxis={"title": "phase error (rad)", "range": [-np.pi, np.pi]},
        ),
    )


def doppler_figure(
    results: Results,
    run: int = 0,
    max_points: int = MAX_POINTS,
    title: str | None = "Doppler: truth and estimates",
    height: int = 400,
) -> go.Figure:
    """True and estimated Doppler (Hz) of one run.

    Parameters
    ----------
    results : CarrierResult or list of CarrierResult
    run : int
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    res = as_list(results, CarrierResult)
    check_run(res[0], run)
    T = res[0].scenario.integration_s
    truth, _ = line_trace(
        res[0].true_doppler_hz[run],
        "true",
        T,
        max_points,
        line={"color": COLORS["truth"], "width": 2},
    )
    traces = [truth]
    for i, r in enumerate(res):
        est = r.estimate[run, :, 1] / (2 * np.pi)
        trace, _ = line_trace(
            est,
            result_label(r),
            T,
            max_points,
            line={"color": PALETTE[i % len(PALETTE)], "width": 1},
        )
        traces.append(trace)
    return go.Figure(
        traces, layout(title, height, xaxis={"title": "time (s)"}, yaxis={"title": "Doppler (Hz)"})
    )


def adaptation_figure(
    results: Results,
    run: int = 0,
    max_points: int = MAX_POINTS,
    title: str | None = "Noise covariances used: R (I channel) and Q[phase, phase]",
    height: int = 520,
) -> go.Figure:
    """``R[0,0]`` and ``Q[0,0]`` of each filter over time (log axes), one run.

    Parameters
    ----------
    results : CarrierResult or list of CarrierResult
    run : int
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    res = as_list(results, CarrierResult)
    fig = make_subplots(rows=2, cols=1, shared_xaxes=True, vertical_spacing=0.08)
    for i, r in enumerate(res):
        check_run(r, run)
        color = PALETTE[i % len(PALETTE)]
        T = r.scenario.integration_s
        tr, _ = line_trace(
            r.R_track[run, :, 0], f"{result_label(r)} R", T, max_points, line={"color": color}
        )
        tq, _ = line_trace(
            r.Q_phase_track[run],
            f"{result_label(r)} Q",
            T,
            max_points,
            line={"color": color, "dash": "dot"},
        )
        fig.add_trace(tr, row=1, col=1)
        fig.add_trace(tq, row=2, col=1)
    fig.update_layout(**layout(title, height))
    drawn_r, drawn_q = fig.data[0::2], fig.data[1::2]
    fig.update_yaxes(log_axis("R (I/Q noise)", traces_y(drawn_r)), row=1, col=1)
    fig.update_yaxes(log_axis("Q phase (rad²)", traces_y(drawn_q)), row=2, col=1)
    fig.update_xaxes(title_text="time (s)", row=2, col=1)
    return fig


def iq_figure(
    result: CarrierResult,
    run: int = 0,
    max_points: int = MAX_POINTS,
    title: str | None = "Prompt correlator outputs (after the NCO)",
    height: int = 460,
) -> go.Figure:
    """The I/Q pairs the filter received, one run.

    Parameters
    ----------
    result : CarrierResult
    run : int
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    check_run(result, run)
    iq = result.iq[run]
    step = max(1, iq.shape[0] // max_points)
    pts = iq[::step]
    amp = result.scenario.amplitude
    circle = np.linspace(0, 2 * np.pi, 181)
    return go.Figure(
        [
            go.Scatter(
                x=pts[:, 0],
                y=pts[:, 1],
                mode="markers",
                name="I, Q",
                marker={"size": 3, "color": PALETTE[0], "opacity": 0.5},
            ),
            go.Scatter(
                x=amp * np.cos(circle),
                y=amp * np.sin(circle),
                mode="lines",
                name=f"|A| = {amp:.2f}",
                line={"color": COLORS["truth"], "dash": "dash"},
            ),
        ],
        layout(
            title,
            height,
            xaxis={"title": "I"},
            yaxis={"title": "Q", "scaleanchor": "x"},
        ),
    )


def sweep_figure(
    sweep: CarrierSweep,
    title: str | None = "EKF vs AEKF over C/N0",
    height: int = 480,
) -> go.Figure:
    """RMS phase error (log) and loss-of-lock fraction against C/N0.

    Parameters
    ----------
    sweep : CarrierSweep
    title : str, optional
    height : int

    Returns
    -------
    go.Figure
    """
    fig = make_subplots(rows=2, cols=1, shared_xaxes=True, vertical_spacing=0.08)
    for i, method in enumerate(sweep.rms_phase_error_rad):
        color = PALETTE[i % len(PALETTE)]
        name = LABELS.get(method, method)
        if method == "aekf" and method in sweep.q_rules:  # say which Q rule it ran with
            kind, _, rule = sweep.q_rules[method].partition("/")
            name = _rule_label(kind, rule, method)
        fig.add_trace(
            go.Scatter(
                x=sweep.cn0_dbhz,
                y=sweep.rms_phase_error_rad[method],
                mode="lines+markers",
                name=name,
                line={"color": color},
                legendgroup=method,
            ),
            row=1,
            col=1,
        )
        fig.add_trace(
            go.Scatter(
                x=sweep.cn0_dbhz,
                y=sweep.loss_of_lock[method],
                mode="lines+markers",
                name=name,
                line={"color": color, "dash": "dot"},
                legendgroup=method,
                showlegend=False,
            ),
            row=2,
            col=1,
        )
    fig.update_layout(**layout(title, height))
    rms = traces_y(fig.data[0::2])
    fig.update_yaxes(log_axis("RMS phase error (rad)", rms), row=1, col=1)
    fig.update_yaxes(title_text="runs that slipped", range=[-0.05, 1.05], row=2, col=1)
    fig.update_xaxes(title_text="C/N0 (dB-Hz)", row=2, col=1)
    return fig


__all__ = [
    "adaptation_figure",
    "doppler_figure",
    "iq_figure",
    "phase_error_figure",
    "sweep_figure",
]

"""Figures of a tuned Kalman filter and of the noise-model comparison (docs/algorithms.md §E5-§E6).

* :func:`tuning_rows`, :func:`coloured_rows` — the comparison tables;
* :func:`tuned_run_figure` — the record and the tuned filter's position estimate;
* :func:`nis_figure` — the NIS of the tuned filter over the record, its moving mean
  and that mean's 95 % chi-square band;
* :func:`innovation_acf_figure` — the autocorrelation of the normalised
  innovations with the white-noise band ``±1.96/√n``;
* :func:`model_comparison_figure` — each coloured-noise model's BIC/AIC above the best.
"""

from __future__ import annotations

import numpy as np
import plotly.graph_objects as go
import scipy.signal

from noisevar.figures._common import (
    COLORS,
    MAX_POINTS,
    PALETTE,
    layout,
    line_trace,
    log_axis,
    note_downsampled,
    traces_y,
    x_title,
)
from noisevar.figures._shapes import band, hline
from noisevar.format import eng, eng_range
from noisevar.kalman.divergence import nis_band
from noisevar.noise_model.coloured import ColouredNoiseFit
from noisevar.noise_model.kalman_fit import KalmanTuning
from noisevar.noise_model.kalman_run import TunedRun
from noisevar.units import in_data_unit


def tuning_rows(tunings: dict[str, KalmanTuning], unit: str = "") -> list[dict[str, object]]:
    """One table row per fitted kinematic model: q, r, h with intervals, criteria, checks.

    Parameters
    ----------
    tunings : dict
        Model name -> :class:`~noisevar.noise_model.KalmanTuning`.
    unit : str
        The data's unit: q's unit is written in it (``m²/s^3``), as ``noisevar fit``
        writes it.

    Returns
    -------
    list of dict
    """
    best = min(tunings.values(), key=lambda t: t.bic).model if tunings else None
    rows = []
    for name, t in tunings.items():
        rows.append(
            {
                "model": name,
                # one formatter, four significant digits each (not r 0.3 beside q 1.234567891e-5)
                "q": eng(t.q),
                "q 95 %": eng_range(*t.q_interval),
                "q unit": in_data_unit(t.units.get("q", ""), unit),
                "r": eng(t.r),
                "r 95 %": eng_range(*t.r_interval),
                # r against the record's answer (auto's R): which model agrees with it
                "r / record's R": None if t.record is None else round(t.record.ratio, 3),
                "h": eng(t.h),
                "log-likelihood": t.loglik,
                "ΔBIC": t.bic - min(u.bic for u in tunings.values()),
                "NIS mean": t.nis_mean,
                "NIS in band": t.nis_consistent,
                "innovations white": t.innovations_white,
                "best (BIC)": name == best,
            }
        )
    return rows


def coloured_rows(fit: ColouredNoiseFit) -> list[dict[str, object]]:
    """One table row per fitted coloured-noise model (parameters per sample)."""
    best_bic = min(f.bic for f in fit.fits)
    best_aic = min(f.aic for f in fit.fits)
    return [
        {
            "model": f.name,
            "r (white)": f.r,
            "phi": f.phi,
            "q AR(1)": f.q_ar,
            "q random walk": f.q_rw,
            "log-likelihood": f.loglik,
            "ΔAIC": f.aic - best_aic,
            "ΔBIC": f.bic - best_bic,
            "chosen": f.name == fit.model,
        }
        for f in fit.fits
    ]


def tuned_run_figure(
    run: TunedRun,
    z: np.ndarray,
    dt: float | None = None,
    max_points: int = MAX_POINTS,
    title: str | None = "The record and the tuned filter",
    height: int = 380,
    y_title: str = "measured value",
) -> go.Figure:
    """The measured record and the filter's position estimate ``x(k|k)``.

    ``y_title`` names the quantity (the record's column and unit).

    Returns
    -------
    plotly.graph_objects.Figure
    """
    pad = np.full(int(run.index[0]), np.nan)
    raw, reduced = line_trace(z, "record", dt, max_points, line={"color": COLORS["raw"]})
    est, _ = line_trace(
        np.r_[pad, run.states[:, 0]],
        "filtered",
        dt,
        max_points,
        line={"color": COLORS["estimate"], "width": 2},
    )
    fig = go.Figure([raw, est])
    fig.update_layout(**layout(title, height, xaxis_title=x_title(dt), yaxis_title=y_title))
    return note_downsampled(fig, len(z), max_points) if reduced else fig


def nis_figure(
    run: TunedRun,
    dt: float | None = None,
    window: int = 100,
    max_points: int = MAX_POINTS,
    title: str | None = "NIS of the tuned filter",
    height: int = 380,
) -> go.Figure:
    """NIS per sample, its moving mean over ``window`` samples and that mean's 95 % band.

    Parameters
    ----------
    run : TunedRun
        From :func:`noisevar.noise_model.run_tuned`.
    dt : float, optional
        Sample period (abscissa in seconds), else the sample index.
    window : int
        Samples in the moving mean.
    max_points : int
    title : str, optional
    height : int

    Returns
    -------
    plotly.graph_objects.Figure
    """
    w = int(max(1, min(window, run.nis.size)))
    # moving mean of NIS over w samples (causal FIR)
    mean = scipy.signal.lfilter(np.full(w, 1.0 / w), [1.0], run.nis)[w - 1 :]
    pad = np.full(int(run.index[0]), np.nan)  # the diffuse start has no NIS
    raw, _ = line_trace(
        np.r_[pad, run.nis], "NIS", dt, max_points, line={"color": COLORS["raw"], "width": 1}
    )
    avg, _ = line_trace(
        np.r_[pad, np.full(w - 1, np.nan), mean],
        f"mean over {w}",
        dt,
        max_points,
        line={"color": COLORS["estimate"], "width": 2},
    )
    lo, hi = nis_band(1, w)
    line, note = hline(1.0, text="E[NIS] = 1")
    fig = go.Figure([raw, avg])
    fig.update_layout(
        **layout(title, height, xaxis_title=x_title(dt), yaxis=log_axis("NIS", traces_y(fig.data))),
        shapes=[band(lo, hi, color=COLORS["band"]), line],
        annotations=[note] if note else [],
    )
    return fig


def innovation_acf_figure(
    run: TunedRun,
    lags: int = 40,
    title: str | None = "Innovation autocorrelation",
    height: int = 340,
) -> go.Figure:
    """ACF of the normalised innovations, with the ``±1.96/√n`` band of white noise.

    Returns
    -------
    plotly.graph_objects.Figure
    """
    from statsmodels.tsa.stattools import acf

    nu = run.innovations / np.sqrt(run.s)
    lags = int(min(lags, nu.size - 1))
    rho = acf(nu, nlags=lags, fft=True)
    k = np.arange(1, lags + 1)
    half = 1.959963984540054 / np.sqrt(nu.size)
    fig = go.Figure(go.Bar(x=k, y=rho[1:], name="ACF", marker_color=COLORS["estimate"]))
    fig.update_layout(
        **layout(title, height, xaxis_title="lag (samples)", yaxis_title="autocorrelation"),
        shapes=[band(-half, half, color=COLORS["band"])],
    )
    return fig


def model_comparison_figure(
    fit: ColouredNoiseFit,
    title: str | None = "Noise models: information criterion above the best",
    height: int = 340,
) -> go.Figure:
    """Bars of ΔBIC and ΔAIC of every fitted model (0 = best; lower is better).

    Returns
    -------
    plotly.graph_objects.Figure
    """
    names = [f.name for f in fit.fits]
    traces = []
    for i, crit in enumerate(("bic", "aic")):
        vals = np.array([getattr(f, crit) for f in fit.fits])
        traces.append(
            go.Bar(x=names, y=vals - vals.min(), name=f"Δ{crit.upper()}", marker_color=PALETTE[i])
        )
    fig = go.Figure(traces)
    fig.update_layout(
        **layout(title, height, barmode="group", yaxis_title="above the best model"),
    )
    return fig

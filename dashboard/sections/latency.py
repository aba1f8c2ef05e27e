"""The Latency page's parts: the flight form and the delay results (docs/algorithms.md §C)."""

from __future__ import annotations

import json
from dataclasses import dataclass

import numpy as np
import streamlit as st

from dashboard import cache
from dashboard.state import initial
from dashboard.widgets import (
    figure_view,
    guarded,
    show_figure,
    show_table,
    table_and_figure_downloads,
)
from noisevar.figures.latency import cost_figure, delay_figure, records_figure
from noisevar.systems.latency import LatencyResult

VIEWS = ["Records", "Cost against shift", "Delay per segment"]
FIGURES = {
    "Records": records_figure,
    "Cost against shift": cost_figure,
    "Delay per segment": delay_figure,
}


@dataclass
class LatencySettings:
    """The page's choices; ``scenario_json`` holds the :class:`LatencyScenario` arguments."""

    scenario_json: str
    seed: int
    max_delay: float


def _slider(label: str, lo: float, hi: float, step: float, key: str, default: float) -> float:
    """A query-param-bound slider with its initial value."""
    return st.slider(
        label, lo, hi, step=step, key=key, bind="query-params", **initial(key, default)
    )


def settings_form() -> LatencySettings:
    """Duration, rate, delays, jitter, segment, GPS noise, seed and the searched range."""
    c1, c2, c3, c4 = st.columns(4)
    with c1:
        duration = _slider("Duration (s)", 100, 2000, 50, "la_dur", 550)
    rate = c2.select_slider(
        "Sample rate (Hz)",
        [1, 2, 5, 10, 20, 50],
        key="la_rate",
        bind="query-params",
        **initial("la_rate", 10),
    )
    with c3:
        unknown = _slider("Unknown delay (s)", 0.0, 1.5, 0.01, "la_unknown", 0.2)
    with c4:
        measurable = _slider("Measurable delay (s)", 0.0, 0.5, 0.01, "la_meas", 0.1)
    c1, c2, c3, c4 = st.columns(4)
    with c1:
        jitter = _slider("Measurable jitter (± s)", 0.0, 0.2, 0.01, "la_jitter", 0.05)
    with c2:
        segment = _slider("Segment (s)", 10, 120, 5, "la_seg", 30)
    with c3:
        gps_noise = _slider("GPS speed noise (m/s)", 0.0, 2.0, 0.05, "la_noise", 0.1)
    seed = c4.number_input(
        "Seed", 0, 2**31 - 1, key="la_seed", bind="query-params", **initial("la_seed", 0)
    )
    max_delay = _slider("Largest delay searched (± s)", 0.5, 5.0, 0.5, "la_max", 2.0)
    scenario = {
        "duration_s": float(duration),
        "rate_hz": float(rate),
        "unknown_delay_s": float(unknown),
        "measurable_delay_s": float(measurable),
        "measurable_jitter_s": float(jitter),
        "segment_s": float(segment),
        "gps_noise_std": float(gps_noise),
    }
    return LatencySettings(json.dumps(scenario, sort_keys=True), seed, max_delay)


def delay_results(s: LatencySettings) -> None:
    """The delay estimates: metrics, residual table, a figure and the downloads."""
    res = None
    with guarded():
        res = cache.latency_run(s.scenario_json, s.seed, s.max_delay)
    if res is None:
        return
    _metrics(res)
    rows = [
        {"compensation": "none", "residual delay RMS (s)": res.residual_none_s},
        {"compensation": "fixed (whole record)", "residual delay RMS (s)": res.residual_fixed_s},
        {"compensation": "per-segment coarse", "residual delay RMS (s)": res.residual_coarse_s},
        {"compensation": "filtered", "residual delay RMS (s)": res.residual_filtered_s},
    ]
    show_table(
        rows,
        hide_index=True,
        column_config={"residual delay RMS (s)": st.column_config.NumberColumn(format="%.4f")},
    )
    view = figure_view(VIEWS, "la_view", VIEWS[0])
    fig = None
    zoom = None
    if view == "Records" and st.toggle(
        "Zoom on the sharpest speed change (the delay is a fraction of a second)",
        value=True,
        key="la_zoom",
    ):
        zoom = _sharpest_change(res)
    with guarded():
        fig = records_figure(res, window_s=zoom) if zoom else FIGURES[view](res)
    if fig is not None:
        show_figure(fig, key="la_chart")
    table_and_figure_downloads(
        "Residual delays (CSV)",
        rows,
        "noisevar-latency.csv",
        "la_csv",
        fig,
        "noisevar-latency",
        "la_fig",
    )
    st.caption(
        "The Two sensors page uses the same least-squares delay to line two sensors up before "
        "differencing them."
    )


def _sharpest_change(res: LatencyResult, half_width_s: float = 4.0) -> tuple[float, float]:
    """A few seconds around the reference's steepest speed change."""
    rec = res.record
    k = int(np.argmax(np.abs(np.gradient(rec.reference))))
    t = float(rec.time[k])
    return max(t - half_width_s, float(rec.time[0])), t + half_width_s


def _metrics(res: LatencyResult) -> None:
    m = st.columns(4)
    m[0].metric("True mean delay", f"{res.true_delay_s * 1000:.1f} ms")
    m[1].metric(
        "Estimated (filtered)",
        f"{res.estimated_delay_s * 1000:.1f} ms",
        delta=f"{(res.estimated_delay_s - res.true_delay_s) * 1000:+.1f} ms",
        delta_color="off",
        delta_arrow="off",
    )
    m[2].metric(
        "Whole-record least squares",
        f"{res.coarse.delay_s * 1000:.1f} ms",
        help=f"± {res.coarse.std_s * 1000:.1f} ms (1σ)",
    )
    m[3].metric("Segments", f"{res.segment_time.size}")

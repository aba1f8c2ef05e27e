"""The Robust filter page's parts: the fly-over form and the filters' results (§B3)."""

from __future__ import annotations

from dataclasses import dataclass

import streamlit as st

from dashboard import cache
from dashboard.state import initial
from dashboard.widgets import (
    blank_missing,
    figure_view,
    guarded,
    show_figure,
    show_table,
    table_and_figure_downloads,
)
from noisevar.figures.robust import bearing_figure, error_figure, magvar_figure, track_figure
from noisevar.systems.robust import DEFAULT_KAPPA, RobustResult

VIEWS = ["Track", "Position error", "Magnetic variation", "Bearing error"]
FIGURES = {
    "Track": track_figure,
    "Position error": error_figure,
    "Magnetic variation": magvar_figure,
    "Bearing error": bearing_figure,
}


@dataclass
class RobustSettings:
    """The page's choices (the arguments of :func:`dashboard.cache.robust_run`)."""

    outliers: bool
    magvar: float
    burst_rate: float
    kappa: float
    iterations: int
    runs: int
    seed: int


def settings_form() -> RobustSettings:
    """Outliers, magnetic variation, burst rate, runs, Huber κ and iterations, seed."""
    c1, c2, c3, c4 = st.columns(4)
    outliers = c1.toggle(
        "Bearing outliers near the station",
        key="ro_outliers",
        bind="query-params",
        **initial("ro_outliers", True),
    )
    magvar = c2.slider(
        "Magnetic variation (°)",
        -20.0,
        20.0,
        step=0.5,
        key="ro_magvar",
        bind="query-params",
        **initial("ro_magvar", -5.0),
    )
    burst = c3.slider(
        "Burst rate near the station",
        0.0,
        0.3,
        step=0.01,
        key="ro_burst",
        bind="query-params",
        disabled=not outliers,
        **initial("ro_burst", 0.08),
    )
    runs = c4.slider(
        "Monte Carlo runs", 1, 50, key="ro_runs", bind="query-params", **initial("ro_runs", 10)
    )
    c1, c2, c3 = st.columns(3)
    kappa = c1.slider(
        "Huber κ",
        0.5,
        5.0,
        step=0.05,
        key="ro_kappa",
        bind="query-params",
        **initial("ro_kappa", DEFAULT_KAPPA),
    )
    iterations = c2.slider(
        "Huber iterations", 1, 20, key="ro_iter", bind="query-params", **initial("ro_iter", 10)
    )
    seed = c3.number_input(
        "Seed", 0, 2**31 - 1, key="ro_seed", bind="query-params", **initial("ro_seed", 0)
    )
    return RobustSettings(outliers, magvar, burst, kappa, iterations, runs, seed)


def robust_results(s: RobustSettings) -> None:
    """Run the three filters; metrics, table, a figure and the downloads."""
    res = None
    with guarded(), st.spinner("Filtering..."):
        res = cache.robust_run(
            s.outliers, s.magvar, s.burst_rate, s.kappa, s.iterations, s.runs, s.seed
        )
    if res is None:
        return
    _metrics(res, s.magvar)
    rows = [
        {
            "filter": name,
            "position RMSE (m)": res.rmse_position.get(name),
            "final magvar (deg, mean over runs)": (
                res.magvar_mean_deg
                if name == "huber"
                else res.magvar_mean_ekf_deg
                if name == "ekf"
                else None
            ),
        }
        for name in res.filters
    ]
    show_table(blank_missing(rows), hide_index=True)
    view = figure_view(VIEWS, "ro_view", VIEWS[0])
    fig = None
    with guarded():
        fig = FIGURES[view](res)
    if fig is not None:
        show_figure(fig, key="ro_chart")
    table_and_figure_downloads(
        "Results (CSV)", rows, "noisevar-robust.csv", "ro_csv", fig, "noisevar-robust", "ro_fig"
    )


def _metrics(res: RobustResult, magvar: float) -> None:
    m = st.columns(4)
    for col, name in zip(m[:3], ("ekf", "no-bias", "huber"), strict=True):
        if name in res.rmse_position:
            col.metric(f"Position RMSE, {name}", f"{res.rmse_position[name]:.4g} m")
    m[3].metric(
        "Magnetic variation (Huber)",
        f"{res.magvar_mean_deg:.3f}°",
        delta=f"true {magvar:g}°",
        delta_color="off",
        delta_arrow="off",
    )

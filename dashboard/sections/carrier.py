"""The Carrier tracking page's parts: the signal form, the filters' results, the C/N0 sweep."""

from __future__ import annotations

import json
from dataclasses import dataclass

import plotly.graph_objects as go
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
from noisevar.figures.carrier import (
    adaptation_figure,
    doppler_figure,
    iq_figure,
    phase_error_figure,
    result_label,
    sweep_figure,
)
from noisevar.systems.carrier import CarrierResult

VIEWS = ["Phase error", "Doppler", "Adaptation (R, Q)", "I/Q plane"]
#: The C/N0 points of the on-demand sweep (dB-Hz).
SWEEP_CN0 = (25.0, 30.0, 35.0, 40.0, 45.0)


@dataclass
class CarrierSettings:
    """The page's choices; ``scenario_json`` holds the :class:`CarrierScenario` arguments."""

    scenario_json: str
    runs: int
    seed: int
    window: int
    nominal_cn0: float


def settings_form() -> CarrierSettings:  # long: one widget call per scenario setting
    """C/N0, integration time, duration, Doppler rate, data bits, runs, window, seed, design."""
    c1, c2, c3, c4 = st.columns(4)
    cn0 = c1.slider(
        "C/N0 (dB-Hz)",
        15.0,
        50.0,
        step=0.5,
        key="ca_cn0",
        bind="query-params",
        **initial("ca_cn0", 30.0),
    )
    tint = c2.select_slider(
        "Integration time (ms)",
        [1, 2, 4, 5, 10, 20],
        key="ca_tint",
        bind="query-params",
        **initial("ca_tint", 10),
    )
    duration = c3.slider(
        "Duration (s)",
        2.0,
        30.0,
        step=1.0,
        key="ca_dur",
        bind="query-params",
        **initial("ca_dur", 10.0),
    )
    rate = c4.slider(
        "Peak Doppler rate (Hz/s)",
        0.0,
        100.0,
        step=5.0,
        key="ca_rate",
        bind="query-params",
        **initial("ca_rate", 25.0),
    )
    c1, c2, c3, c4, c5 = st.columns(5)
    bits = c1.toggle("Navigation data bits", key="ca_bits", bind="query-params")
    nominal_cn0 = c5.slider(
        "Fixed EKF designed for (dB-Hz)",
        25.0,
        50.0,
        step=1.0,
        key="ca_nominal",
        bind="query-params",
        help="A receiver's fixed-noise EKF is tuned for nominal conditions; the AEKF starts "
        "from the same design and adapts.",
        **initial("ca_nominal", 45.0),
    )
    runs = c2.slider(
        "Monte Carlo runs", 1, 50, key="ca_runs", bind="query-params", **initial("ca_runs", 10)
    )
    window = c3.slider(
        "AEKF window (periods)",
        10,
        200,
        step=5,
        key="ca_window",
        bind="query-params",
        **initial("ca_window", 50),
    )
    seed = c4.number_input(
        "Seed", 0, 2**31 - 1, key="ca_seed", bind="query-params", **initial("ca_seed", 0)
    )
    scenario = {
        "cn0_dbhz": float(cn0),
        "integration_s": int(tint) / 1000.0,
        "duration_s": float(duration),
        "doppler_rate_hz_s": float(rate),
        "data_bits": bool(bits),
    }
    return CarrierSettings(json.dumps(scenario, sort_keys=True), runs, seed, window, nominal_cn0)


def tracking_results(s: CarrierSettings) -> None:
    """Run the filters on the same signals; table, a figure and the downloads."""
    by_name = None
    with guarded(), st.spinner("Tracking..."):
        by_name = cache.carrier_runs(s.scenario_json, s.runs, s.seed, s.window, s.nominal_cn0)
    if by_name is None:
        return
    rows = [
        {
            "filter": result_label(r),
            "RMS phase error (rad)": r.rms_phase_error,
            "loss of lock (fraction of runs)": r.loss_of_lock,
        }
        for name, r in by_name.items()
    ]
    show_table(rows, hide_index=True, width="stretch")
    st.caption(
        "EKF: fixed noise designed for the C/N0 above. AEKF: adapts R from its residuals (its "
        "window starts full of the design R) with a stabilised Q from the same design. EKF, "
        "matched: knows the true noise (the bound). AEKF with the paper's Q: Q from the "
        "innovations as printed in the paper, which runs away (a finding we report)."
    )
    view = figure_view(VIEWS, "ca_view", VIEWS[0])
    fig = None
    with guarded():
        fig = _figure(view, by_name)
    if fig is not None:
        show_figure(fig, key="ca_chart")
    table_and_figure_downloads(
        "Results (CSV)", rows, "noisevar-carrier.csv", "ca_csv", fig, "noisevar-carrier", "ca_fig"
    )


def _figure(view: str, by_name: dict[str, CarrierResult]) -> go.Figure:
    results = list(by_name.values())
    if view == "Phase error":
        return phase_error_figure(results)
    if view == "Doppler":
        return doppler_figure(results)
    if view == "Adaptation (R, Q)":
        return adaptation_figure(results)
    which = st.radio(
        "Filter",
        list(by_name),
        key="ca_iq",
        horizontal=True,
        format_func=lambda k: result_label(by_name[k]),
    )
    return iq_figure(by_name[which])


def sweep_panel(s: CarrierSettings) -> None:
    """The C/N0 sweep, run on request with its own number of runs per point."""
    with st.expander("Sweep over C/N0 (on demand)"):
        c1, c2 = st.columns([1, 3], vertical_alignment="bottom")
        sweep_runs = c1.number_input(
            "Runs per point", 1, 200, key="ca_sweep_runs", **initial("ca_sweep_runs", 20)
        )
        span = f"{min(SWEEP_CN0):g} … {max(SWEEP_CN0):g}"
        if c2.button(f"Run the sweep {span} dB-Hz", key="ca_sweep_go"):
            st.session_state["ca_sweep"] = (
                s.scenario_json,
                int(sweep_runs),
                int(s.seed),
                s.nominal_cn0,
            )
        ask = st.session_state.get("ca_sweep")
        if ask:
            sweep = None
            with guarded(), st.spinner("Sweeping C/N0..."):
                sweep = cache.carrier_sweep(ask[0], SWEEP_CN0, ask[1], ask[2], ask[3])
            if sweep is not None:
                show_figure(sweep_figure(sweep), key="ca_sweep_chart")

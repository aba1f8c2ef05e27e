"""Carrier tracking page: fixed EKF vs adaptive EKF on a weak GNSS carrier (spec B1)."""

from __future__ import annotations

import json

import streamlit as st

import dashboard_common as dc
from noisevar.estimators.compare import rows_to_csv
from noisevar.figures.carrier import (
    adaptation_figure,
    doppler_figure,
    iq_figure,
    phase_error_figure,
    sweep_figure,
)

dc.setup_page("Carrier tracking", ":material/satellite_alt:")
st.title("Carrier tracking")
st.caption(
    "One GPS L1 C/A channel after acquisition: prompt I/Q correlator outputs each integration "
    "period, noise set by C/N0, a Doppler that changes with the receiver's manoeuvres. "
    "The EKF tracks [phase, Doppler, Doppler rate, amplitude] with fixed R and Q; the adaptive "
    "EKF estimates R from its residuals (eq. 22) and Q = K C_d Kᵀ (eq. 26)."
)
VIEWS = ["Phase error", "Doppler", "Adaptation (R, Q)", "I/Q plane"]

c1, c2, c3, c4 = st.columns(4)
cn0 = c1.slider(
    "C/N0 (dB-Hz)",
    15.0,
    50.0,
    step=0.5,
    key="ca_cn0",
    bind="query-params",
    **dc.initial("ca_cn0", 30.0),
)
tint = c2.select_slider(
    "Integration time (ms)",
    [1, 2, 4, 5, 10, 20],
    key="ca_tint",
    bind="query-params",
    **dc.initial("ca_tint", 10),
)
duration = c3.slider(
    "Duration (s)",
    2.0,
    30.0,
    step=1.0,
    key="ca_dur",
    bind="query-params",
    **dc.initial("ca_dur", 10.0),
)
rate = c4.slider(
    "Peak Doppler rate (Hz/s)",
    0.0,
    100.0,
    step=5.0,
    key="ca_rate",
    bind="query-params",
    **dc.initial("ca_rate", 25.0),
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
    **dc.initial("ca_nominal", 45.0),
)
runs = c2.slider(
    "Monte Carlo runs", 1, 50, key="ca_runs", bind="query-params", **dc.initial("ca_runs", 10)
)
window = c3.slider(
    "AEKF window (periods)",
    10,
    200,
    step=5,
    key="ca_window",
    bind="query-params",
    **dc.initial("ca_window", 50),
)
seed = c4.number_input(
    "Seed", 0, 2**31 - 1, key="ca_seed", bind="query-params", **dc.initial("ca_seed", 0)
)
settings = json.dumps(
    {
        "cn0_dbhz": float(cn0),
        "integration_s": int(tint) / 1000.0,
        "duration_s": float(duration),
        "doppler_rate_hz_s": float(rate),
        "data_bits": bool(bits),
    },
    sort_keys=True,
)

results = None
with dc.guarded(), st.spinner("Tracking..."):
    by_name = dc.carrier_runs(settings, runs, seed, window, nominal_cn0)
    results = list(by_name.values())
if results is not None:
    rows = [
        {
            "filter": name,
            "RMS phase error (rad)": r.rms_phase_error,
            "loss of lock (fraction of runs)": r.loss_of_lock,
        }
        for name, r in by_name.items()
    ]
    st.dataframe(rows, hide_index=True, width="stretch")
    st.caption(
        "ekf: fixed noise designed for the C/N0 above; aekf: adapts R (eq. 22, its window "
        "starting full of the design R) and a stabilised Q from the same design; ekf_matched: "
        "knows the true noise (the bound); "
        "aekf_paper_q: the paper's Q of eq. 26, which runs away (a finding we report)."
    )
    view = st.segmented_control(
        "Figure",
        VIEWS,
        key="ca_view",
        bind="query-params",
        **dc.initial("ca_view", VIEWS[0], "default"),
    )
    view = view or VIEWS[0]
    fig = None
    with dc.guarded():
        if view == "Phase error":
            fig = phase_error_figure(results)
        elif view == "Doppler":
            fig = doppler_figure(results)
        elif view == "Adaptation (R, Q)":
            fig = adaptation_figure(results)
        else:
            which = st.radio("Filter", list(by_name), key="ca_iq", horizontal=True)
            fig = iq_figure(by_name[which])
    if fig is not None:
        dc.show_figure(fig, key="ca_chart")
    c1, c2 = st.columns([1, 2])
    c1.download_button(
        "Results (CSV)",
        data=rows_to_csv(rows),
        file_name="noisevar-carrier.csv",
        mime="text/csv",
        key="ca_csv",
        on_click="ignore",
        icon=":material/table:",
        width="stretch",
    )
    if fig is not None:
        with c2:
            dc.figure_downloads(fig, "noisevar-carrier", "ca_fig")

with st.expander("Sweep over C/N0 (on demand)"):
    c1, c2 = st.columns([1, 3], vertical_alignment="bottom")
    sweep_runs = c1.number_input(
        "Runs per point", 1, 200, key="ca_sweep_runs", **dc.initial("ca_sweep_runs", 20)
    )
    if c2.button("Run the sweep 25 … 45 dB-Hz", key="ca_sweep_go"):
        st.session_state["ca_sweep"] = (settings, int(sweep_runs), int(seed), nominal_cn0)
    ask = st.session_state.get("ca_sweep")
    if ask:
        sweep = None
        with dc.guarded(), st.spinner("Sweeping C/N0..."):
            sweep = dc.carrier_sweep(ask[0], (25.0, 30.0, 35.0, 40.0, 45.0), ask[1], ask[2], ask[3])
        if sweep is not None:
            dc.show_figure(sweep_figure(sweep), key="ca_sweep_chart")

dc.how_it_works(
    "**Measurements.** After the numerically controlled oscillator, the prompt correlator of "
    "integration period $T$ gives",
    "$$I = A\\cos\\theta_e + n_I,\\qquad Q = A\\sin\\theta_e + n_Q,\\qquad "
    "\\frac{A^2}{2\\sigma_n^2} = \\frac{C}{N_0}\\,T$$",
    "nonlinear in the phase error $\\theta_e$, hence an EKF on the state "
    "$[\\theta, f_d, \\dot f_d, A]$ with",
    "$$F = \\begin{bmatrix}1 & 2\\pi T & \\pi T^2 & 0\\\\ 0 & 1 & T & 0\\\\ 0 & 0 & 1 & 0\\\\ "
    "0 & 0 & 0 & 1\\end{bmatrix}$$",
    "**Adaptation.** Over a window of $W$ periods, the residuals give $R$ (eq. 22, positive "
    "definite) and the innovations give $Q$ (eq. 26, as printed; it feeds on itself and "
    "runs away, so our AEKF scales the design $Q$ only when the innovations leave their "
    "$\\chi^2$ band). Our window starts full of the design $R$, each residual replacing one "
    "entry: started from the paper's running mean, a few pull-in residuals set $R$ alone, "
    "inflate it and stall the loop (the AEKF's only slips, at 30 dB-Hz):",
    "$$\\hat R = \\overline{r r^\\top} + HP_{k|k}H^\\top,\\qquad \\hat Q = K\\,\\overline{d "
    "d^\\top}\\,K^\\top$$",
    "A cycle slip is a jump of the phase error by a whole cycle: the loop has lost lock.",
)

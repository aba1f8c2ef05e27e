"""Fusion page: distributed VB-adaptive fusion with chi-square fault isolation (spec B2)."""

from __future__ import annotations

import streamlit as st

import dashboard_common as dc
from noisevar.estimators.compare import rows_to_csv
from noisevar.figures.fusion import error_figure, isolation_figure, r_track_figure, track_figure

dc.setup_page("Fusion", ":material/hub:")
st.title("Fusion")
st.caption(
    "Two position sensors and a velocity sensor track one target. Each sensor has a local "
    "filter (variational-Bayes, fixed or true R); a fusion centre combines them in "
    "information form. Sensor 1 misbehaves; a chi-square test can isolate it."
)

FAULTS = ["none", "noise-step", "noise-ramp", "bias", "frozen"]
CONFIGS = ["vb", "fixed", "oracle", "vb+isolation", "fixed+isolation", "oracle+isolation"]
VIEWS = ["Track", "Position error", "VB estimate of R", "Isolation test"]

c1, c2, c3, c4 = st.columns(4)
fault = c1.selectbox(
    "Fault of sensor 1",
    FAULTS,
    key="fu_fault",
    bind="query-params",
    **dc.initial("fu_fault", FAULTS.index("bias"), "index"),
)
steps = c2.slider(
    "Steps (1 s)",
    100,
    2000,
    step=100,
    key="fu_steps",
    bind="query-params",
    **dc.initial("fu_steps", 600),
)
runs = c3.slider(
    "Monte Carlo runs", 1, 50, key="fu_runs", bind="query-params", **dc.initial("fu_runs", 10)
)
seed = c4.number_input(
    "Seed", 0, 2**31 - 1, key="fu_seed", bind="query-params", **dc.initial("fu_seed", 0)
)
c1, c2, c3 = st.columns(3)
factor = c1.slider(
    "Noise increase (×, step / ramp)",
    1.0,
    10.0,
    step=0.5,
    key="fu_factor",
    bind="query-params",
    disabled=fault not in ("noise-step", "noise-ramp"),
    **dc.initial("fu_factor", 4.0),
)
bias = c2.slider(
    "Bias (noise standard deviations)",
    2.0,
    50.0,
    step=1.0,
    key="fu_bias",
    bind="query-params",
    disabled=fault != "bias",
    **dc.initial("fu_bias", 20.0),
)
false_alarm = c3.select_slider(
    "Chi-square false-alarm probability",
    [1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 5e-2],
    key="fu_fa",
    bind="query-params",
    **dc.initial("fu_fa", 1e-3),
)
configs = st.multiselect(
    "Fusion configurations (local R [+ isolation])",
    CONFIGS,
    key="fu_configs",
    bind="query-params",
    **dc.initial("fu_configs", ["vb", "fixed", "vb+isolation", "fixed+isolation"], "default"),
)

data = None
with dc.guarded():
    data = dc.fusion_data(fault, steps, runs, seed, factor, bias)
if data is not None:
    key = f"{fault}|{steps}|{runs}|{seed}|{factor}|{bias}"
    results = []
    with st.spinner("Fusing..."):
        for cfg in configs:
            with dc.guarded(f"{cfg}: "):
                results.append(dc.fusion_run(data, key, cfg, false_alarm))
        diff = None
        with dc.guarded():
            diff = dc.fusion_equivalence(data, key)
    if diff is not None:
        st.metric(
            "Distributed (fixed R, eq. 24) vs centralised Kalman filter: largest |Δx|",
            f"{diff:.2e}",
            help="The information-form fusion equals the centralised filter (target < 1e-8).",
        )
    if not results:
        st.info("Pick at least one configuration.")
    else:
        rows = [dc.fusion_row(r, data) for r in results]
        st.dataframe(
            rows,
            hide_index=True,
            column_config={
                "position RMSE (m)": st.column_config.NumberColumn(format="%.3f"),
                "sensor 1 isolated in fault": st.column_config.NumberColumn(format="percent"),
                "sensor 1 isolated when healthy": st.column_config.NumberColumn(format="percent"),
            },
        )
        view = st.segmented_control(
            "Figure",
            VIEWS,
            key="fu_view",
            bind="query-params",
            **dc.initial("fu_view", VIEWS[1], "default"),
        )
        view = view or VIEWS[1]
        fig = None
        with dc.guarded():
            if view == "Track":
                fig = track_figure(results)
            elif view == "Position error":
                fig = error_figure(results)
            elif view == "VB estimate of R":
                vb = [r for r in results if r.label.startswith("vb")]
                if vb:
                    fig = r_track_figure(vb[0], sensor=0, channel=0)
                else:
                    st.info("Add a vb configuration to see its estimate of R.")
            else:
                iso = [r for r in results if "+isolation" in r.label]
                if iso:
                    fig = isolation_figure(iso[0])
                else:
                    st.info("Add a configuration with isolation to see the test.")
        if fig is not None:
            dc.show_figure(fig, key="fu_chart")
        c1, c2 = st.columns([1, 2])
        c1.download_button(
            "Fusion table (CSV)",
            data=rows_to_csv(rows),
            file_name="noisevar-fusion.csv",
            mime="text/csv",
            key="fu_csv",
            on_click="ignore",
            icon=":material/table:",
            width="stretch",
        )
        if fig is not None:
            with c2:
                dc.figure_downloads(fig, "noisevar-fusion", "fu_fig")

dc.how_it_works(
    "**Local filters.** Sensor $i$ runs its own Kalman filter; with variational Bayes each "
    "noise variance has an inverse-gamma distribution $\\mathrm{IG}(\\alpha_j, \\beta_j)$, "
    "forgotten at rate $\\rho$ and updated with the residual:",
    "$$\\alpha_j \\leftarrow \\rho\\alpha_j + \\tfrac12,\\qquad "
    "\\beta_j \\leftarrow \\rho\\beta_j + \\tfrac12 (z - H\\hat x)_j^2 + "
    "\\tfrac12 (HPH^\\top)_{jj},\\qquad \\hat R_{jj} = \\beta_j/\\alpha_j$$",
    "**Fusion centre (eq. 24).** In information form the local updates simply add up:",
    "$$P^{-1} = P_{pred}^{-1} + \\sum_i \\big(P_i^{-1} - P_{i,pred}^{-1}\\big),\\qquad "
    "\\hat x = P\\Big(P_{pred}^{-1}\\hat x_{pred} + \\sum_i \\big(P_i^{-1}\\hat x_i - "
    "P_{i,pred}^{-1}\\hat x_{i,pred}\\big)\\Big)$$",
    "Each bracket is $H_i^\\top R_i^{-1} H_i$ (and $H_i^\\top R_i^{-1} z_i$), so the sum equals "
    "the centralised filter on all measurements: the metric above checks it.",
    "**Fault isolation.** Before its update, a sensor's normalised innovation is tested:",
    "$$d_i^\\top\\big(H_iP_{i,pred}H_i^\\top + R_i\\big)^{-1}d_i > \\chi^2_{m_i}(1-p_{fa})$$",
    "A flagged sensor does only its time update, so it adds nothing to the sums until its "
    "samples pass again.",
)

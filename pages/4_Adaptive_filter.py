"""Adaptive filter page: Kalman filters that estimate R on line, on a scenario or loaded data."""

from __future__ import annotations

import numpy as np
import streamlit as st

import dashboard_common as dc
from noisevar.estimators.compare import rows_to_csv
from noisevar.figures.kalman import (
    innovations_figure,
    r_estimates_figure,
    states_figure,
    track_figure,
)
from noisevar.kalman import STRATEGIES
from noisevar.systems.scenarios import SCENARIOS

#: The page's how-it-works expander (shown even before a signal is loaded).
HOW_IT_WORKS = (
    "**The filter.** Predict, then correct with the measurement $z_k$:",
    "$$\\hat x_{k|k-1} = F\\hat x_{k-1},\\quad P_{k|k-1} = FPF^\\top + Q,\\quad "
    "d_k = z_k - H\\hat x_{k|k-1},\\quad S_k = HP_{k|k-1}H^\\top + R_k$$",
    "$$K_k = P_{k|k-1}H^\\top S_k^{-1},\\qquad \\hat x_k = \\hat x_{k|k-1} + K_k d_k$$",
    "The gain weighs the measurement by how noisy it is: a wrong $R$ gives a wrong gain. "
    "Adaptive filters estimate $R$ as they go.",
    "**RAE and IAE (spec A10)** use the filter's own residuals $r_k = z_k - H\\hat x_{k|k}$ "
    "or innovations over a window of $N$ steps:",
    "$$\\hat R_{RAE} = \\overline{r r^\\top} + HP_{k|k}H^\\top,\\qquad "
    "\\hat R_{IAE} = \\overline{d d^\\top} - HP_{k|k-1}H^\\top$$",
    "Both depend on the state estimate: when the filter lags, the lag looks like noise, $R$ "
    "grows, the filter trusts the data less and lags more (the paper's RAE diverged).",
    "**Sage-Husa** updates recursively, "
    "$\\hat R_k = (1-d_k)\\hat R_{k-1} + d_k(d_kd_k^\\top - HP^-H^\\top)$, "
    "$d_k = (1-b)/(1-b^{k+1})$; **VB** keeps an inverse-gamma distribution per channel.",
    "**SOMD online** estimates each channel's variance from the raw samples alone (the "
    "second-order mutual difference of the Estimator page), so a lagging filter cannot "
    "corrupt it. The oracle knows the true $R$: no adaptive filter can beat it.",
    "**Consistency.** The normalised innovation squared is chi-square with $m$ degrees of "
    "freedom for a consistent filter:",
    "$$\\mathrm{NIS}_k = d_k^\\top S_k^{-1} d_k \\sim \\chi^2_m$$",
)

dc.setup_page("Adaptive filter", ":material/route:")
st.title("Adaptive filter")
st.caption(
    "Kalman filters whose measurement-noise covariance R is estimated while they run: SOMD "
    "on a trailing window (independent of the filter), residual and innovation windows "
    "(RAE, IAE), Sage-Husa, variational Bayes, against the oracle that knows the true R."
)

VIEWS = ["Track", "States", "R estimates", "Innovations and NIS"]

source = st.radio(
    "Data",
    ["Scenario", "Loaded signal"],
    key="af_source",
    bind="query-params",
    horizontal=True,
    help="A seeded scenario with truth, or the columns of the loaded file (no truth).",
)
is_scenario = source == "Scenario"
names = list(STRATEGIES) if is_scenario else [s for s in STRATEGIES if s != "oracle"]
default = ["oracle", "somd", "rae", "sage-husa", "vb"]
dc.keep_valid("af_strats", lambda v: all(s in names for s in v), [s for s in default if s in names])
strategies = st.multiselect(
    "Strategies",
    names,
    key="af_strats",
    bind="query-params",
    format_func=lambda s: f"{s}: {STRATEGIES[s].help}",
    **dc.initial("af_strats", [s for s in default if s in names], "default"),
)
with st.expander("Strategy settings"):
    c1, c2, c3, c4, c5 = st.columns(5)
    window = c1.number_input(
        "RAE/IAE window N",
        5,
        1000,
        key="af_window",
        bind="query-params",
        **dc.initial("af_window", STRATEGIES["rae"].defaults()["window"]),
    )
    forgetting = c2.slider(
        "Sage-Husa b",
        0.90,
        0.999,
        step=0.001,
        format="%.3f",
        key="af_b",
        bind="query-params",
        **dc.initial("af_b", STRATEGIES["sage-husa"].defaults()["forgetting"]),
    )
    rho = c3.slider(
        "VB ρ",
        0.90,
        1.0,
        step=0.005,
        format="%.3f",
        key="af_rho",
        bind="query-params",
        **dc.initial("af_rho", STRATEGIES["vb"].defaults()["rho"]),
    )
    every = c4.number_input(
        "SOMD every N steps",
        10,
        2000,
        step=10,
        key="af_every",
        bind="query-params",
        **dc.initial("af_every", STRATEGIES["somd"].defaults()["every"]),
    )
    huber = c5.toggle(
        "Huber update (κ = 1.345)",
        key="af_huber",
        bind="query-params",
        help="Robust M-estimation update (spec B3); combines with every strategy.",
    )
settings = {
    "window": int(window),
    "forgetting": float(forgetting),
    "rho": float(rho),
    "every": int(every),
}
kappa = 1.345 if huber else None

results = []
truth_R = None
z_shown = None
groups = None
track_states: tuple[int, int] | None = None
track_channels: tuple[int, int] | None = None
title = ""

if is_scenario:
    scen_names = list(SCENARIOS)
    c1, c2, c3, c4 = st.columns(4)
    scen = c1.selectbox("Scenario", scen_names, key="af_scenario", bind="query-params")
    seed = c2.number_input(
        "Seed",
        0,
        2**31 - 1,
        step=1,
        key="af_seed",
        bind="query-params",
        **dc.initial("af_seed", 0),
    )
    if scen == "gps-circle":
        size = c3.slider(
            "Duration (s)",
            100,
            3000,
            step=100,
            key="af_duration",
            bind="query-params",
            **dc.initial("af_duration", 3000),
        )
    else:
        size = c3.slider(
            "Steps",
            500,
            6000,
            step=500,
            key="af_steps",
            bind="query-params",
            **dc.initial("af_steps", 6000),
        )
    factor = 3.0
    if scen in ("noise-step", "noise-ramp"):
        factor = c4.slider(
            "Noise increase (×)",
            1.0,
            10.0,
            step=0.5,
            key="af_factor",
            bind="query-params",
            **dc.initial("af_factor", 3.0),
        )
    sc = None
    with dc.guarded():
        sc = dc.kalman_scenario(scen, int(seed), float(size), float(factor))
    if sc is not None:
        st.caption(sc.description)
        key = f"{scen}|{seed}|{size}|{factor}"
        with st.spinner("Filtering..."):
            for s in strategies:
                with dc.guarded(f"{s}: "):
                    results.append(dc.scenario_run(sc, key, s, settings, kappa))
        truth_R = sc.R_true[sc.first_step :]
        z_shown = sc.z[:, sc.first_step :]
        groups = dc.KALMAN_STATE_GROUPS.get(scen)
        track_states = (0, 1) if scen == "gps-circle" else (0, 2)
        track_channels = (0, 1)
        title = scen
else:
    sig = dc.require_signal(
        "The Adaptive filter page filters the columns of the loaded file.",
        preferred=("gps_circle.csv", "gps_track.nmea", "two_sensors.csv"),
        explain=HOW_IT_WORKS,
    )
    cols = sig.table.data_columns
    usable = [c for c in cols if np.all(np.isfinite(sig.table.columns[c]))]
    pick_default = usable[:2] if len(usable) >= 2 else usable[:1]
    if st.session_state.get("af_table") != sig.table_digest:
        st.session_state["af_table"] = sig.table_digest
        if "af_cols" in st.session_state:
            st.session_state["af_cols"] = pick_default
    dc.keep_valid("af_cols", lambda v: all(c in usable for c in v), pick_default)
    c1, c2, c3, c4 = st.columns(4)
    chosen = c1.multiselect(
        "Channels",
        usable,
        key="af_cols",
        max_selections=6,
        **dc.initial("af_cols", pick_default, "default"),
    )
    h_opts = dc.h_grid(1e-9, 1e-1)
    h_model = c2.select_slider(
        "Model h = q T³ / r",
        h_opts,
        key="af_h",
        bind="query-params",
        help="White-acceleration level of the constant-velocity model per channel, relative "
        "to its noise (unit-free, like the alpha-beta-gamma h).",
        **dc.initial("af_h", "0.001"),
    )
    r0_factor = c3.select_slider(
        "Initial R (× quick estimate)",
        [0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 10.0, 100.0],
        key="af_r0",
        bind="query-params",
        **dc.initial("af_r0", 4.0),
        help="The filters start from this R to show how they adapt.",
    )
    hs_opts = dc.h_grid(1e-9, 3e-3)
    h_somd = c4.select_slider(
        "SOMD h_S",
        hs_opts,
        key="af_hs",
        bind="query-params",
        **dc.initial("af_hs", "0.001"),
    )
    settings["h_smooth"] = float(h_somd)
    if not chosen:
        st.info("Pick at least one channel.")
    else:
        quick = None
        with st.spinner("Filtering..."):
            for s in strategies:
                with dc.guarded(f"{s}: "):
                    res, z, quick = dc.data_run(
                        sig, chosen, float(h_model), float(r0_factor), s, settings, kappa
                    )
                    results.append(res)
                    z_shown = z
        if quick is not None:
            st.caption(
                "Quick single-signal estimates (method auto) per channel: "
                + ", ".join(f"{c} {dc.fmt(v)}" for c, v in zip(chosen, quick, strict=True))
                + " — drawn as the reference line of the R panels."
            )
            truth_R = np.asarray(quick)
        if len(chosen) >= 2:
            track_states, track_channels = (0, 2), (0, 1)
        title = sig.label

if not strategies:
    st.info("Pick at least one strategy.")
elif results:
    rows = [dc.filter_summary(r, groups) for r in results]
    st.dataframe(
        rows,
        hide_index=True,
        column_config={
            k: st.column_config.NumberColumn(format="%.4g")
            for k in rows[0]
            if k.startswith("RMSE") or k == "mean NIS"
        },
    )
    st.caption(
        "Mean NIS near the number of channels m means the filter's innovations match its "
        "covariance (consistent); far above, it is over-confident (R too small)."
    )
    view = st.segmented_control(
        "Figure",
        VIEWS,
        key="af_view",
        bind="query-params",
        **dc.initial("af_view", VIEWS[0] if track_states else VIEWS[2], "default"),
    )
    view = view or VIEWS[2]
    fig = None
    with dc.guarded():
        if view == "Track":
            if track_states is None:
                st.info("The track needs two position channels: pick two channels.")
            else:
                fig = track_figure(
                    results,
                    z_shown,
                    states=track_states,
                    channels=track_channels,
                    title=f"Track: {title}",
                )
        elif view == "States":
            errors = st.toggle(
                "Errors with ±2σ bands", key="af_errors", disabled=results[0].truth is None
            )
            fig = states_figure(results, errors=bool(errors), title="States")
        elif view == "R estimates":
            fig = r_estimates_figure(
                results,
                R_true=truth_R,
                title="R̂ per channel (log scale) against the true value"
                if is_scenario
                else "R̂ per channel (log scale) against a quick estimate",
            )
        else:
            which = st.selectbox(
                "Filter",
                [r.strategy for r in results],
                key="af_innov",
            )
            res = next(r for r in results if r.strategy == which)
            fig = innovations_figure(res)
    if fig is not None:
        dc.show_figure(fig, key="af_chart")
    c1, c2 = st.columns([1, 2])
    c1.download_button(
        "Filter table (CSV)",
        data=rows_to_csv(rows),
        file_name="noisevar-filters.csv",
        mime="text/csv",
        key="af_csv",
        on_click="ignore",
        icon=":material/table:",
        width="stretch",
    )
    if fig is not None:
        with c2:
            dc.figure_downloads(fig, "noisevar-filter", "af_fig")

# ------------------------------------------------------------------ Table 1
with st.expander("The paper's Table 1, reproduced on demand (gps-circle)"):
    st.caption(
        "Noise variance of each GPS channel: the paper's SOMD and RAE beside ours, averaged "
        "over Monte Carlo runs of the full 3000 s scenario (about 2 s per run)."
    )
    c1, c2, c3 = st.columns([1, 1, 2], vertical_alignment="bottom")
    t_runs = c1.number_input("Runs", 1, 100, key="t1_runs", **dc.initial("t1_runs", 5))
    t_seed = c2.number_input("Seed", 0, 2**31 - 1, key="t1_seed", **dc.initial("t1_seed", 0))
    if c3.button("Reproduce Table 1", key="t1_go", icon=":material/play_arrow:"):
        st.session_state["t1_ask"] = (int(t_runs), int(t_seed))
    ask = st.session_state.get("t1_ask")
    if ask:
        res1 = None
        with dc.guarded(), st.spinner(f"Running {ask[0]} runs of every filter..."):
            res1 = dc.table1(*ask)
        if res1 is not None:
            chans = list(res1["channels"])
            table = [
                {"row": "true", **{c: res1["channels"][c]["true"] for c in chans}},
                {"row": "paper SOMD", **{c: res1["channels"][c]["paper"]["somd"] for c in chans}},
                {"row": "paper RAE", **{c: res1["channels"][c]["paper"]["rae"] for c in chans}},
            ]
            for m in res1["channels"][chans[0]]["methods"]:
                table.append(
                    {"row": m, **{c: res1["channels"][c]["methods"][m]["mean"] for c in chans}}
                )
            st.markdown(f"**Noise variance per channel** ({ask[0]} runs, seed {ask[1]})")
            st.dataframe(
                table,
                hide_index=True,
                column_config={c: st.column_config.NumberColumn(format="%.4g") for c in chans},
            )
            rm = [
                {
                    "filter": k,
                    **v,
                    "diverged": f"{res1['divergence'][k]['runs']}/{res1['divergence'][k]['of']}",
                }
                for k, v in res1["rmse"].items()
            ]
            st.markdown("**RMSE over runs and steps**")
            st.dataframe(rm, hide_index=True)
            for note in res1.get("notes", []):
                st.caption(note)
            st.download_button(
                "Table 1 (CSV)",
                data=rows_to_csv(table),
                file_name="noisevar-table1.csv",
                mime="text/csv",
                key="t1_csv",
                on_click="ignore",
            )

dc.how_it_works(*HOW_IT_WORKS)

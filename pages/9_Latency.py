"""Latency page: GPS delay by least squares over shifts and a random-constant filter (spec C)."""

from __future__ import annotations

import json

import streamlit as st

import dashboard_common as dc
from noisevar.estimators.compare import rows_to_csv
from noisevar.figures.latency import cost_figure, delay_figure, records_figure

dc.setup_page("Latency", ":material/timer:")
st.title("Latency")
st.caption(
    "The same speed seen by an inertial unit (on time) and by a GPS (late). The delay is the "
    "shift that best lines the two records up; a measurable part (timestamps, scheduler) is "
    "known per segment, and the unknown rest is filtered over the segments."
)
VIEWS = ["Records", "Cost against shift", "Delay per segment"]

c1, c2, c3, c4 = st.columns(4)
duration = c1.slider(
    "Duration (s)",
    100,
    2000,
    step=50,
    key="la_dur",
    bind="query-params",
    **dc.initial("la_dur", 550),
)
rate = c2.select_slider(
    "Sample rate (Hz)",
    [1, 2, 5, 10, 20, 50],
    key="la_rate",
    bind="query-params",
    **dc.initial("la_rate", 10),
)
unknown = c3.slider(
    "Unknown delay (s)",
    0.0,
    1.5,
    step=0.01,
    key="la_unknown",
    bind="query-params",
    **dc.initial("la_unknown", 0.2),
)
measurable = c4.slider(
    "Measurable delay (s)",
    0.0,
    0.5,
    step=0.01,
    key="la_meas",
    bind="query-params",
    **dc.initial("la_meas", 0.1),
)
c1, c2, c3, c4 = st.columns(4)
jitter = c1.slider(
    "Measurable jitter (± s)",
    0.0,
    0.2,
    step=0.01,
    key="la_jitter",
    bind="query-params",
    **dc.initial("la_jitter", 0.05),
)
segment = c2.slider(
    "Segment (s)",
    10,
    120,
    step=5,
    key="la_seg",
    bind="query-params",
    **dc.initial("la_seg", 30),
)
gps_noise = c3.slider(
    "GPS speed noise (m/s)",
    0.0,
    2.0,
    step=0.05,
    key="la_noise",
    bind="query-params",
    **dc.initial("la_noise", 0.1),
)
seed = c4.number_input(
    "Seed", 0, 2**31 - 1, key="la_seed", bind="query-params", **dc.initial("la_seed", 0)
)
max_delay = st.slider(
    "Largest delay searched (± s)",
    0.5,
    5.0,
    step=0.5,
    key="la_max",
    bind="query-params",
    **dc.initial("la_max", 2.0),
)
settings = json.dumps(
    {
        "duration_s": float(duration),
        "rate_hz": float(rate),
        "unknown_delay_s": float(unknown),
        "measurable_delay_s": float(measurable),
        "measurable_jitter_s": float(jitter),
        "segment_s": float(segment),
        "gps_noise_std": float(gps_noise),
    },
    sort_keys=True,
)

res = None
with dc.guarded():
    res = dc.latency_run(settings, seed, max_delay)
if res is not None:
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
    rows = [
        {"compensation": "none", "residual delay RMS (s)": res.residual_none_s},
        {"compensation": "fixed (whole record)", "residual delay RMS (s)": res.residual_fixed_s},
        {"compensation": "per-segment coarse", "residual delay RMS (s)": res.residual_coarse_s},
        {"compensation": "filtered", "residual delay RMS (s)": res.residual_filtered_s},
    ]
    st.dataframe(
        rows,
        hide_index=True,
        column_config={"residual delay RMS (s)": st.column_config.NumberColumn(format="%.4f")},
    )
    view = st.segmented_control(
        "Figure",
        VIEWS,
        key="la_view",
        bind="query-params",
        **dc.initial("la_view", VIEWS[0], "default"),
    )
    view = view or VIEWS[0]
    fig = None
    with dc.guarded():
        if view == "Records":
            fig = records_figure(res)
        elif view == "Cost against shift":
            fig = cost_figure(res)
        else:
            fig = delay_figure(res)
    if fig is not None:
        dc.show_figure(fig, key="la_chart")
    c1, c2 = st.columns([1, 2])
    c1.download_button(
        "Residual delays (CSV)",
        data=rows_to_csv(rows),
        file_name="noisevar-latency.csv",
        mime="text/csv",
        key="la_csv",
        on_click="ignore",
        icon=":material/table:",
        width="stretch",
    )
    if fig is not None:
        with c2:
            dc.figure_downloads(fig, "noisevar-latency", "la_fig")
    st.caption(
        "The Two sensors page uses the same least-squares delay to line two sensors up before "
        "differencing them."
    )

dc.how_it_works(
    "**Coarse delay.** Shift the GPS record against the inertial one and keep the shift with "
    "the smallest mean squared difference (the mean difference removed, so a constant offset "
    "does not matter):",
    "$$\\hat\\tau = \\arg\\min_s \\frac{1}{m}\\sum_k \\big(v_{GPS}[k+s] - v_{INS}[k] - "
    "\\bar\\Delta_s\\big)^2$$",
    "then refine below one sample with a parabola through the three best shifts "
    "$c_{-1}, c_0, c_{+1}$:",
    "$$\\delta = \\frac{c_{-1} - c_{+1}}{2(c_{-1} - 2c_0 + c_{+1})}$$",
    "**Filtering the unknown part.** Per segment, the measurable part (known) is subtracted; "
    "the unknown remainder is a random constant, estimated by a scalar Kalman filter:",
    "$$x_{k+1} = x_k + w_k,\\qquad y_k = \\hat\\tau_k - \\tau^{meas}_k = x_k + v_k$$",
)

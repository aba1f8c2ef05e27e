"""Estimator page: tune SOMD and see every step (filters, windows, envelopes, h scan, estimate)."""

from __future__ import annotations

import math

import streamlit as st

import dashboard_common as dc
import noisevar
from noisevar.config import config_to_json, params_to_config, parse_config
from noisevar.estimators.compare import rows_to_csv
from noisevar.figures._common import range_to_slice
from noisevar.figures.estimator import (
    envelope_figure,
    estimate_rows,
    scan_figure,
    signal_figure,
    somd_figure,
    window_rows,
    window_tests_figure,
    window_variance_figure,
)
from noisevar.filters.abg import settling_samples
from noisevar.filters.envelope import RATIO_BAND

#: The page's how-it-works expander (shown even before a signal is loaded).
HOW_IT_WORKS = (
    "**1. A virtual second sensor (spec A2).** An alpha-beta-gamma filter (position, rate, "
    "acceleration; white jerk) with constant gains smooths the record. With $h = q/r$ "
    "(jerk spectral density over noise variance) the steady-state gains are",
    "$$\\alpha = 2h^{1/3},\\qquad \\beta = 2h^{2/3},\\qquad \\gamma = h$$",
    "A small $h_S$ gives a smooth output $Z_1$ with little noise left; a faster filter "
    "($h_T$ 10 to 100 times larger) tracks quick changes.",
    "**2. Choosing $h_S$ (eq. 13-14).** Envelopes through the local maxima $U$ and minima $L$ "
    "give a noise amplitude per window of $m$ samples; $h_S$ should cut it 10 to 20 times:",
    "$$|V| = \\frac{1}{2m}\\sum_{k}(U_k - L_k),\\qquad "
    "\\frac{1}{20} \\le \\frac{|V_1|}{|V_2|} \\le \\frac{1}{10}$$",
    "**3. Keeping windows (eq. 16-19).** In each window, lines $x = a\\,i + b$ are fitted to "
    "both filter outputs. $A_1, A_2$ ($A_3, A_4$) are the mean deviations of the smooth output "
    "above and below its line in the first (second) half. A window is kept when",
    "$$\\left|\\tfrac{A_1}{A_2}\\right|,\\left|\\tfrac{A_2}{A_3}\\right|,"
    "\\left|\\tfrac{A_3}{A_4}\\right| \\in (1-\\Gamma_{amp},\\,1+\\Gamma_{amp}),\\qquad "
    "|\\arctan a_S - \\arctan a_T| < \\Gamma_{ang}$$",
    "The first test says the smooth output is straight inside the window (no curvature); the "
    "second says the smooth filter is not lagging behind the tracking filter.",
    "**4. The estimate (eq. 8).** Over the kept windows, with $Z_2 = z$ the raw samples:",
    "$$\\hat\\sigma^2 = \\frac{1}{c}\\,\\mathrm{E}\\big[(\\Delta Z_1 - \\Delta Z_2)^2\\big]$$",
    "The paper uses $c = 2$, assuming the virtual sensor's noise is independent and tiny. It is "
    "neither: $Z_1$ is $z$ filtered by $g$, so the noise of $\\Delta Z_1 - \\Delta Z_2$ is white "
    "noise through $\\Delta(g-\\delta)$ and the exact factor is",
    "$$c(h) = \\sum_k \\big(\\Delta(g-\\delta)\\big)_k^2$$",
    "(2.10 at $h = 1.5\\cdot10^{-5}$, 2.43 at $9\\cdot10^{-4}$). Method `somd` divides by "
    "$c(h)$; `somd-paper` by 2. The 95 % interval is a chi-square interval with the "
    "effective degrees of freedom of the correlated squares.",
)

dc.setup_page("Estimator", ":material/tune:")
st.title("Estimator")
sig = dc.require_signal(
    "The Estimator tunes the SOMD estimator on it and shows every step.", explain=HOW_IT_WORKS
)

SOMD = ("somd", "somd-paper")
METHODS = [m for m in noisevar.methods() if m != "somd-redundant"]
DESC = noisevar.describe_methods()
RATIOS = [2, 3, 5, 7, 10, 15, 20, 30, 50, 70, 100]
VIEWS = ["Window tests", "Envelopes and |V|", "h scan", "Per-window variance"]
SCAN_AUTO_LIMIT = 300_000

n = sig.n
min_window = 8


def _valid_h(options: list[str], window: int) -> list[str]:
    """h values whose filters settle with room for two windows (widgets never offer others)."""
    ok = [h for h in options if settling_samples(float(h)) + 2 * window < n]
    return ok or options[-1:]


def _closest(options: list[str], target: float) -> str:
    return min(options, key=lambda h: abs(math.log(float(h) / target)))


def _apply_config() -> None:
    """Load an exported config JSON into the widgets (runs before the page script)."""
    up = st.session_state.get("est_config_upload")
    if up is None:
        return
    try:
        cfg = parse_config(up.getvalue(), up.name)
    except noisevar.NoisevarError as exc:
        st.session_state["est_config_error"] = str(exc)
        return
    st.session_state.pop("est_config_error", None)
    method = cfg.get("method")
    if method in METHODS:
        st.session_state["est_method"] = method
    hs = cfg.get("h_smooth")
    if hs is not None:
        hs = hs if isinstance(hs, list) else [hs]
        st.session_state["h_s"] = _closest(H_ALL, hs[0])
        st.session_state["h_more"] = sorted({_closest(H_ALL, h) for h in hs[1:]}, key=float)
    if "h_track" in cfg:
        st.session_state["ht_mode"] = "value"
        st.session_state["h_t"] = _closest(HT_ALL, cfg["h_track"])
    elif "track_ratio" in cfg:
        st.session_state["ht_mode"] = "multiple of h_S"
        st.session_state["ht_ratio"] = min(RATIOS, key=lambda r: abs(r - cfg["track_ratio"]))
    if "window" in cfg:
        st.session_state["win"] = int(min(max(cfg["window"], min_window), max_window))
    if "gamma_amp" in cfg:
        st.session_state["g_amp"] = float(min(max(round(cfg["gamma_amp"] * 20) / 20, 0.05), 1.0))
    if "gamma_ang" in cfg:
        st.session_state["g_ang"] = float(min(max(round(cfg["gamma_ang"] * 2) / 2, 0.5), 90.0))
    if "angle" in cfg:
        st.session_state["angle"] = cfg["angle"]
    if "select" in cfg:
        st.session_state["select"] = bool(cfg["select"])


def _clear_stretch() -> None:
    st.session_state["s0"] = 0
    st.session_state["s1"] = 0


H_ALL = dc.h_grid(1e-9, 3e-3)
HT_ALL = dc.h_grid(1e-8, 0.3)
max_window = int(max(min(400, n // 4), min_window + 1))

# --------------------------------------------------------------- parameters
left, right = st.columns([1, 3], gap="large")
with left:
    st.markdown("#### Parameters")
    dc.keep_valid("est_method", lambda v: v in METHODS, "somd")
    method = st.selectbox(
        "Method",
        METHODS,
        key="est_method",
        bind="query-params",
        format_func=lambda m: f"{m}: {DESC[m]}",
        **dc.initial("est_method", METHODS.index("somd"), "index"),
    )
    somd = method in SOMD
    hs_opts = _valid_h(H_ALL, min_window)
    dc.keep_valid("h_s", lambda v: v in hs_opts, _closest(hs_opts, 1.5e-5))
    h_s = st.select_slider(
        "Smoothing filter h_S (log scale)",
        hs_opts,
        key="h_s",
        bind="query-params",
        disabled=not somd,
        help="h = q/r of the alpha-beta-gamma filter; smaller = smoother. Paper: 1.5e-5.",
        **dc.initial("h_s", _closest(hs_opts, 1.5e-5)),
    )
    h_more = st.multiselect(
        "More smoothing filters (several h)",
        [h for h in hs_opts if h != h_s],
        key="h_more",
        bind="query-params",
        disabled=not somd,
        help="Section 2.4: a window counts when any smoothing filter passes; more windows.",
    )
    ht_mode = st.radio(
        "Tracking filter h_T",
        ["multiple of h_S", "value"],
        key="ht_mode",
        bind="query-params",
        horizontal=True,
        disabled=not somd,
    )
    if ht_mode == "multiple of h_S":
        ratio_opts = [r for r in RATIOS if float(h_s) * r < 0.3]
        dc.keep_valid("ht_ratio", lambda v: v in ratio_opts, ratio_opts[-1])
        ratio = st.select_slider(
            "h_T / h_S",
            ratio_opts,
            key="ht_ratio",
            bind="query-params",
            disabled=not somd,
            help="The paper takes h_T 10 to 100 times h_S.",
            **dc.initial("ht_ratio", 30 if 30 in ratio_opts else ratio_opts[-1]),
        )
        h_t = None
    else:
        ht_opts = _valid_h(HT_ALL, min_window)
        dc.keep_valid("h_t", lambda v: v in ht_opts, _closest(ht_opts, 5e-4))
        h_t = st.select_slider(
            "h_T (log scale)",
            ht_opts,
            key="h_t",
            bind="query-params",
            disabled=not somd,
            **dc.initial("h_t", _closest(ht_opts, 5e-4)),
        )
        ratio = None
    dc.keep_valid("win", lambda v: min_window <= v <= max_window, min(40, max_window))
    window = st.slider(
        "Window m (samples)",
        min_window,
        max_window,
        key="win",
        bind="query-params",
        help="Windows for the selection tests and the envelope amplitude (paper: 40).",
        **dc.initial("win", min(40, max_window)),
    )
    g_amp = st.slider(
        "Γ_amp (amplitude test)",
        0.05,
        1.0,
        step=0.05,
        key="g_amp",
        bind="query-params",
        disabled=not somd,
        help=(
            "somd-paper (as printed): keep a window when |A1/A2|, |A2/A3|, |A3/A4| are all "
            "within (1 − Γ, 1 + Γ). somd: the same chain closed by |A4/A1|, each ratio within "
            "a band of the same log-width centred on 1, so that −z keeps the same windows as z."
        ),
        **dc.initial("g_amp", 0.5),
    )
    g_ang = st.slider(
        "Γ_ang (angle test, degrees)",
        0.5,
        90.0,
        step=0.5,
        key="g_ang",
        bind="query-params",
        disabled=not somd,
        help="Keep a window when the smooth and tracking slopes differ by less than Γ_ang.",
        **dc.initial("g_ang", 10.0),
    )
    angle = st.radio(
        "Slopes of the angle test",
        ["scaled", "paper"],
        key="angle",
        bind="query-params",
        horizontal=True,
        disabled=not somd,
        help="scaled: slopes in noise units (unit-free); paper: raw units per sample.",
    )
    select = st.toggle(
        "Window selection",
        key="select",
        bind="query-params",
        disabled=not somd,
        help="Off for a signal known to be slowly varying (the paper's GPS experiment).",
        **dc.initial("select", True),
    )
    st.file_uploader(
        "Load tuned parameters (JSON)",
        type=["json"],
        key="est_config_upload",
        on_change=_apply_config,
        help="A config exported here or written for `noisevar estimate --config`.",
    )
    if st.session_state.get("est_config_error"):
        st.error(st.session_state["est_config_error"])

hs_list = [float(h_s)] + [float(h) for h in h_more if h != h_s]
params: dict = {}
if somd:
    params = {
        "h_smooth": hs_list if len(hs_list) > 1 else hs_list[0],
        "window": int(window),
        "gamma_amp": float(g_amp),
        "gamma_ang": float(g_ang),
        "angle": angle,
        "select": bool(select),
    }
    if h_t is not None:
        params["h_track"] = float(h_t)
    else:
        params["track_ratio"] = float(ratio)
    # the Compare page runs the SOMD methods with these tuned parameters
    st.session_state["nv_tuned"] = dict(params)

# ------------------------------------------------------------------ results
with right:
    truth = dc.truth_of(sig)
    est = None
    diag = None
    try:
        with st.spinner("Estimating..."):
            est = dc.estimate(sig, method, params)
    except noisevar.NoisevarError as exc:
        st.error(str(exc))
        if isinstance(exc, noisevar.NoWindowKept) and exc.diagnosis is not None:
            diag = exc.diagnosis  # the refused estimate: filter outputs and every window's tests
            st.info(
                "The figures below show every window's tests against your thresholds: "
                "move Γ_amp / Γ_ang past the points, or lengthen the window m."
            )
    shown = est if est is not None else diag

    if est is not None:
        cols = st.columns(5)
        cols[0].metric("Noise variance", dc.fmt(est.variance))
        cols[1].metric("Noise std", dc.fmt(est.std))
        cols[2].metric(
            "95 % interval",
            f"{dc.fmt(est.ci95[0], 3)}–{dc.fmt(est.ci95[1], 3)}",
            help=f"{dc.fmt(est.ci95[0], 6)} to {dc.fmt(est.ci95[1], 6)} (chi-square, "
            f"{est.dof:.0f} effective degrees of freedom)",
        )
        d = est.details
        if d is not None and d.selection is not None:
            summ = d.selection.rejection_summary()
            kept = int(d.kept_windows.sum())
            cols[3].metric(
                "Windows kept",
                f"{kept} / {summ['windows']}",
                help=(
                    f"amplitude test failed: {summ['failed_amplitude']}, angle test failed: "
                    f"{summ['failed_angle']} (a window can fail both); the first "
                    f"{d.skip} samples are the filters' start-up transient"
                ),
            )
            if summ["windows"] and kept < 0.2 * summ["windows"]:
                worst = "Γ_amp" if summ["failed_amplitude"] >= summ["failed_angle"] else "Γ_ang"
                st.warning(
                    f"Only {kept} of {summ['windows']} windows kept ({summ['failed_amplitude']} "
                    f"failed the amplitude test, {summ['failed_angle']} the angle test): the "
                    f"estimate rests on few samples. Relax {worst} first, or change m."
                )
        else:
            cols[3].metric("Samples used", f"{est.n_used:,} / {est.n_total:,}")
        if truth is not None:
            cols[4].metric(
                "True variance",
                dc.fmt(truth),
                delta=f"{100 * (est.variance / truth - 1):+.1f} %",
                delta_color="off",
                delta_arrow="off",
                help="Known for a generated signal; the delta is the relative error.",
            )
        for note in est.notes:
            st.caption(f"Note: {note}")
        if somd and method == "somd-paper":
            st.caption(
                "somd-paper divides by 2 as printed; its bias is c(h)/2 − 1 (spec A8). "
                "`somd` divides by the exact c(h)."
            )

    # ------------------------------------------------------- stretch (box select)
    chart_state = st.session_state.get("est_chart")
    boxes = []
    try:
        boxes = list(chart_state["selection"]["box"]) if chart_state else []
    except (KeyError, TypeError):
        boxes = []
    if boxes:
        box = boxes[-1]
        sig_box = (round(float(box["x"][0]), 6), round(float(box["x"][1]), 6))
        if st.session_state.get("_last_box") != sig_box:
            st.session_state["_last_box"] = sig_box
            sl = range_to_slice(sig_box[0], sig_box[1], n, sig.sample_period)
            st.session_state["s0"], st.session_state["s1"] = sl.start, sl.stop
    s0 = int(st.session_state.get("s0", 0) or 0)
    s1 = int(st.session_state.get("s1", 0) or 0)
    stretch = slice(min(s0, s1), max(s0, s1)) if max(s0, s1) > min(s0, s1) else None

    if shown is not None:
        fig = somd_figure(
            sig.z, shown, sig.sample_period, stretch=stretch, title="Raw signal, filters, windows"
        )
    else:
        fig = signal_figure(sig.z, sig.sample_period, sig.column, title="Raw signal")
        fig.update_layout(dragmode="select", selectdirection="h")
    st.caption(
        "Drag across the plot to estimate over a chosen stretch only (double-click clears the "
        "selection). Shaded: kept windows; marks above the record: rejected windows and why."
    )
    dc.show_figure(fig, key="est_chart", select=True)

    c1, c2, c3 = st.columns([1, 1, 1], vertical_alignment="bottom")
    c1.number_input(
        "Stretch from sample", min_value=0, max_value=n, step=1, key="s0", bind="query-params"
    )
    c2.number_input(
        "Stretch to sample", min_value=0, max_value=n, step=1, key="s1", bind="query-params"
    )
    c3.button("Whole record", key="clear_stretch", on_click=_clear_stretch, width="stretch")
    if stretch is not None:
        try:
            part = dc.estimate(sig, method, params, stretch=stretch)
            cols = st.columns(4)
            cols[0].metric(
                "Stretch variance",
                dc.fmt(part.variance),
                help=f"samples {stretch.start} to {stretch.stop - 1}",
            )
            cols[1].metric("Stretch std", dc.fmt(part.std))
            cols[2].metric("95 % interval", f"{dc.fmt(part.ci95[0], 3)}–{dc.fmt(part.ci95[1], 3)}")
            cols[3].metric("Samples in stretch", f"{stretch.stop - stretch.start:,}")
        except noisevar.NoisevarError as exc:
            st.error(f"Stretch {stretch.start}–{stretch.stop - 1}: {exc} (choose a longer stretch)")

    # ---------------------------------------------------------- detail views
    view = st.segmented_control(
        "Step by step",
        VIEWS,
        key="est_view",
        bind="query-params",
        **dc.initial("est_view", VIEWS[0], "default"),
    )
    view = view or VIEWS[0]
    detail = None
    d = shown.details if shown is not None else None
    if view == "Window tests":
        if d is not None and d.selection is not None:
            detail = window_tests_figure(
                d.selection,
                g_amp,
                g_ang,
                sig.sample_period,
                title="Window tests of eq. 19 (first smoothing filter)",
            )
        else:
            st.info("Window tests exist for the SOMD methods with window selection on.")
    elif view == "Envelopes and |V|":
        with dc.guarded():
            raw_amp, det = dc.amplitude(sig, window)
            smooth_amp = None
            if d is not None:
                smooth_amp, _ = dc.amplitude(
                    sig, window, d.smooth_output[0], which=f"smooth:{d.h_smooth[0]!r}"
                )
            detail = envelope_figure(
                raw_amp, det, smooth_amp, sig.sample_period, title="Envelope noise amplitude"
            )
            ratio_txt = (
                f"; smooth/raw ratio {smooth_amp.mean_amplitude / raw_amp.mean_amplitude:.3g}"
                if smooth_amp is not None
                else ""
            )
            st.caption(f"Mean |V| of the raw record {dc.fmt(raw_amp.mean_amplitude)}{ratio_txt}.")
    elif view == "h scan":
        run_scan = n <= SCAN_AUTO_LIMIT or st.session_state.get("scan_ok") == (sig.digest, window)
        if not run_scan:
            st.info(
                f"The h scan filters the {n:,} samples once per grid point (41 points): "
                "it takes several seconds on this record."
            )
            if st.button("Run the h scan", key="scan_go"):
                st.session_state["scan_ok"] = (sig.digest, window)
                run_scan = True
        if run_scan:
            with dc.guarded(), st.spinner("Scanning h..."):
                scan = dc.h_scan(sig, window)
                detail = scan_figure(
                    scan,
                    hs_list if somd else (),
                    d.h_track if d is not None else None,
                    title="Choosing h_S: noise amplitude ratio against h (eq. 14)",
                )
                if math.isfinite(scan.h_min):
                    st.caption(
                        f"Ratio within [{RATIO_BAND[0]:g}, {RATIO_BAND[1]:g}] for h from "
                        f"{scan.h_min:.3g} to {scan.h_max:.3g}; chosen h = {scan.h_chosen:.3g} "
                        f"(the ratio closest to the band's centre)."
                    )
                else:
                    st.caption(
                        f"No grid h puts the ratio inside the band; closest: {scan.h_chosen:.3g}."
                    )
    else:
        if shown is not None:
            detail = window_variance_figure(
                shown,
                sig.sample_period,
                truth,
                title="Per-window variance and the final estimate",
            )
    if detail is not None:
        dc.show_figure(detail, key="est_detail")

    # ---------------------------------------------------------------- exports
    st.markdown("#### Export")
    if est is not None:
        c1, c2, c3 = st.columns(3)
        try:
            cfg_json = config_to_json(params_to_config(est.params["method"], est.params))
        except noisevar.NoisevarError as exc:  # pragma: no cover - params come from widgets
            cfg_json = None
            st.error(str(exc))
        if cfg_json is not None:
            c1.download_button(
                "Tuned parameters (JSON)",
                data=cfg_json,
                file_name="noisevar-config.json",
                mime="application/json",
                key="dl_config",
                on_click="ignore",
                icon=":material/settings:",
                width="stretch",
                help="Use it with: noisevar estimate --config noisevar-config.json data.csv",
            )
        c2.download_button(
            "Estimate (CSV)",
            data=rows_to_csv(estimate_rows(est, truth)),
            file_name="noisevar-estimate.csv",
            mime="text/csv",
            key="dl_summary",
            on_click="ignore",
            icon=":material/table:",
            width="stretch",
        )
        c3.download_button(
            "Per-window results (CSV)",
            data=lambda: rows_to_csv(window_rows(est, sig.sample_period)) or "no windows\n",
            file_name="noisevar-windows.csv",
            mime="text/csv",
            key="dl_windows",
            on_click="ignore",
            icon=":material/view_list:",
            width="stretch",
            disabled=est.details is None,
        )
        if cfg_json is not None:
            with st.expander("Tuned parameters (the JSON config)"):
                st.code(cfg_json, language="json")
                st.caption("`noisevar estimate --config noisevar-config.json yourfile.csv`")
    st.caption("Main figure")
    dc.figure_downloads(fig, "noisevar-estimator", "fig_main")
    if detail is not None:
        st.caption(f"{view} figure")
        dc.figure_downloads(detail, f"noisevar-{str(view).split()[0].lower()}", "fig_detail")

dc.how_it_works(*HOW_IT_WORKS)

"""The Estimator page's results: the estimate, the stretch, the SOMD step figures, exports."""

from __future__ import annotations

import math
import shlex

import plotly.graph_objects as go
import streamlit as st
from streamlit.delta_generator import DeltaGenerator

import noisevar
from dashboard import cache
from dashboard.cache import DEFAULT_METHOD
from dashboard.sections.estimator_tuning import H_ALL, Tuning, closest, tuned_methods
from dashboard.state import LoadedSignal, initial, signal_units, time_of
from dashboard.text import plain
from dashboard.widgets import (
    csv_download,
    figure_downloads,
    fmt,
    guarded,
    html_report,
    lazy_expander,
    show_figure,
)
from noisevar.config import config_to_json, params_to_config
from noisevar.estimators import describe_methods
from noisevar.estimators.answer import record_answer
from noisevar.estimators.compare import rows_to_csv
from noisevar.estimators.results import VarianceEstimate, row_label
from noisevar.figures.axes import range_to_slice
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
from noisevar.filters.abg import somd_bias_factor
from noisevar.filters.envelope import RATIO_BAND
from noisevar.format import eng_range, squared

VIEWS = ["Window tests", "Envelopes and |V|", "h scan", "Per-window variance"]
#: Windows the window-tests figure draws: it is drawn again on every change of a threshold.
WINDOW_MARKERS = 400
#: Session-state key of the (lazy) Export expander.
EXPORT_KEY = "est_export_open"
#: Longer records run the h scan only on request.
SCAN_AUTO_LIMIT = 300_000


def run_estimate(
    sig: LoadedSignal, tuning: Tuning
) -> tuple[VarianceEstimate | None, VarianceEstimate | None]:
    """The estimate, and what the figures show: the estimate or, when refused, its diagnosis."""
    try:
        with st.spinner("Estimating..."):
            est = cache.estimate(sig, tuning.method, tuning.params)
        return est, est
    except noisevar.NoisevarError as exc:
        st.error(plain(exc))
        if isinstance(exc, noisevar.NoWindowKept) and exc.diagnosis is not None:
            st.info(
                "The figures below show every window's tests against your thresholds: "
                "move Γ_amp / Γ_ang past the points, or lengthen the window m."
            )
            return None, exc.diagnosis  # the refused estimate: filter outputs, window tests
        return None, None


def headline(sig: LoadedSignal, est: VarianceEstimate, truth: float | None, tuning: Tuning) -> None:
    """Variance, std, interval, windows kept (or samples used), the truth when known."""
    u = signal_units()
    # with a stretch chosen (below), these are still the whole record's: say so
    whole = " (whole record)" if _selected_stretch(sig) is not None else ""
    cols = st.columns(5)
    cols[0].metric("Noise variance" + whole, fmt(est.variance, unit=squared(u)))
    cols[1].metric("Noise std" + whole, fmt(est.std, unit=u))
    cols[2].metric(
        "95 % interval" + whole,
        eng_range(est.ci95[0], est.ci95[1], squared(u), 3),
        help=f"{fmt(est.ci95[0], 6)} to {fmt(est.ci95[1], 6)} (chi-square, "
        f"{est.dof:.0f} effective degrees of freedom)",
    )
    d = est.details
    if d is not None and d.selection is not None:
        _windows_kept(cols[3], est)
    else:
        cols[3].metric("Samples used", f"{est.n_used:,} / {est.n_total:,}")
    if truth is not None:
        cols[4].metric(
            "True variance",
            fmt(truth, unit=squared(u)),
            delta=f"{100 * (est.variance / truth - 1):+.1f} %",
            delta_color="off",
            delta_arrow="off",
            help="Known for a generated signal; the delta is the relative error.",
        )
    # the noise panel below shows the diagnostics' notes under its flags: not twice
    panel = set(getattr(est.diagnostics, "notes", None) or ())
    for note in est.notes:
        if note not in panel:
            st.caption(f"Note: {note}")
    _versus_default(sig, est)
    if tuning.somd:
        h = tuning.h_smooth[0]
        st.caption(
            f"The paper divides by 2; the exact factor at h_S = {h:g} is c(h) = "
            f"{somd_bias_factor(h):.4g}, so the paper's factor overstates the variance by "
            f"{somd_bias_factor(h) / 2 - 1:+.1%} (docs/algorithms.md §A8)."
        )


def _versus_default(sig: LoadedSignal, est: VarianceEstimate) -> None:
    """Why the Home and Signal pages (the default method) may show another number."""
    if est.method == DEFAULT_METHOD:
        return
    auto = None
    if sig.n <= SCAN_AUTO_LIMIT:
        try:
            auto = cache.estimate(sig, DEFAULT_METHOD, {})
        except noisevar.NoisevarError:
            auto = None
    u = signal_units()
    versus = ""
    if auto is not None:
        overlap = auto.ci95[0] <= est.ci95[1] and est.ci95[0] <= auto.ci95[1]
        versus = (
            f" There it gives std {fmt(auto.std, unit=u)} ({100 * (auto.std / est.std - 1):+.1f} %"
            f" against {fmt(est.std, unit=u)} here; the 95 % intervals "
            f"{'overlap' if overlap else 'do not overlap'})."
        )
    st.caption(
        f"The Home and Signal pages use method `{DEFAULT_METHOD}` "
        f"({describe_methods()[DEFAULT_METHOD]}); this page defaults to "
        f"`{tuned_methods()[0]}`, the paper's method, tuned step by step.{versus} Different "
        "assumptions give slightly different answers; the Compare page puts every method side "
        "by side."
    )


def _windows_kept(col: DeltaGenerator, est: VarianceEstimate) -> None:
    d = est.details
    summ = d.selection.rejection_summary()
    kept = int(d.kept_windows.sum())
    col.metric(
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


def _selected_stretch(sig: LoadedSignal) -> slice | None:
    """The stretch: a new box selection on the main chart moves the s0/s1 widgets."""
    chart_state = st.session_state.get("est_chart")
    try:
        boxes = list(chart_state["selection"]["box"]) if chart_state else []
    except (KeyError, TypeError):
        boxes = []
    if boxes:
        box = boxes[-1]
        sig_box = (round(float(box["x"][0]), 6), round(float(box["x"][1]), 6))
        if st.session_state.get("_last_box") != sig_box:
            st.session_state["_last_box"] = sig_box
            sl = range_to_slice(sig_box[0], sig_box[1], sig.n, time_of(sig))
            st.session_state["s0"], st.session_state["s1"] = sl.start, sl.stop
    s0 = int(st.session_state.get("s0", 0) or 0)
    s1 = int(st.session_state.get("s1", 0) or 0)
    return slice(min(s0, s1), max(s0, s1)) if max(s0, s1) > min(s0, s1) else None


def _signal_key(sig: LoadedSignal) -> dict[str, object]:
    """What identifies the record of a figure: its samples, table (times), column and T."""
    return {
        "digest": sig.digest,
        "table": sig.table_digest,
        "column": sig.column,
        "T": sig.sample_period,
    }


def _clear_stretch() -> None:
    st.session_state["s0"] = 0
    st.session_state["s1"] = 0


def main_figure(sig: LoadedSignal, shown: VarianceEstimate | None, tuning: Tuning) -> go.Figure:
    """The raw signal with filters and windows (box-select a stretch), and the stretch estimate."""
    stretch = _selected_stretch(sig)
    if shown is not None:
        units = signal_units()
        inputs = {
            **_signal_key(sig),
            "method": tuning.method,
            "params": tuning.params,
            "stretch": None if stretch is None else [stretch.start, stretch.stop],
            "units": units,
            "name": sig.column,
        }
        fig = cache.figure(
            "signal_filters_windows",
            inputs,
            lambda: somd_figure(
                sig.z,
                shown,
                time_of(sig),
                stretch=stretch,
                title="Raw signal, filters, windows",
                units=units,
                name=sig.column,
            ),
        )
    else:
        fig = signal_figure(
            sig.z, time_of(sig), sig.column, title="Raw signal", units=signal_units()
        )
        fig.update_layout(dragmode="select", selectdirection="h")
    st.caption(
        "Drag across the plot to estimate over a chosen stretch only (double-click clears the "
        "selection). Shaded: kept windows; marks above the record: rejected windows and why."
    )
    show_figure(fig, key="est_chart", select=True)
    n = sig.n
    c1, c2, c3 = st.columns([1, 1, 1], vertical_alignment="bottom")
    c1.number_input(
        "Stretch from sample", min_value=0, max_value=n, step=1, key="s0", bind="query-params"
    )
    c2.number_input(
        "Stretch to sample", min_value=0, max_value=n, step=1, key="s1", bind="query-params"
    )
    c3.button("Whole record", key="clear_stretch", on_click=_clear_stretch, width="stretch")
    if stretch is not None:
        _stretch_estimate(sig, tuning, stretch)
    return fig


def _stretch_estimate(sig: LoadedSignal, tuning: Tuning, stretch: slice) -> None:
    try:
        part = cache.estimate(sig, tuning.method, tuning.params, stretch=stretch)
        cols = st.columns(4)
        u = signal_units()
        cols[0].metric(
            "Stretch variance",
            fmt(part.variance, unit=squared(u)),
            help=f"samples {stretch.start} to {stretch.stop - 1}",
        )
        cols[1].metric("Stretch std", fmt(part.std, unit=u))
        cols[2].metric("95 % interval", eng_range(part.ci95[0], part.ci95[1], squared(u), 3))
        cols[3].metric("Samples in stretch", f"{stretch.stop - stretch.start:,}")
    except noisevar.NoisevarError as exc:
        reason = f"Stretch {stretch.start}–{stretch.stop - 1}: {plain(exc)}"
        # the stretch's own row says "refused": no whole-record number beside the highlight
        cols = st.columns(4)
        cols[0].metric("Stretch variance", "refused", help=reason)
        cols[1].metric("Stretch std", "refused", help=reason)
        cols[2].metric("95 % interval", "refused", help=reason)
        cols[3].metric("Samples in stretch", f"{stretch.stop - stretch.start:,}")
        st.error(f"{reason} (choose a longer stretch)")


@st.fragment
def step_views(
    sig: LoadedSignal, shown: VarianceEstimate | None, tuning: Tuning, truth: float | None
) -> None:
    """The "Step by step" figures: window tests, envelopes, h scan, per-window variance.

    A fragment: choosing another view (or running the h scan) reruns this part only.

    Notes
    -----
    No view is chosen at first: its figure is drawn only once asked for, and then again on
    every change of a control. Each Plotly figure costs the browser about a quarter of a
    CPU-s when the page opens and a tenth on each slider step (issue 29: a class of 16 on
    one 2-core machine is CPU-bound, mostly in the browsers); the main figure above shows
    the kept and rejected windows already.
    """
    view = st.segmented_control(
        "Step by step",
        VIEWS,
        key="est_view",
        bind="query-params",
        **initial("est_view", None, "default"),
    )
    if view is None:
        st.caption(f"Choose a step to see its figure: {', '.join(VIEWS)}.")
        return
    detail = None
    d = shown.details if shown is not None else None
    if view == "Window tests":
        if d is not None and d.selection is not None:
            inputs = {
                **_signal_key(sig),
                "method": tuning.method,
                "params": tuning.params,
                "gammas": [tuning.gamma_amp, tuning.gamma_ang],
            }
            detail = cache.figure(
                "window_tests",
                inputs,
                lambda: window_tests_figure(
                    d.selection,
                    tuning.gamma_amp,
                    tuning.gamma_ang,
                    sig.sample_period,
                    title="Window tests: straight (amplitude) and not lagging (angle)",
                    max_markers=WINDOW_MARKERS,
                ),
            )
        else:
            st.info("Window tests exist for the SOMD methods with window selection on.")
    elif view == "Envelopes and |V|":
        detail = _envelope_view(sig, shown, tuning.window)
    elif view == "h scan":
        detail = _scan_view(sig, shown, tuning)
    elif shown is not None:
        detail = window_variance_figure(
            shown,
            sig.sample_period,
            truth,
            title="Per-window variance and the final estimate",
        )
    if detail is not None:
        show_figure(detail, key="est_detail")
        st.caption(f"{view} figure")
        figure_downloads(detail, f"noisevar-{str(view).split()[0].lower()}", "fig_detail")


def _envelope_view(
    sig: LoadedSignal, shown: VarianceEstimate | None, window: int
) -> go.Figure | None:
    d = shown.details if shown is not None else None
    detail = None
    with guarded():
        raw_amp, det = cache.amplitude(sig, window)
        smooth_amp = None
        if d is not None:
            smooth_amp, _ = cache.amplitude(
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
        st.caption(f"Mean |V| of the raw record {fmt(raw_amp.mean_amplitude)}{ratio_txt}.")
    return detail


def _scan_view(
    sig: LoadedSignal, shown: VarianceEstimate | None, tuning: Tuning
) -> go.Figure | None:
    d = shown.details if shown is not None else None
    n, window = sig.n, tuning.window
    run_scan = n <= SCAN_AUTO_LIMIT or st.session_state.get("scan_ok") == (sig.digest, window)
    if not run_scan:
        st.info(
            f"The h scan filters the {n:,} samples once per point of its h grid: "
            "it takes several seconds on this record."
        )
        if st.button("Run the h scan", key="scan_go"):
            st.session_state["scan_ok"] = (sig.digest, window)
            run_scan = True
    if not run_scan:
        return None
    detail = None
    with guarded(), st.spinner("Scanning h..."):
        scan = cache.h_scan(sig, window)
        detail = scan_figure(
            scan,
            tuning.h_smooth if tuning.somd else (),
            d.h_track if d is not None else None,
            title="Choosing h_S: noise left after smoothing, |V1| / |V2|, against h",
        )
        in_use = f"h_S in use: {tuning.h_smooth[0]:.3g}." if tuning.somd else ""
        if math.isfinite(scan.h_min):
            st.caption(
                f"Ratio within [{RATIO_BAND[0]:g}, {RATIO_BAND[1]:g}] for h from "
                f"{scan.h_min:.3g} to {scan.h_max:.3g}; the scan suggests h = "
                f"{scan.h_chosen:.3g} (the ratio closest to the band's centre). {in_use}"
            )
        else:
            st.caption(
                f"No grid h puts the ratio inside the band; closest: {scan.h_chosen:.3g}. {in_use}"
            )
        if tuning.somd:
            st.button(
                f"Apply the suggested h_S = {scan.h_chosen:.3g}",
                key="scan_apply",
                on_click=_apply_scan_h,
                args=(scan.h_chosen,),
                icon=":material/check:",
            )
    if st.session_state.pop("_scan_applied", False):
        st.rerun()  # h_S lives outside this fragment: rerun the whole page
    return detail


def _apply_scan_h(h: float) -> None:
    st.session_state["h_s"] = closest(H_ALL, h)
    st.session_state["_scan_applied"] = True


def exports(
    sig: LoadedSignal,
    est: VarianceEstimate | None,
    truth: float | None,
    fig: go.Figure,
) -> None:
    """Downloads: the tuned-parameter JSON, the estimate and windows as CSV, the main figure.

    Lazy: built and sent only while the Export expander is open (a dozen elements less
    to send and draw on every tuning change). The step-by-step figure's downloads sit
    under it (:func:`step_views`).
    """
    label = "Export: tuned parameters, estimate, windows, report, figure"
    with lazy_expander(label, EXPORT_KEY, icon=":material/download:") as is_open:
        if is_open:
            _exports(sig, est, truth, fig)


def _exports(
    sig: LoadedSignal, est: VarianceEstimate | None, truth: float | None, fig: go.Figure
) -> None:
    if est is not None:
        _estimate_downloads(sig, est, truth)
        unit = signal_units()
        st.download_button(
            "Report of this analysis (HTML: numbers, config, figure)",
            data=lambda: report(sig, est, truth, fig, unit),
            file_name="noisevar-report.html",
            mime="text/html",
            key="dl_report",
            on_click="ignore",
            icon=":material/description:",
            width="stretch",
        )
    st.caption("Main figure")
    figure_downloads(fig, "noisevar-estimator", "fig_main")


def report(
    sig: LoadedSignal, est: VarianceEstimate, truth: float | None, fig: go.Figure, unit: str = ""
) -> str:
    """The HTML report: the verdict, the record's answer and the regime warning first, then
    the rows with human labels (:func:`~noisevar.estimators.results.row_label`) and units."""
    rows = [
        {"quantity": "signal", "value": f"{sig.label}, column {sig.column}"},
        {"quantity": "samples", "value": f"{sig.n:,}"},
        {"quantity": "units", "value": unit or "not given"},
        *(
            {"quantity": row_label(r["quantity"], unit), "value": r["value"]}
            for r in estimate_rows(est, truth)
        ),
    ]
    cfg = config_to_json(
        params_to_config(est.params["method"], est.params),
        column=sig.column,
        record=record_answer(est).summary(unit),
        time_unit=sig.time_unit,
        series=sig.series,
    )
    notes = [cli_hint(sig), cfg, *est.notes]
    said = {"regime warning": "Regime warning: ", "other still levels": "Other still levels: "}
    summary = [said.get(r["quantity"], "") + r["value"] for r in answer_rows(est, unit)]
    return html_report(f"noisevar: noise of {sig.label}", rows, [fig], notes, summary)


def estimate_csv(est: VarianceEstimate, truth: float | None, unit: str = "") -> str:
    """The Estimate CSV: the estimate's rows, then :func:`answer_rows`."""
    return rows_to_csv([*estimate_rows(est, truth), *answer_rows(est, unit)])


def answer_rows(est: VarianceEstimate, unit: str = "") -> list[dict[str, str]]:
    """The record's verdict, its answer, (when the level varies) the regime warning and the
    other still levels, as ``{"quantity", "value"}`` rows: the report's first lines and the
    Estimate CSV's last."""
    labels = {
        "verdict": "verdict",
        "answer": "record's answer",
        "regime_warning": "regime warning",
        "other_still_levels": "other still levels",
    }
    return [
        {"quantity": labels[k], "value": v} for k, v in record_answer(est).summary(unit).items()
    ]


def cli_hint(sig: LoadedSignal) -> str:
    """The command line that repeats the page's estimate on the source file."""
    name = sig.table.name if sig.source != "generated" else "yourfile.csv"
    column, name = shlex.quote(sig.column), shlex.quote(name)
    return f"noisevar estimate --config noisevar-config.json --column {column} {name}"


def _estimate_downloads(sig: LoadedSignal, est: VarianceEstimate, truth: float | None) -> None:
    c1, c2, c3 = st.columns(3)
    try:
        cfg_json = config_to_json(
            params_to_config(est.params["method"], est.params),
            column=sig.column,
            record=record_answer(est).summary(signal_units()),
            time_unit=sig.time_unit,
            series=sig.series,
        )
    except noisevar.NoisevarError as exc:  # pragma: no cover - params come from widgets
        cfg_json = None
        st.error(plain(exc))
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
            help=f"Use it with: {cli_hint(sig)}",
        )
    csv_download(
        c2,
        "Estimate (CSV)",
        data=estimate_csv(est, truth, signal_units()),
        file_name="noisevar-estimate.csv",
        key="dl_summary",
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
        st.code(cfg_json, language="json")
        st.caption(f"`{cli_hint(sig)}` gives the same estimate (the config names the column too).")

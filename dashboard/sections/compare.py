"""The Compare page's parts: every method on the signal, and the Monte Carlo comparison."""

from __future__ import annotations

import time
from collections.abc import Sequence
from dataclasses import dataclass

import pandas as pd
import plotly.graph_objects as go
import streamlit as st
from pandas.io.formats.style import Styler
from streamlit.delta_generator import DeltaGenerator

import noisevar
from dashboard import cache, workers
from dashboard.sections.estimator_tuning import tuned_methods
from dashboard.sections.noise_panel import render_assumptions, render_noise_panel
from dashboard.sections.regimes import record_answer_box
from dashboard.state import LoadedSignal, initial, times_of, truth_of
from dashboard.text import plain
from dashboard.widgets import (
    blank_frame,
    csv_download,
    figure_downloads,
    fmt,
    guarded,
    show_figure,
    show_table,
)
from noisevar.estimators.compare import (
    SLOW_METHODS,
    Comparison,
    MethodResult,
    MonteCarloResult,
    comparison_of,
    cramer_rao_floor,
    default_methods,
    rows_to_csv,
    single_signal_methods,
    slow_methods,
)
from noisevar.figures.estimator import compare_figure, monte_carlo_figure
from noisevar.signals import PAPER_SIGNAL

#: The peers' status line while their tasks wait for a place in the pool's bounded queue.
QUEUE_FULL = "waiting for a place in the worker pool's queue"
#: Number formats of the comparison table's columns.
_COMPARE_FORMATS = {
    "variance": "%.4g",
    "std": "%.4g",
    "95 % low": "%.4g",
    "95 % high": "%.4g",
    "± (rel.)": "percent",
    "rel. error": "percent",
    "time (ms)": "%.1f",
}
#: Number formats of the Monte Carlo summary's columns.
_MC_FORMATS = {
    "bias": "percent",
    "sd": "percent",
    "RMSE": "percent",
    "RMSE / CR floor": "%.2f",
    "within ±10 %": "percent",
    "max |error|": "percent",
    "ms per run": "%.2f",
}


def tuned_params(tuned: dict[str, object] | None) -> dict[str, dict[str, object]]:
    """The SOMD methods' parameters tuned on the Estimator page (empty: their defaults)."""
    return {m: dict(tuned) for m in tuned_methods()} if tuned else {}


def comparison(sig: LoadedSignal, tuned: dict[str, object] | None) -> None:
    """Choose methods; every chosen method on the signal: table, figure, downloads."""
    with guarded("Noise estimate: "):  # the record's one answer, as the Estimator page
        record_answer_box(cache.estimate(sig, cache.DEFAULT_METHOD, {}), differs="method")
    chosen = st.multiselect(
        "Methods",
        single_signal_methods(),
        key="cmp_methods",
        bind="query-params",
        format_func=lambda m: m,
        help=f"The maximum-likelihood peers ({', '.join(SLOW_METHODS)}) take seconds on long "
        "records.",
        **initial("cmp_methods", default_methods(sig.n), "default"),
    )
    if tuned:
        st.caption(
            "SOMD methods use the parameters tuned on the Estimator page: "
            + ", ".join(f"{k}={v}" for k, v in tuned.items())
        )
    else:
        st.caption("SOMD methods use their defaults (tune them on the Estimator page).")
    if any(m in SLOW_METHODS for m in chosen) and sig.n > 50_000:
        st.warning(
            f"{' and '.join(SLOW_METHODS)} take several seconds on {sig.n:,} samples; leave them "
            "out for a quick comparison."
        )
    if not chosen:
        st.info("Choose at least one method.")
        return
    params = tuned_params(tuned)
    done: dict[str, MethodResult] = {}
    fast = [m for m in chosen if m not in slow_methods()]
    with guarded(), st.spinner("Running every method..."):
        if fast:
            done.update(zip(fast, cache.fast_rows(sig, fast, params), strict=True))
    if len(done) < len(fast):
        return  # the fast rows failed: guarded() said why
    # the slow peers: rows already computed (by any session) go in the first view; the
    # others are started after it, and their rows drawn as they arrive
    pending: dict[str, workers.Started | None] = {}
    for m in chosen:
        if m not in done:
            started = cache.peer_row(sig, m, params.get(m, {}), start=False)
            if started is not None and started.done():
                with guarded(f"{m}: "):
                    done[m] = started.result()
            else:
                pending[m] = started
    _table_as_rows_arrive(sig, chosen, done, pending, params)


def _table_as_rows_arrive(
    sig: LoadedSignal,
    chosen: list[str],
    done: dict[str, MethodResult],
    pending: dict[str, workers.Started | None],
    params: dict[str, dict[str, object]],
) -> None:
    """The table (and figure) of the rows done, redrawn as each pending peer's arrives;
    the record's diagnostics once, under it; a status line while peers compute."""
    status, view, chart = st.empty(), st.empty(), st.empty()
    panel, assumptions = st.container(), st.empty()
    paneled, charted, shown, sent = False, False, None, 0.0
    while True:
        rows = [done[m] for m in chosen if m in done]
        waiting = [m for m in chosen if m in pending]
        estimates = [r.estimate for r in rows if r.estimate is not None]
        if estimates or not waiting:
            with view.container(), guarded():
                comp = comparison_of(sig.n, rows, truth_of(sig))
                # the figure: in the first view and once every row is in, not on each
                # arrival between (each draw costs the browser a quarter of a CPU-s)
                draw = not charted or not waiting
                comparison_table(comp, sig, waiting, chart if draw else None)
                charted = charted or draw
        if estimates and not paneled:  # the record's diagnostics are the same for every method
            with panel:
                st.subheader("Which numbers to trust")
                render_noise_panel(
                    sig.z, estimates[0], times_of(sig), key="cmp_np", digest=sig.digest
                )
            paneled = True
        if estimates:
            with assumptions.container():
                render_assumptions(estimates)
        if not waiting:
            status.empty()
            return
        if any(pending[m] is None for m in waiting):  # a full queue waits below
            status.caption(f"{len(waiting)} of the peers still computing: {QUEUE_FULL}")
        for m in waiting:  # started once the first view is drawn
            pending[m] = pending[m] or cache.peer_row(sig, m, params.get(m, {}))
        started = {m: task for m in waiting if (task := pending[m]) is not None}
        while not any(task.done() for task in started.values()):
            text = f"{len(started)} of the peers still computing: " + "; ".join(
                f"{m}: {task.status()}" for m, task in started.items()
            )
            if text != shown or time.monotonic() - sent >= workers.RESEND_SECONDS:
                status.caption(text)  # a rerun asked meanwhile is honoured here
                shown, sent = text, time.monotonic()
            workers.wait_any(list(started.values()), workers.POLL_SECONDS)
        for m, task in started.items():
            if task.done():
                with guarded(f"{m}: "):
                    done[m] = task.result()
                del pending[m]


def comparison_table(
    comp: Comparison,
    sig: LoadedSignal,
    waiting: Sequence[str] = (),
    chart: DeltaGenerator | None = None,
) -> None:
    """The comparison table, the Cramér-Rao floor, and in ``chart`` (a placeholder) the
    figure and the downloads; without ``chart``, the figure already drawn stays.

    ``waiting`` names methods still computing: a row each saying so, and no downloads or
    figure key until every row is in (the view is redrawn then).
    """
    frame = comparison_frame(comp, waiting)  # a failed or waiting method's cells read "—"
    show_table(frame, hide_index=True)  # drawn whole: every method visible
    truth = f" True variance {fmt(comp.true_variance)}." if comp.true_variance is not None else ""
    st.caption(
        f"Cramér-Rao floor for {sig.n:,} samples: relative sd "
        f"{100 * comp.cr_floor:.2f} % (± {196 * comp.cr_floor:.2f} % at 95 %)." + truth
    )
    if chart is None:
        return
    with chart.container():
        _figure_and_downloads(comp, sig, waiting)


def comparison_frame(comp: Comparison, waiting: Sequence[str] = ()) -> Styler:
    """The comparison table as drawn: one row per method (``waiting``: still computing),
    its numbers in their formats, and a missing cell (a failed or waiting method) as "—"."""
    rows = comp.rows()
    table = {
        "method": [r["method"] for r in rows] + list(waiting),
        "variance": [r["variance"] for r in rows] + [None] * len(waiting),
        "std": [r["std"] for r in rows] + [None] * len(waiting),
        "95 % low": [r["ci95_low"] for r in rows] + [None] * len(waiting),
        "95 % high": [r["ci95_high"] for r in rows] + [None] * len(waiting),
        "± (rel.)": [r["rel_halfwidth"] for r in rows] + [None] * len(waiting),
    }
    more = [None] * len(waiting)
    if comp.true_variance is not None:
        table["rel. error"] = [r["rel_error"] for r in rows] + more
        table["CI covers truth"] = [r["covers_truth"] for r in rows] + more
    table["samples used"] = [r["n_used"] for r in rows] + more
    table["time (ms)"] = [r["ms"] for r in rows] + more
    # never a blank or None
    table["note"] = [r["error"] or r["notes"] or "—" for r in rows] + ["computing..."] * len(
        waiting
    )
    return blank_frame(pd.DataFrame(table), formats=_COMPARE_FORMATS)


def _figure_and_downloads(comp: Comparison, sig: LoadedSignal, waiting: Sequence[str]) -> None:
    fig = compare_figure(comp, title=f"Every method on {sig.label}")
    if waiting:
        show_figure(fig)
        return
    show_figure(fig, key="cmp_chart")
    c1, c2 = st.columns([1, 2])
    csv_download(
        c1,
        "Comparison (CSV)",
        data=comp.to_csv(),
        file_name="noisevar-compare.csv",
        key="cmp_csv",
    )
    with c2:
        figure_downloads(fig, "noisevar-compare", "cmp_fig")


@dataclass
class MonteCarloSettings:
    """The Monte Carlo form's choices."""

    family: str
    n: int
    noise_std: float | None
    runs: int
    seed: int
    methods: list[str]


def monte_carlo_form(sig: LoadedSignal) -> MonteCarloSettings:
    """Scenario, samples, noise, runs, seed and methods of the Monte Carlo runs."""
    gen_default = None
    if sig.source == "generated" and sig.recipe_base:
        gen_default = sig.recipe_base.split(";")[0].split(":", 1)[1]
    names = noisevar.signal_names()
    c1, c2, c3, c4, c5 = st.columns(5)
    family = c1.selectbox(
        "Scenario",
        names,
        key="mc_signal",
        bind="query-params",
        **initial("mc_signal", names.index(gen_default or PAPER_SIGNAL), "index"),
    )
    n_mc = c2.number_input(
        "Samples per run",
        min_value=500,
        max_value=200_000,
        step=500,
        key="mc_n",
        bind="query-params",
        **initial("mc_n", 6000),
    )
    std_mc = c3.number_input(
        "Noise std (empty: default)",
        min_value=1e-6,
        max_value=1e6,
        format="%.6g",
        key="mc_std",
        bind="query-params",
        placeholder="default",
        **initial("mc_std", None),
    )
    runs = c4.number_input(
        "Runs",
        min_value=5,
        max_value=5000,
        step=50,
        key="mc_runs",
        bind="query-params",
        **initial("mc_runs", 100),
    )
    seed = c5.number_input(
        "Seed",
        min_value=0,
        max_value=2**31 - 1,
        step=1,
        key="mc_seed",
        bind="query-params",
        **initial("mc_seed", 0),
    )
    mc_methods = st.multiselect(
        "Methods",
        single_signal_methods(),
        key="mc_methods",
        bind="query-params",
        help=f"{' and '.join(SLOW_METHODS)} are left out by default: a state-space fit per run.",
        **initial("mc_methods", default_methods(6000, monte_carlo=True), "default"),
    )
    return MonteCarloSettings(family, int(n_mc), std_mc, int(runs), int(seed), mc_methods)


def monte_carlo_runs(mc: MonteCarloSettings, tuned: dict[str, object] | None) -> bool:
    """Run / Cancel buttons and the run with live progress; True when Cancel was pressed.

    The latest snapshot is kept in ``st.session_state["mc_result"]``, so an interrupted
    run keeps the runs done.
    """
    b1, b2, _ = st.columns([1, 1, 3])
    go = b1.button(
        "Run Monte Carlo",
        key="mc_go",
        type="primary",
        icon=":material/play_arrow:",
        disabled=not mc.methods,
        width="stretch",
    )
    cancel = b2.button("Cancel", key="mc_cancel", icon=":material/stop:", width="stretch")
    status = st.empty()
    live = st.empty()
    if st.session_state.get("mc_running") and not go:
        # the run was interrupted: by Cancel, or by another widget (a rerun stops the script)
        st.session_state["mc_running"] = False
        last = st.session_state.get("mc_result")
        done = f" after {last.runs_done} of {last.runs_requested} runs" if last else ""
        why = "cancelled" if cancel else "interrupted by a change on the page"
        status.warning(f"Monte Carlo {why}{done}; the partial results are shown.")
    if go and mc.methods:
        _run(mc, tuned, status, live)
    return cancel


def _run(
    mc: MonteCarloSettings,
    tuned: dict[str, object] | None,
    status: DeltaGenerator,
    live: DeltaGenerator,
) -> None:
    st.session_state["mc_running"] = True
    st.session_state.pop("mc_result", None)
    gen = workers.monte_carlo_chunks(  # on the worker pool (dashboard/workers.py)
        show=status.caption,
        signal=mc.family,
        runs=mc.runs,
        methods=mc.methods,
        params=tuned_params(tuned),
        n=mc.n,
        noise_std=mc.noise_std,
        seed=mc.seed,
    )
    every = max(1, mc.runs // 10)
    ended = False  # stays False when Streamlit interrupts the loop (Cancel): see above
    try:
        bar = status.progress(0.0, text="Starting...")
        for snap in gen:
            st.session_state["mc_result"] = snap
            bar.progress(
                snap.fraction_done,
                text=f"Run {snap.runs_done} of {snap.runs_requested} (Cancel stops here)",
            )
            if snap.runs_done % every == 0 and not snap.finished:
                show_figure(
                    monte_carlo_figure(snap, title="Relative errors so far"),
                    key=f"mc_live_{snap.runs_done}",
                    where=live,
                )
        ended = True
        status.success(f"Monte Carlo done: {mc.runs} runs.")
    except noisevar.NoisevarError as exc:
        ended = True
        status.error(plain(exc))
    finally:
        gen.close()
        if ended:
            st.session_state["mc_running"] = False
    live.empty()


def monte_carlo_results(cancelled: bool) -> None:
    """The kept Monte Carlo result: summary table, Fig. 2 histograms, downloads."""
    res: MonteCarloResult | None = st.session_state.get("mc_result")
    if res is None:
        st.info("Press **Run Monte Carlo** to start (Cancel stops it and keeps the runs done).")
        return
    if not res.finished and not cancelled:
        st.caption(f"Partial result: {res.runs_done} of {res.runs_requested} runs.")
    st.markdown(
        f"**{res.signal}**, n = {res.n:,}, {res.runs_done} runs, true variance "
        f"{fmt(res.true_variance)}; Cramér-Rao floor "
        f"{100 * cramer_rao_floor(res.n):.2f} % relative sd."
    )
    summary = res.summary()
    st.caption(
        "Parameters in use: "
        + "; ".join(f"{r['method']}: {r['params']}" for r in summary)
        + (" (tuned on the Estimator page)" if any(res.params.values()) else "")
    )
    columns = {
        "method": "method",
        "status": "status",
        "bias": "bias",
        "sd": "sd",
        "RMSE": "rmse",
        "RMSE / CR floor": "rmse_over_cr",
        "within ±10 %": "within_10pct",
        "max |error|": "max_abs",
        "failures": "failures",
        "ms per run": "ms_per_run",
        "parameters": "params",
    }
    frame = pd.DataFrame({label: [r[k] for r in summary] for label, k in columns.items()})
    show_table(blank_frame(frame, formats=_MC_FORMATS), hide_index=True)
    for m, msg in res.first_error.items():
        st.caption(f"{m} failed {res.failures[m]} times; first: {msg}")
    mc_fig = monte_carlo_figure(res, title="Relative error of the variance (the paper's Fig. 2)")
    show_figure(mc_fig, key="mc_chart")
    _monte_carlo_downloads(res, summary, mc_fig)


def _monte_carlo_downloads(
    res: MonteCarloResult, summary: list[dict[str, object]], mc_fig: go.Figure
) -> None:
    c1, c2, c3 = st.columns([1, 1, 2])
    csv_download(
        c1,
        "Summary (CSV)",
        data=rows_to_csv(summary),
        file_name="noisevar-montecarlo-summary.csv",
        key="mc_csv_summary",
    )
    c2.download_button(
        "Every run (CSV)",
        data=lambda: res.to_csv(),
        file_name="noisevar-montecarlo-runs.csv",
        mime="text/csv",
        key="mc_csv_runs",
        on_click="ignore",
        icon=":material/view_list:",
        width="stretch",
    )
    with c3:
        figure_downloads(mc_fig, "noisevar-montecarlo", "mc_fig")

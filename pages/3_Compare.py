"""Compare page: every method on the signal; Monte Carlo relative errors against the CR floor."""

from __future__ import annotations

import streamlit as st

import dashboard_common as dc
import noisevar
from noisevar.estimators.compare import (
    SLOW_METHODS,
    cramer_rao_floor,
    default_methods,
    monte_carlo,
    rows_to_csv,
    single_signal_methods,
)
from noisevar.figures.estimator import compare_figure, monte_carlo_figure

#: The page's how-it-works expander (shown even before a signal is loaded).
HOW_IT_WORKS = (
    "**Peers (spec D).** Difference estimators remove the slowly varying signal with a short "
    "difference sequence $d$ and normalise by its energy:",
    "$$\\hat\\sigma^2 = \\frac{\\operatorname{mean}\\big((d * z)_k^2\\big)}{\\sum_j d_j^2},\\qquad"
    "\\text{Rice: } d = (1,-1),\\quad \\text{second difference: } d = (1,-2,1)$$",
    "Hall-Kay-Titterington sequences are the optimal $d$ of each order; MAD versions replace the "
    "mean square by a median ($\\hat\\sigma = \\operatorname{median}|x - \\tilde x| / 0.6745$) "
    "and ignore jumps; the wavelet estimator takes the MAD of the finest wavelet details; "
    "the maximum-likelihood peers fit a state-space model (local level / local linear trend) "
    "and read its irregular variance.",
    "**Intervals.** Each method's 95 % interval is a chi-square interval with its effective "
    "degrees of freedom $\\nu$ (for a mean of correlated squares "
    "$\\nu = n / \\sum_k \\rho_k^2$):",
    "$$\\left[\\frac{\\nu\\hat\\sigma^2}{\\chi^2_{0.975,\\nu}},\\;"
    "\\frac{\\nu\\hat\\sigma^2}{\\chi^2_{0.025,\\nu}}\\right]$$",
    "**Monte Carlo.** The relative error of run $i$ is $e_i = \\hat\\sigma_i^2/\\sigma^2 - 1$. "
    "No unbiased estimator from $n$ Gaussian samples does better than the Cramér-Rao floor",
    "$$\\operatorname{sd}(e) \\ge \\sqrt{2/n}$$",
    "so the column *RMSE / CR floor* says how many times worse than ideal each method is. The "
    "paper's criterion for Fig. 2: 95 % of the relative errors within 10 %, none above 20 %.",
)

dc.setup_page("Compare", ":material/leaderboard:")
st.title("Compare")
sig = dc.require_signal(
    "The Compare page runs every estimator on it side by side.", explain=HOW_IT_WORKS
)

ALL = single_signal_methods()
DESC = noisevar.describe_methods()
tuned = st.session_state.get("nv_tuned")

tab_one, tab_mc = st.tabs(["On this signal", "Monte Carlo"], key="cmp_tab", bind="query-params")

# ------------------------------------------------------------- this signal
with tab_one:
    defaults = default_methods(sig.n)
    chosen = st.multiselect(
        "Methods",
        ALL,
        key="cmp_methods",
        bind="query-params",
        format_func=lambda m: m,
        help="The maximum-likelihood peers (mle-*) take seconds on long records.",
        **dc.initial("cmp_methods", defaults, "default"),
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
            f"The mle-* methods take several seconds on {sig.n:,} samples; leave them out for "
            "a quick comparison."
        )
    if not chosen:
        st.info("Choose at least one method.")
    else:
        params = {m: dict(tuned) for m in ("somd", "somd-paper")} if tuned else {}
        comp = None
        with dc.guarded(), st.spinner("Running every method..."):
            comp = dc.compare(sig, chosen, params)
        if comp is not None:
            rows = comp.rows()
            table = {
                "method": [r["method"] for r in rows],
                "variance": [r["variance"] for r in rows],
                "std": [r["std"] for r in rows],
                "95 % low": [r["ci95_low"] for r in rows],
                "95 % high": [r["ci95_high"] for r in rows],
                "± (rel.)": [r["rel_halfwidth"] for r in rows],
            }
            if comp.true_variance is not None:
                table["rel. error"] = [r["rel_error"] for r in rows]
                table["CI covers truth"] = [r["covers_truth"] for r in rows]
            table["samples used"] = [r["n_used"] for r in rows]
            table["time (ms)"] = [r["ms"] for r in rows]
            table["note"] = [r["note"] for r in rows]
            st.dataframe(
                table,
                hide_index=True,
                column_config={
                    "variance": st.column_config.NumberColumn(format="%.4g"),
                    "std": st.column_config.NumberColumn(format="%.4g"),
                    "95 % low": st.column_config.NumberColumn(format="%.4g"),
                    "95 % high": st.column_config.NumberColumn(format="%.4g"),
                    "± (rel.)": st.column_config.NumberColumn(format="percent"),
                    "rel. error": st.column_config.NumberColumn(format="percent"),
                    "time (ms)": st.column_config.NumberColumn(format="%.1f"),
                },
            )
            st.caption(
                f"Cramér-Rao floor for {sig.n:,} samples: relative sd "
                f"{100 * comp.cr_floor:.2f} % (± {196 * comp.cr_floor:.2f} % at 95 %)."
                + (
                    f" True variance {dc.fmt(comp.true_variance)}."
                    if comp.true_variance is not None
                    else ""
                )
            )
            fig = compare_figure(comp, title=f"Every method on {sig.label}")
            dc.show_figure(fig, key="cmp_chart")
            c1, c2 = st.columns([1, 2])
            c1.download_button(
                "Comparison (CSV)",
                data=comp.to_csv(),
                file_name="noisevar-compare.csv",
                mime="text/csv",
                key="cmp_csv",
                on_click="ignore",
                icon=":material/table:",
                width="stretch",
            )
            with c2:
                dc.figure_downloads(fig, "noisevar-compare", "cmp_fig")

# -------------------------------------------------------------- Monte Carlo
with tab_mc:
    st.caption(
        "Monte Carlo runs on a generated scenario: each run draws fresh noise (seed + run "
        "index) and every method estimates the variance; the histograms of relative errors "
        "are the paper's Fig. 2, drawn against the best possible estimator (Cramér-Rao)."
    )
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
        **dc.initial("mc_signal", names.index(gen_default or "fast-slow"), "index"),
    )
    n_mc = c2.number_input(
        "Samples per run",
        min_value=500,
        max_value=200_000,
        step=500,
        key="mc_n",
        bind="query-params",
        **dc.initial("mc_n", 6000),
    )
    std_mc = c3.number_input(
        "Noise std (empty: default)",
        min_value=1e-6,
        max_value=1e6,
        format="%g",
        key="mc_std",
        bind="query-params",
        placeholder="default",
        **dc.initial("mc_std", None),
    )
    runs = c4.number_input(
        "Runs",
        min_value=5,
        max_value=5000,
        step=50,
        key="mc_runs",
        bind="query-params",
        **dc.initial("mc_runs", 100),
    )
    seed = c5.number_input(
        "Seed",
        min_value=0,
        max_value=2**31 - 1,
        step=1,
        key="mc_seed",
        bind="query-params",
        **dc.initial("mc_seed", 0),
    )
    mc_methods = st.multiselect(
        "Methods",
        ALL,
        key="mc_methods",
        bind="query-params",
        help="mle-* are left out by default: about 0.4 s per run each.",
        **dc.initial("mc_methods", default_methods(6000, monte_carlo=True), "default"),
    )
    b1, b2, _ = st.columns([1, 1, 3])
    go = b1.button(
        "Run Monte Carlo",
        key="mc_go",
        type="primary",
        icon=":material/play_arrow:",
        disabled=not mc_methods,
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
    if go and mc_methods:
        params = {m: dict(tuned) for m in ("somd", "somd-paper")} if tuned else {}
        st.session_state["mc_running"] = True
        st.session_state.pop("mc_result", None)
        gen = monte_carlo(
            family,
            runs=int(runs),
            methods=mc_methods,
            params=params,
            n=int(n_mc),
            noise_std=std_mc,
            seed=int(seed),
        )
        every = max(1, int(runs) // 10)
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
                    live.plotly_chart(
                        monte_carlo_figure(snap, title="Relative errors so far"),
                        width="stretch",
                        key=f"mc_live_{snap.runs_done}",
                    )
            ended = True
            status.success(f"Monte Carlo done: {int(runs)} runs.")
        except noisevar.NoisevarError as exc:
            ended = True
            status.error(str(exc))
        finally:
            gen.close()
            if ended:
                st.session_state["mc_running"] = False
        live.empty()
    res = st.session_state.get("mc_result")
    if res is None:
        st.info("Press **Run Monte Carlo** to start (Cancel stops it and keeps the runs done).")
    else:
        if not res.finished and not cancel:
            st.caption(f"Partial result: {res.runs_done} of {res.runs_requested} runs.")
        st.markdown(
            f"**{res.signal}**, n = {res.n:,}, {res.runs_done} runs, true variance "
            f"{dc.fmt(res.true_variance)}; Cramér-Rao floor "
            f"{100 * cramer_rao_floor(res.n):.2f} % relative sd."
        )
        summary = res.summary()
        st.dataframe(
            {
                "method": [r["method"] for r in summary],
                "bias": [r["bias"] for r in summary],
                "sd": [r["sd"] for r in summary],
                "RMSE": [r["rmse"] for r in summary],
                "RMSE / CR floor": [r["rmse_over_cr"] for r in summary],
                "within ±10 %": [r["within_10pct"] for r in summary],
                "max |error|": [r["max_abs"] for r in summary],
                "failures": [r["failures"] for r in summary],
                "ms per run": [r["ms_per_run"] for r in summary],
            },
            hide_index=True,
            column_config={
                "bias": st.column_config.NumberColumn(format="percent"),
                "sd": st.column_config.NumberColumn(format="percent"),
                "RMSE": st.column_config.NumberColumn(format="percent"),
                "RMSE / CR floor": st.column_config.NumberColumn(format="%.2f"),
                "within ±10 %": st.column_config.NumberColumn(format="percent"),
                "max |error|": st.column_config.NumberColumn(format="percent"),
                "ms per run": st.column_config.NumberColumn(format="%.2f"),
            },
        )
        for m, msg in res.first_error.items():
            st.caption(f"{m} failed {res.failures[m]} times; first: {msg}")
        mc_fig = monte_carlo_figure(
            res, title="Relative error of the variance (the paper's Fig. 2)"
        )
        dc.show_figure(mc_fig, key="mc_chart")
        c1, c2, c3 = st.columns([1, 1, 2])
        c1.download_button(
            "Summary (CSV)",
            data=rows_to_csv(summary),
            file_name="noisevar-montecarlo-summary.csv",
            mime="text/csv",
            key="mc_csv_summary",
            on_click="ignore",
            icon=":material/table:",
            width="stretch",
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
            dc.figure_downloads(mc_fig, "noisevar-montecarlo", "mc_fig")

dc.how_it_works(*HOW_IT_WORKS)

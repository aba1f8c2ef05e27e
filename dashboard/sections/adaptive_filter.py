"""The Adaptive filter page's parts: strategies and settings, the data, the results, Table 1."""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import Any

import numpy as np
import plotly.graph_objects as go
import streamlit as st

from dashboard import cache
from dashboard.sections.regimes import record_answer_box
from dashboard.sections.signal_loader import require_signal
from dashboard.state import follow_table, initial, keep_valid
from dashboard.widgets import (
    fmt,
    glossary,
    guarded,
    h_grid,
    show_figure,
    show_table,
    table_and_figure_downloads,
)
from noisevar.estimators.answer import WHY_DIFFERENT
from noisevar.estimators.compare import rows_to_csv
from noisevar.figures.kalman import (
    innovations_figure,
    r_estimates_figure,
    states_figure,
    track_figure,
)
from noisevar.kalman import STRATEGIES, HuberUpdate
from noisevar.kalman.evaluation import filter_summary
from noisevar.kalman.result import FilterResult
from noisevar.params import ParamSpec
from noisevar.systems.scenarios import GPS_DURATION, SCENARIOS

VIEWS = ["Track", "States", "R estimates", "Innovations and NIS"]
#: The strategies picked at first: the registry's featured ones.
DEFAULT_STRATEGIES = [name for name, spec in STRATEGIES.items() if spec.featured]


@dataclass
class FilterRuns:
    """The filters run on the page's data, and what the figures need to draw them."""

    results: list[FilterResult] = field(default_factory=list)
    truth_R: np.ndarray | None = None
    z_shown: np.ndarray | None = None
    groups: dict[str, tuple[int, ...]] | None = None
    track_states: tuple[int, int] | None = None
    track_channels: tuple[int, int] | None = None
    title: str = ""


def strategy_picker(is_scenario: bool) -> list[str]:
    """The strategies to run (one that needs the true R needs a scenario's truth)."""
    names = [s for s, spec in STRATEGIES.items() if is_scenario or "R_true" not in spec.needs]
    default = [s for s in DEFAULT_STRATEGIES if s in names]
    keep_valid("af_strats", lambda v: all(s in names for s in v), default)
    picked = st.multiselect(
        "Strategies",
        names,
        key="af_strats",
        bind="query-params",
        # the chip shows the name only (a chip with its description is cut on a phone);
        # the descriptions are in the help and under the widget
        help="\n".join(f"- **{s}**: {STRATEGIES[s].help}" for s in names),
        **initial("af_strats", default, "default"),
    )
    if picked:
        st.caption("  \n".join(f"**{s}**: {STRATEGIES[s].help}" for s in picked))
    return picked


#: The page's widget for each strategy parameter it offers, one value for every strategy
#: that takes it: (widget key, label, the widget's range and step). An integer parameter
#: gets a number input, a real one a slider; the default is the registry's.
SETTING_WIDGETS: dict[str, tuple[str, str, dict[str, Any]]] = {
    "window": ("af_window", "RAE/IAE window N", {"min_value": 5, "max_value": 1000}),
    "forgetting": (
        "af_b",
        "Sage-Husa b",
        {"min_value": 0.90, "max_value": 0.999, "step": 0.001, "format": "%.3f"},
    ),
    "rho": (
        "af_rho",
        "VB ρ",
        {"min_value": 0.90, "max_value": 1.0, "step": 0.005, "format": "%.3f"},
    ),
    "every": ("af_every", "SOMD every N steps", {"min_value": 10, "max_value": 2000, "step": 10}),
}


def tunable_spec(name: str) -> ParamSpec:
    """The registry's spec of a strategy parameter: the first one with a default."""
    return next(
        p
        for spec in STRATEGIES.values()
        for p in spec.params
        if p.name == name and p.default is not None
    )


def strategy_settings() -> tuple[cache.Settings, float | None]:
    """The strategies' tunable settings and the Huber κ (None: plain update)."""
    settings: cache.Settings = {}
    with st.expander("Strategy settings"):
        *cols, last = st.columns(len(SETTING_WIDGETS) + 1)
        for (name, (key, label, widget)), col in zip(SETTING_WIDGETS.items(), cols, strict=True):
            spec = tunable_spec(name)
            draw = col.number_input if spec.kind == "int" else col.slider
            value = draw(
                label, key=key, bind="query-params", **widget, **initial(key, spec.default)
            )
            settings[name] = int(value) if spec.kind == "int" else float(value)
        huber = last.toggle(
            f"Huber update (κ = {HuberUpdate.kappa:g})",
            key="af_huber",
            bind="query-params",
            help="Robust M-estimation update (docs/algorithms.md §B3); works with every strategy.",
        )
    return settings, (HuberUpdate.kappa if huber else None)


#: The page's sliders for the scenario parameters it offers, when a scenario takes them:
#: (widget key, label, lowest, highest, step); the default is the scenario's own.
SCENARIO_WIDGETS = {
    "duration": ("af_duration", "Duration (s)", 100.0, 3000.0, 100.0),
    "n_steps": ("af_steps", "Steps", 500, 6000, 500),
    "factor": ("af_factor", "Noise increase (×)", 1.0, 10.0, 0.5),
}


def _scenario_form() -> tuple[str, int, dict[str, float | int]]:
    """Scenario, seed, and the scenario's own parameters the page offers (its signature's)."""
    c1, c2, *cols = st.columns(4)
    scen = c1.selectbox("Scenario", list(SCENARIOS), key="af_scenario", bind="query-params")
    seed = c2.number_input(
        "Seed", 0, 2**31 - 1, step=1, key="af_seed", bind="query-params", **initial("af_seed", 0)
    )
    defaults = cache.scenario_defaults(scen)
    offered = [p for p in SCENARIO_WIDGETS if p in defaults]
    params: dict[str, float | int] = {}
    for name, col in zip(offered, cols, strict=False):
        key, label, lo, hi, step = SCENARIO_WIDGETS[name]
        params[name] = col.slider(
            label, lo, hi, step=step, key=key, bind="query-params", **initial(key, defaults[name])
        )
    return scen, int(seed), params


def on_scenario(strategies: list[str], settings: cache.Settings, kappa: float | None) -> FilterRuns:
    """Run the strategies on a seeded scenario (with truth)."""
    scen, seed, params = _scenario_form()
    runs = FilterRuns()
    sc = None
    with guarded():
        sc = cache.kalman_scenario(scen, seed, cache.params_key(params))
    if sc is None:
        return runs
    st.caption(sc.description)
    key = f"{scen}|{seed}|{cache.params_key(params)}"
    with st.spinner("Filtering..."):
        for s in strategies:
            with guarded(f"{s}: "):
                runs.results.append(cache.scenario_run(sc, key, s, settings, kappa))
    runs.truth_R = sc.R_true[sc.first_step :]
    runs.z_shown = sc.z[:, sc.first_step :]
    runs.groups = sc.state_groups or None
    runs.track_states = next(iter(runs.groups.values()))[:2] if runs.groups else (0, 1)
    runs.track_channels = (0, 1)
    runs.title = scen
    return runs


def _data_form(usable: list[str], pick_default: list[str]) -> tuple[list[str], float, float, float]:
    """Channels, model h, initial-R factor and SOMD h_S for the loaded data."""
    c1, c2, c3, c4 = st.columns(4)
    chosen = c1.multiselect(
        "Channels",
        usable,
        key="af_cols",
        max_selections=6,
        **initial("af_cols", pick_default, "default"),
    )
    h_model = c2.select_slider(
        "Model h = q T³ / r",
        h_grid(1e-9, 1e-1),
        key="af_h",
        bind="query-params",
        help="White-acceleration level of the constant-velocity model per channel, relative "
        "to its noise (unit-free, like the alpha-beta-gamma h).",
        **initial("af_h", "0.001"),
    )
    r0_factor = c3.select_slider(
        "Initial R (× quick estimate)",
        [0.1, 0.25, 0.5, 1.0, 2.0, 4.0, 10.0, 100.0],
        key="af_r0",
        bind="query-params",
        **initial("af_r0", 4.0),
        help="The filters start from this R to show how they adapt.",
    )
    h_somd = c4.select_slider(
        "SOMD h_S",
        h_grid(1e-9, 3e-3),
        key="af_hs",
        bind="query-params",
        **initial("af_hs", "0.001"),
    )
    return chosen, float(h_model), float(r0_factor), float(h_somd)


def on_loaded_data(
    strategies: list[str], settings: cache.Settings, kappa: float | None, explain: tuple[str, ...]
) -> FilterRuns:
    """Run the strategies on chosen columns of the loaded file (no truth)."""
    sig = require_signal(
        "The Adaptive filter page filters the columns of the loaded file.",
        preferred=("gps_circle.csv", "gps_track.nmea", "two_sensors.csv"),
        explain=explain,
    )
    cols = sig.table.data_columns
    usable = [c for c in cols if np.all(np.isfinite(sig.table.columns[c]))]
    pick_default = usable[:2] if len(usable) >= 2 else usable[:1]
    follow_table("af_table", "af_cols", sig.table_digest, pick_default)
    keep_valid("af_cols", lambda v: all(c in usable for c in v), pick_default)
    chosen, h_model, r0_factor, h_somd = _data_form(usable, pick_default)
    settings["h_smooth"] = h_somd
    runs = FilterRuns(title=sig.label)
    if not chosen:
        st.info("Pick at least one channel.")
        return runs
    quick = None
    with st.spinner("Filtering..."):
        for s in strategies:
            with guarded(f"{s}: "):
                res, z, quick = cache.data_run(sig, chosen, h_model, r0_factor, s, settings, kappa)
                runs.results.append(res)
                runs.z_shown = z
    if quick is not None:
        st.caption(
            f"Quick single-signal estimates (method {cache.DEFAULT_METHOD}) per channel: "
            + ", ".join(f"{c} {fmt(v)}" for c, v in zip(chosen, quick, strict=True))
            + " — drawn as the reference line of the R panels."
        )
        runs.truth_R = np.asarray(quick)
        for c in chosen:  # each channel's record answer: its verdict and regime warning
            with guarded(f"{c}: "):
                record_answer_box(cache.column_estimate(sig, c), name=c)
        st.caption(f"The filters' R differ from these: {WHY_DIFFERENT['filter']}.")
    if len(chosen) >= 2:
        runs.track_states, runs.track_channels = (0, 2), (0, 1)
    return runs


def results_view(runs: FilterRuns, is_scenario: bool) -> None:
    """The filter table (RMSE, NIS), the chosen figure and the downloads."""
    results = runs.results
    rows = [filter_summary(r, runs.groups) for r in results]
    show_table(rows, hide_index=True)
    glossary("NIS", "NEES", "RMSE")
    st.caption(
        "Mean NIS near the number of channels m means the filter's innovations match its "
        "covariance (consistent); far above, it is over-confident (R too small)."
    )
    view = st.segmented_control(
        "Figure",
        VIEWS,
        key="af_view",
        bind="query-params",
        **initial("af_view", VIEWS[0] if runs.track_states else VIEWS[2], "default"),
    )
    fig = None
    with guarded():
        fig = _figure(view or VIEWS[2], runs, is_scenario)
    if fig is not None:
        show_figure(fig, key="af_chart")
    table_and_figure_downloads(
        "Filter table (CSV)",
        rows,
        "noisevar-filters.csv",
        "af_csv",
        fig,
        "noisevar-filter",
        "af_fig",
    )


def _figure(view: str, runs: FilterRuns, is_scenario: bool) -> go.Figure | None:
    results = runs.results
    if view == "Track":
        if runs.track_states is None:
            st.info("The track needs two position channels: pick two channels.")
            return None
        return track_figure(
            results,
            runs.z_shown,
            states=runs.track_states,
            channels=runs.track_channels,
            title=f"Track: {runs.title}",
        )
    if view == "States":
        errors = st.toggle(
            "Errors with ±2σ bands", key="af_errors", disabled=results[0].truth is None
        )
        return states_figure(results, errors=bool(errors), title="States")
    if view == "R estimates":
        return r_estimates_figure(
            results,
            R_true=runs.truth_R,
            title="R̂ per channel (log scale) against the true value"
            if is_scenario
            else "R̂ per channel (log scale) against a quick estimate",
            reference_name="true R"
            if is_scenario
            else f"quick estimate of R (method {cache.DEFAULT_METHOD})",
        )
    which = st.selectbox("Filter", [r.strategy for r in results], key="af_innov")
    return innovations_figure(next(r for r in results if r.strategy == which))


def table1_panel() -> None:
    """The paper's Table 1 (gps-circle), run on request with chosen runs and seed."""
    with st.expander("The paper's Table 1, reproduced on demand (gps-circle)"):
        st.caption(
            "Noise variance of each GPS channel: the paper's SOMD and RAE beside ours, averaged "
            f"over Monte Carlo runs of the full {GPS_DURATION:g} s scenario (seconds per run)."
        )
        c1, c2, c3 = st.columns([1, 1, 2], vertical_alignment="bottom")
        t_runs = c1.number_input("Runs", 1, 100, key="t1_runs", **initial("t1_runs", 5))
        t_seed = c2.number_input("Seed", 0, 2**31 - 1, key="t1_seed", **initial("t1_seed", 0))
        if c3.button("Reproduce Table 1", key="t1_go", icon=":material/play_arrow:"):
            st.session_state["t1_ask"] = (int(t_runs), int(t_seed))
        ask = st.session_state.get("t1_ask")
        if not ask:
            return
        res1 = None
        with guarded(), st.spinner(f"Running {ask[0]} runs of every filter..."):
            res1 = cache.table1(*ask)
        if res1 is not None:
            _table1(res1, ask)


def _table1(res1: cache.JsonDict, ask: tuple[int, int]) -> None:
    chans = list(res1["channels"])
    table = [
        {"row": "true", **{c: res1["channels"][c]["true"] for c in chans}},
    ]
    for key in res1["channels"][chans[0]]["paper"]:  # the paper's rows, in its order
        table.append(
            {"row": f"paper {key.upper()}", **{c: res1["channels"][c]["paper"][key] for c in chans}}
        )
    for m in res1["channels"][chans[0]]["methods"]:
        table.append({"row": m, **{c: res1["channels"][c]["methods"][m]["mean"] for c in chans}})
    st.markdown(f"**Noise variance per channel** ({ask[0]} runs, seed {ask[1]})")
    show_table(table, hide_index=True)
    rm = [
        {
            "filter": k,
            **v,
            "diverged": f"{res1['divergence'][k]['runs']}/{res1['divergence'][k]['of']}",
        }
        for k, v in res1["rmse"].items()
    ]
    st.markdown("**RMSE over runs and steps**")
    show_table(rm, hide_index=True)
    st.caption(
        "diverged: runs in which the filter's NEES left its chi-square band, i.e. its claimed "
        "covariance P became too small for its actual errors. That judges the filter's "
        "confidence, not its accuracy: a filter can keep an RMSE close to the best and still be "
        "over-confident."
    )
    glossary("NEES", "RMSE")
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

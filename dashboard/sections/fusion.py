"""The Fusion page's parts: the scenario form and the fused results (docs/algorithms.md §B2)."""

from __future__ import annotations

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
from noisevar.figures.fusion import error_figure, isolation_figure, r_track_figure, track_figure
from noisevar.format import percent
from noisevar.kalman import STRATEGIES
from noisevar.systems.fusion import (
    ADAPTIVE_LOCAL,
    FAULTS,
    LOCAL_STRATEGIES,
    NOISE_FAULTS,
    FusionData,
    FusionResult,
    FusionScenario,
)

#: Each local filter, without and with chi-square isolation (``run_fusion``'s arguments).
CONFIGS = [*LOCAL_STRATEGIES, *(f"{local}+isolation" for local in LOCAL_STRATEGIES)]
#: Shown at first: every configuration whose local filter needs no truth.
DEFAULT_CONFIGS = [c for c in CONFIGS if "R_true" not in STRATEGIES[c.partition("+")[0]].needs]
#: The scenario's defaults (fault sizes).
SCENARIO = FusionScenario()
VIEWS = ["Track", "Position error", "VB estimate of R", "Isolation test"]


@dataclass
class FusionSettings:
    """The page's choices."""

    fault: str
    steps: int
    runs: int
    seed: int
    factor: float
    bias: float
    false_alarm: float
    configs: list[str]

    @property
    def data_key(self) -> str:
        """The cache key of the simulated data."""
        return f"{self.fault}|{self.steps}|{self.runs}|{self.seed}|{self.factor}|{self.bias}"


def settings_form() -> FusionSettings:
    """Fault, steps, runs, seed, fault size, false-alarm probability, configurations."""
    c1, c2, c3, c4 = st.columns(4)
    fault = c1.selectbox(
        "Fault of sensor 1",
        FAULTS,
        key="fu_fault",
        bind="query-params",
        **initial("fu_fault", list(FAULTS).index("bias"), "index"),
    )
    steps = c2.slider(
        "Steps (1 s)",
        100,
        2000,
        step=100,
        key="fu_steps",
        bind="query-params",
        **initial("fu_steps", 600),
    )
    runs = c3.slider(
        "Monte Carlo runs", 1, 50, key="fu_runs", bind="query-params", **initial("fu_runs", 10)
    )
    seed = c4.number_input(
        "Seed", 0, 2**31 - 1, key="fu_seed", bind="query-params", **initial("fu_seed", 0)
    )
    c1, c2, c3 = st.columns(3)
    factor = c1.slider(
        "Noise increase (×, step / ramp)",
        1.0,
        10.0,
        step=0.5,
        key="fu_factor",
        bind="query-params",
        disabled=fault not in NOISE_FAULTS,
        **initial("fu_factor", SCENARIO.noise_factor),
    )
    bias = c2.slider(
        "Bias (noise standard deviations)",
        2.0,
        50.0,
        step=1.0,
        key="fu_bias",
        bind="query-params",
        disabled=fault != "bias",
        **initial("fu_bias", SCENARIO.bias_sigmas),
    )
    false_alarm = c3.select_slider(
        "Chi-square false-alarm probability",
        [1e-6, 1e-5, 1e-4, 1e-3, 1e-2, 5e-2],
        key="fu_fa",
        bind="query-params",
        **initial("fu_fa", 1e-3),
    )
    configs = st.multiselect(
        "Fusion configurations (local R [+ isolation])",
        CONFIGS,
        key="fu_configs",
        bind="query-params",
        **initial("fu_configs", DEFAULT_CONFIGS, "default"),
    )
    return FusionSettings(fault, steps, runs, seed, factor, bias, false_alarm, configs)


def fusion_row(result: FusionResult) -> dict[str, object]:
    """A row of the fusion table: position RMSE and, with isolation, how often sensor 1 was cut."""
    row: dict[str, object] = {"configuration": result.label, "position RMSE (m)": result.rmse()}
    if "+isolation" in result.label:
        in_fault, healthy = result.isolated_fraction(0)
        row["sensor 1 isolated in fault"] = in_fault
        row["sensor 1 isolated when healthy"] = healthy
    return row


def fused_results(s: FusionSettings) -> None:
    """Run the configurations; the equivalence check, the table, a figure, the downloads."""
    data: FusionData | None = None
    with guarded():
        data = cache.fusion_data(s.fault, s.steps, s.runs, s.seed, s.factor, s.bias)
    if data is None:
        return
    results = []
    with st.spinner("Fusing..."):
        for cfg in s.configs:
            with guarded(f"{cfg}: "):
                results.append(cache.fusion_run(data, s.data_key, cfg, s.false_alarm))
        diff = None
        with guarded():
            diff = cache.fusion_equivalence(data, s.data_key)
    if diff is not None:
        st.metric(
            "Distributed (fixed R, eq. 24) vs centralised Kalman filter: largest |Δx|",
            f"{diff:.2e}",
            help="The information-form fusion equals the centralised filter, to rounding "
            "(docs/algorithms.md §G6).",
        )
    if not results:
        st.info("Pick at least one configuration.")
        return
    rows = [fusion_row(r) for r in results]
    isolated = ("sensor 1 isolated in fault", "sensor 1 isolated when healthy")
    shown = [dict(r) for r in rows]
    for row in shown:  # a configuration without isolation: said, not a "None" cell
        for k in isolated:
            row[k] = "— (no isolation)" if row.get(k) is None else percent(row[k], 3)
    show_table(
        shown,
        hide_index=True,
        column_config={"position RMSE (m)": st.column_config.NumberColumn(format="%.3f")},
    )
    view = figure_view(VIEWS, "fu_view", VIEWS[1])
    fig = None
    with guarded():
        fig = _figure(view, results)
    if fig is not None:
        show_figure(fig, key="fu_chart")
    table_and_figure_downloads(
        "Fusion table (CSV)",
        rows,
        "noisevar-fusion.csv",
        "fu_csv",
        fig,
        "noisevar-fusion",
        "fu_fig",
    )


def _figure(view: str, results: list[FusionResult]) -> go.Figure | None:
    if view == "Track":
        return track_figure(results)
    if view == "Position error":
        return error_figure(results)
    if view == "VB estimate of R":
        vb = [r for r in results if r.label.startswith(ADAPTIVE_LOCAL)]
        if vb:
            return r_track_figure(vb[0], sensor=0, channel=0)
        st.info("Add a vb configuration to see its estimate of R.")
        return None
    iso = [r for r in results if "+isolation" in r.label]
    if iso:
        return isolation_figure(iso[0])
    st.info("Add a configuration with isolation to see the test.")
    return None

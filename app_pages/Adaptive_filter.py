"""Kalman filters that estimate R on line: tracks, R over time, NIS, RMSE, Table 1.

Adaptive filter page: Kalman filters that estimate R on line, on a scenario or loaded data.
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import adaptive_filter as af
from dashboard.widgets import how_it_works

#: The page's how-it-works expander (shown even before a signal is loaded).
HOW_IT_WORKS = (
    "**The filter.** Predict, then correct with the measurement $z_k$:",
    "$$\\hat x_{k|k-1} = F\\hat x_{k-1},\\quad P_{k|k-1} = FPF^\\top + Q,\\quad "
    "d_k = z_k - H\\hat x_{k|k-1},\\quad S_k = HP_{k|k-1}H^\\top + R_k$$",
    "$$K_k = P_{k|k-1}H^\\top S_k^{-1},\\qquad \\hat x_k = \\hat x_{k|k-1} + K_k d_k$$",
    "The gain weighs the measurement by how noisy it is: a wrong $R$ gives a wrong gain. "
    "Adaptive filters estimate $R$ as they go.",
    "**RAE and IAE (docs/algorithms.md §A10)** use the filter's own residuals "
    "$r_k = z_k - H\\hat x_{k|k}$ "
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

st.title("Adaptive filter")
st.caption(
    "Kalman filters whose measurement-noise covariance R is estimated while they run: SOMD "
    "on a trailing window (independent of the filter), residual and innovation windows "
    "(RAE, IAE), Sage-Husa, variational Bayes, against the oracle that knows the true R."
)

source = st.radio(
    "Data",
    ["Scenario", "Loaded signal"],
    key="af_source",
    bind="query-params",
    horizontal=True,
    help="A seeded scenario with truth, or the columns of the loaded file (no truth).",
)
is_scenario = source == "Scenario"
strategies = af.strategy_picker(is_scenario)
settings, kappa = af.strategy_settings()
if is_scenario:
    runs = af.on_scenario(strategies, settings, kappa)
else:
    runs = af.on_loaded_data(strategies, settings, kappa, explain=HOW_IT_WORKS)

if not strategies:
    st.info("Pick at least one strategy.")
elif runs.results:
    af.results_view(runs, is_scenario)
af.table1_panel()

how_it_works(*HOW_IT_WORKS)

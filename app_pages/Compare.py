"""Every method on the signal; Monte Carlo relative errors against the Cramér-Rao floor.

Compare page: every method on the signal; Monte Carlo relative errors against the CR floor.
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import compare
from dashboard.sections.signal_loader import require_signal
from dashboard.widgets import how_it_works
from noisevar.estimators.difference import MAD_TO_SIGMA

#: The page's how-it-works expander (shown even before a signal is loaded).
HOW_IT_WORKS = (
    "**Peers (docs/algorithms.md §D).** Difference estimators remove the slowly varying "
    "signal with a short "
    "difference sequence $d$ and normalise by its energy:",
    "$$\\hat\\sigma^2 = \\frac{\\operatorname{mean}\\big((d * z)_k^2\\big)}{\\sum_j d_j^2},\\qquad"
    "\\text{Rice: } d = (1,-1),\\quad \\text{second difference: } d = (1,-2,1)$$",
    "Hall-Kay-Titterington sequences are the optimal $d$ of each order; MAD versions replace the "
    "mean square by a median ($\\hat\\sigma = \\operatorname{median}|x - \\tilde x| / "
    f"{1 / MAD_TO_SIGMA:.4f}$) "
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
    "paper's criterion for Fig. 2: 95 % of the relative errors within 10 %, none above 20 % "
    "(docs/algorithms.md §A9).",
)

st.title("Compare")
sig = require_signal(
    "The Compare page runs every estimator on it side by side.", explain=HOW_IT_WORKS
)
tuned = st.session_state.get("nv_tuned")

tab_one, tab_mc = st.tabs(["On this signal", "Monte Carlo"], key="cmp_tab", bind="query-params")
with tab_one:
    compare.comparison(sig, tuned)
with tab_mc:
    st.caption(
        "Monte Carlo runs on a generated scenario: each run draws fresh noise (seed + run "
        "index) and every method estimates the variance; the histograms of relative errors "
        "are the paper's Fig. 2, drawn against the best possible estimator (Cramér-Rao)."
    )
    settings = compare.monte_carlo_form(sig)
    cancelled = compare.monte_carlo_runs(settings, tuned)
    compare.monte_carlo_results(cancelled)

how_it_works(*HOW_IT_WORKS)

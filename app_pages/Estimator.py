"""Tune SOMD (h_S, h_T, m, Γ) and see every step: filters, windows, envelopes, h scan.

Estimator page: tune SOMD and see every step (filters, windows, envelopes, h scan, estimate).
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections.estimator_tuning import follow_config_column
from dashboard.sections.estimator_view import tuned_view
from dashboard.sections.signal_loader import require_signal
from dashboard.widgets import how_it_works, tex_number
from noisevar.estimators.params import PAPER_H_SMOOTH
from noisevar.filters.abg import somd_bias_factor
from noisevar.filters.envelope import RATIO_BAND

#: Where the prose evaluates c(h): the paper's h_S and a fast filter (docs/algorithms.md §A8).
C_AT = (PAPER_H_SMOOTH, 9e-4)
#: The band of the noise-amplitude ratio |V1|/|V2| that h_S should reach (eq. 13-14).
LOW, HIGH = (f"\\frac{{1}}{{{1 / r:g}}}" for r in RATIO_BAND)
SHRINK = f"{1 / RATIO_BAND[1]:g} to {1 / RATIO_BAND[0]:g}"

#: The page's how-it-works expander (shown even before a signal is loaded).
HOW_IT_WORKS = (
    "**1. A virtual second sensor (docs/algorithms.md §A2).** An alpha-beta-gamma filter "
    "(position, rate, "
    "acceleration; white jerk) with constant gains smooths the record. With $h = q/r$ "
    "(jerk spectral density over noise variance) the steady-state gains are",
    "$$\\alpha = 2h^{1/3},\\qquad \\beta = 2h^{2/3},\\qquad \\gamma = h$$",
    "A small $h_S$ gives a smooth output $Z_1$ with little noise left; a faster filter "
    "($h_T$ 10 to 100 times larger) tracks quick changes.",
    "**2. Choosing $h_S$ (eq. 13-14).** Envelopes through the local maxima $U$ and minima $L$ "
    f"give a noise amplitude per window of $m$ samples; $h_S$ should cut it {SHRINK} times:",
    "$$|V| = \\frac{1}{2m}\\sum_{k}(U_k - L_k),\\qquad "
    f"{LOW} \\le \\frac{{|V_1|}}{{|V_2|}} \\le {HIGH}$$",
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
    f"({somd_bias_factor(C_AT[0]):.3f} at $h = {tex_number(C_AT[0])}$, "
    f"{somd_bias_factor(C_AT[1]):.3f} at ${tex_number(C_AT[1])}$; docs/algorithms.md §A8). "
    "Method `somd` divides by "
    "$c(h)$; `somd-paper` by 2. The 95 % interval is a chi-square interval with the "
    "effective degrees of freedom of the correlated squares.",
)

st.title("Estimator")
sig = require_signal(
    "The Estimator tunes the SOMD estimator on it and shows every step.", explain=HOW_IT_WORKS
)

sig = follow_config_column(sig)  # a just-loaded config's column (before the fragment)
tuned_view(sig)  # a control change reruns this fragment only

how_it_works(*HOW_IT_WORKS)

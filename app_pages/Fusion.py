"""Distributed VB fusion with chi-square fault isolation.

Fusion page: distributed VB fusion, chi-square fault isolation (docs/algorithms.md §B2).
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import fusion
from dashboard.widgets import how_it_works

HOW_IT_WORKS = (
    "**Local filters.** Sensor $i$ runs its own Kalman filter; with variational Bayes each "
    "noise variance has an inverse-gamma distribution $\\mathrm{IG}(\\alpha_j, \\beta_j)$, "
    "forgotten at rate $\\rho$ and updated with the residual:",
    "$$\\alpha_j \\leftarrow \\rho\\alpha_j + \\tfrac12,\\qquad "
    "\\beta_j \\leftarrow \\rho\\beta_j + \\tfrac12 (z - H\\hat x)_j^2 + "
    "\\tfrac12 (HPH^\\top)_{jj},\\qquad \\hat R_{jj} = \\beta_j/\\alpha_j$$",
    "**Fusion centre (eq. 24).** In information form the local updates simply add up:",
    "$$P^{-1} = P_{pred}^{-1} + \\sum_i \\big(P_i^{-1} - P_{i,pred}^{-1}\\big),\\qquad "
    "\\hat x = P\\Big(P_{pred}^{-1}\\hat x_{pred} + \\sum_i \\big(P_i^{-1}\\hat x_i - "
    "P_{i,pred}^{-1}\\hat x_{i,pred}\\big)\\Big)$$",
    "Each bracket is $H_i^\\top R_i^{-1} H_i$ (and $H_i^\\top R_i^{-1} z_i$), so the sum equals "
    "the centralised filter on all measurements: the metric above checks it.",
    "**Fault isolation.** Before its update, a sensor's normalised innovation is tested:",
    "$$d_i^\\top\\big(H_iP_{i,pred}H_i^\\top + R_i\\big)^{-1}d_i > \\chi^2_{m_i}(1-p_{fa})$$",
    "A flagged sensor does only its time update, so it adds nothing to the sums until its "
    "samples pass again.",
)

st.title("Fusion")
st.caption(
    "Two position sensors and a velocity sensor track one target. Each sensor has a local "
    "filter (variational-Bayes, fixed or true R); a fusion centre combines them in "
    "information form. Sensor 1 misbehaves; a chi-square test can isolate it."
)
settings = fusion.settings_form()
fusion.fused_results(settings)

how_it_works(*HOW_IT_WORKS)

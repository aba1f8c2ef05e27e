"""Adaptive EKF carrier tracking of a weak GNSS signal.

Carrier tracking page: fixed vs adaptive EKF on a weak GNSS carrier (docs/algorithms.md §B1).
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import carrier
from dashboard.widgets import how_it_works

HOW_IT_WORKS = (
    "**Measurements.** After the numerically controlled oscillator, the prompt correlator of "
    "integration period $T$ gives",
    "$$I = A\\cos\\theta_e + n_I,\\qquad Q = A\\sin\\theta_e + n_Q,\\qquad "
    "\\frac{A^2}{2\\sigma_n^2} = \\frac{C}{N_0}\\,T$$",
    "nonlinear in the phase error $\\theta_e$, hence an EKF on the state "
    "$[\\theta, f_d, \\dot f_d, A]$ with",
    "$$F = \\begin{bmatrix}1 & 2\\pi T & \\pi T^2 & 0\\\\ 0 & 1 & T & 0\\\\ 0 & 0 & 1 & 0\\\\ "
    "0 & 0 & 0 & 1\\end{bmatrix}$$",
    "**Adaptation.** Over a window of $W$ periods, the residuals give $R$ (eq. 22, positive "
    "definite) and the innovations give $Q$ (eq. 26, as printed; it feeds on itself and "
    "runs away, so our AEKF scales the design $Q$ only when the innovations leave their "
    "$\\chi^2$ band). Our window starts full of the design $R$, each residual replacing one "
    "entry: started from the paper's running mean, a few pull-in residuals set $R$ alone, "
    "inflate it and stall the loop (the AEKF's only slips in the measured tables of "
    "docs/algorithms.md §B1):",
    "$$\\hat R = \\overline{r r^\\top} + HP_{k|k}H^\\top,\\qquad \\hat Q = K\\,\\overline{d "
    "d^\\top}\\,K^\\top$$",
    "A cycle slip is a jump of the phase error by a whole cycle: the loop has lost lock.",
)

st.title("Carrier tracking")
st.caption(
    "One GPS L1 C/A channel after acquisition: prompt I/Q correlator outputs each integration "
    "period, noise set by C/N0, a Doppler that changes with the receiver's manoeuvres. "
    "The EKF tracks [phase, Doppler, Doppler rate, amplitude] with fixed R and Q; the adaptive "
    "EKF estimates R from its residuals (eq. 22) and Q = K C_d Kᵀ (eq. 26)."
)
settings = carrier.settings_form()
carrier.tracking_results(settings)
carrier.sweep_panel(settings)

how_it_works(*HOW_IT_WORKS)

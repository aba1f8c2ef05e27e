"""Huber M-estimation EKF with a bearing-bias state against outliers.

Robust filter page: Huber M-estimation EKF with a bearing-bias state (docs/algorithms.md §B3).
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import robust
from dashboard.widgets import how_it_works
from noisevar.systems.robust import DEFAULT_KAPPA, PAPER_KAPPA

HOW_IT_WORKS = (
    "**The update as a regression.** Stack the prediction and the measurement and whiten them "
    "with $\\operatorname{blockdiag}(P^-, R)^{-1/2}$:",
    "$$y = M x + \\tau,\\qquad y = \\begin{bmatrix}\\hat x^-\\\\ z\\end{bmatrix}"
    "\\text{ (whitened)},\\quad M = \\begin{bmatrix}I\\\\ H\\end{bmatrix}\\text{ (whitened)}$$",
    "The Kalman update is the least-squares solution. The Huber filter re-weights each "
    "whitened residual (iteratively):",
    "$$\\psi_i = \\begin{cases}1 & |\\tau_i| \\le \\kappa\\\\ \\kappa/|\\tau_i| & "
    "|\\tau_i| > \\kappa\\end{cases},\\qquad \\hat x = (M^\\top\\Psi M)^{-1}M^\\top\\Psi y,"
    "\\quad P = (M^\\top\\Psi M)^{-1}$$",
    "Without outliers every weight is 1 and it is the Kalman filter; an outlier gets a small "
    f"weight instead of pulling the estimate. The paper's $\\kappa = {PAPER_KAPPA:g}$ keeps "
    f"95 % efficiency for Gaussian noise; the default here, $\\kappa = {DEFAULT_KAPPA:g}$, was "
    "chosen from measurements on held-out runs, trading outlier rejection against Gaussian "
    "efficiency (docs/algorithms.md §B3).",
    "**Bias as a state.** The VOR bearing is measured from magnetic north: "
    "$\\psi_{meas} = \\operatorname{atan2}(e, n) - \\alpha$. Adding $\\alpha$ (constant) to "
    "the state lets the filter estimate the magnetic variation.",
)

st.title("Robust filter")
st.caption(
    "An aircraft flies over a DME/VOR station: slant range, magnetic bearing (with the "
    "station's magnetic variation as an unknown constant) and inertial velocity. Near the "
    "station the bearing has bursts of outliers. Plain EKF, an EKF that ignores the bias, and "
    "the Huber EKF."
)
settings = robust.settings_form()
robust.robust_results(settings)

how_it_works(*HOW_IT_WORKS)

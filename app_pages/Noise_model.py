"""Allan deviation, IEEE-952 noise terms with intervals, Kalibr imu.yaml, simulation.

Noise model page: Allan deviation, IEEE-952 terms, Kalibr export (docs/algorithms.md §E4).
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import filter_configs, noise_model, noise_model_temperature
from dashboard.sections.noise_model_fit import render_fit
from dashboard.sections.signal_loader import require_signal
from dashboard.state import signal_units
from dashboard.widgets import ANSWER_KEY, CONTROLS_ABOVE_KEY, how_it_works, lazy_expander

HOW_IT_WORKS = (
    "**Allan deviation.** Average the rate over $\\tau = m\\tau_0$ and take half the mean "
    "squared difference of neighbouring averages; from the phase $x$ (the integrated rate):",
    "$$\\sigma^2(\\tau) = \\frac{1}{2\\tau^2(N-2m)}\\sum_k (x_{k+2m} - 2x_{k+m} + x_k)^2$$",
    "Each $\\tau$'s interval comes from its equivalent degrees of freedom for the noise type "
    "identified there (lag-1 autocorrelation), as allantools and Stable32 compute them.",
    "**Inertial noise terms (IEEE Std 952).** In rate data five noises add, each with its "
    "own slope on the log-log plot ($-1, -\\tfrac12, 0, +\\tfrac12, +1$):",
    "$$\\sigma^2(\\tau) = \\frac{3Q^2}{\\tau^2} + \\frac{N^2}{\\tau} + "
    "\\frac{2\\ln 2}{\\pi}B^2 + \\frac{K^2\\tau}{3} + \\frac{R^2\\tau^2}{2}$$",
    "All five are fitted at once by non-negative weighted least squares over every $\\tau$ "
    "(weights from each $\\tau$'s degrees of freedom). For a filter sampled at $f_s$: white "
    "rate std per sample $N\\sqrt{f_s}$, bias random-walk step $K/\\sqrt{f_s}$. Kalibr's "
    "`imu.yaml` takes $N$ and $K$ themselves.",
)

st.title("Noise model")
sig = require_signal(
    "The Noise model page draws its Allan deviation and fits the IEEE-952 noise terms.",
    explain=HOW_IT_WORKS,
)
regimes = noise_model.regime_panel(sig)
with st.container(key=CONTROLS_ABOVE_KEY):  # on a phone: below the answer
    settings = noise_model.settings_form(sig, regimes)
with st.container(key=ANSWER_KEY):
    fit = noise_model.results(sig, settings)

with st.expander("Filter configs: Kalibr imu.yaml and every consumer", icon=":material/download:"):
    noise_model.kalibr_export(sig, settings)
    filter_configs.consumer_files(sig, settings.rate, settings.regimes)

if settings.rate > 0:  # a bad rate is said once, above
    st.subheader("Coloured noise and the Kalman filter's Q and R")
    record = noise_model.record_summary(sig, regimes)  # the record's answer, in the config
    render_fit(
        sig.z, settings.rate, regimes, sig.column, signal_units(), record, times=sig.times
    )

# temperature, datasheet and composite models (issue 30): dashboard/sections/noise_model_temperature
with st.expander("Temperature: bias(T), warm-up, bias process noise", icon=":material/thermostat:"):
    noise_model_temperature.temperature_panel(sig, settings)
with st.expander("Compare with the datasheet", icon=":material/compare_arrows:"):
    noise_model_temperature.datasheet_panel(fit, settings)
if settings.rate > 0:
    with lazy_expander("Composite noise model (GMWM)", key="nm_gmwm_open") as gmwm_open:
        if gmwm_open:
            noise_model_temperature.composite_panel(sig, settings)

how_it_works(*HOW_IT_WORKS)

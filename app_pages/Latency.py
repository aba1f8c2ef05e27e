"""GPS delay estimation by least squares over shifts and a random-constant filter.

Latency page: GPS delay by shift least squares and a filter (docs/algorithms.md §C).
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import latency
from dashboard.widgets import how_it_works

HOW_IT_WORKS = (
    "**Coarse delay.** Shift the GPS record against the inertial one and keep the shift with "
    "the smallest mean squared difference (the mean difference removed, so a constant offset "
    "does not matter):",
    "$$\\hat\\tau = \\arg\\min_s \\frac{1}{m}\\sum_k \\big(v_{GPS}[k+s] - v_{INS}[k] - "
    "\\bar\\Delta_s\\big)^2$$",
    "then refine below one sample with a parabola through the three best shifts "
    "$c_{-1}, c_0, c_{+1}$:",
    "$$\\delta = \\frac{c_{-1} - c_{+1}}{2(c_{-1} - 2c_0 + c_{+1})}$$",
    "**Filtering the unknown part.** Per segment, the measurable part (known) is subtracted; "
    "the unknown remainder is a random constant, estimated by a scalar Kalman filter:",
    "$$x_{k+1} = x_k + w_k,\\qquad y_k = \\hat\\tau_k - \\tau^{meas}_k = x_k + v_k$$",
)

st.title("Latency")
st.caption(
    "The same speed seen by an inertial unit (on time) and by a GPS (late). The delay is the "
    "shift that best lines the two records up; a measurable part (timestamps, scheduler) is "
    "known per segment, and the unknown rest is filtered over the segments."
)
settings = latency.settings_form()
latency.delay_results(settings)

how_it_works(*HOW_IT_WORKS)

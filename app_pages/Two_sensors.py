"""Redundant SOMD with two or three real sensors (three-cornered hat).

Two sensors page: redundant SOMD with two or three real sensors of one quantity.
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import sensors
from dashboard.state import current_signal
from dashboard.widgets import how_it_works

#: The page's how-it-works expander (shown even before a signal is loaded).
HOW_IT_WORKS = (
    "**Two sensors (eq. 8).** Sensor $i$ reads $Z_i = Z + \\delta Z_i + V_i$: the true value, a "
    "slowly varying systematic error ($\\delta Z_i[k] \\approx \\delta Z_i[k+1]$) and white "
    "noise. Differencing in time removes $Z$'s level and the systematic errors; differencing "
    "the two sensors removes $Z$'s changes. What is left is noise:",
    "$$\\tfrac12\\,\\mathrm{E}\\big[(\\Delta Z_1 - \\Delta Z_2)^2\\big] = "
    "\\operatorname{var}(V_1) + \\operatorname{var}(V_2)$$",
    "With two sensors only the sum is known (the paper assumes one sensor is far better, so the "
    "sum is the worse sensor's variance).",
    "**Three sensors (three-cornered hat).** The three pair sums give three equations in three "
    "unknowns:",
    "$$s_{12} = \\sigma_1^2 + \\sigma_2^2,\\quad s_{13} = \\sigma_1^2 + \\sigma_3^2,\\quad "
    "s_{23} = \\sigma_2^2 + \\sigma_3^2 \\;\\Rightarrow\\; "
    "\\sigma_1^2 = \\tfrac12(s_{12} + s_{13} - s_{23})$$",
    "With more sensors the pair sums are solved by least squares.",
    "**Delays.** If one record lags, $\\Delta Z_1 - \\Delta Z_2$ also contains the signal's "
    "change over the lag. The delay is the shift $\\tau$ minimising "
    "$\\sum_k (Z_1[k] - Z_2[k+\\tau])^2$, refined below one sample by a parabola through the "
    "three best shifts; the late record is then read at $t + \\tau$.",
)

sig = current_signal()
st.title("Two sensors")
st.caption(
    "Two or more real sensors of the same quantity: the second-order mutual difference of "
    "each pair gives the sum of their noise variances; three sensors give each one."
)
sig = sensors.require_sensors(sig, explain=HOW_IT_WORKS)
cols, align = sensors.sensor_picker(sig)
sensors.redundant_results(sig, cols, align)

how_it_works(*HOW_IT_WORKS)

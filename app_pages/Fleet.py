"""Many sensors at once: noise per channel, sensors outside the fleet's range flagged.

Fleet page: the noise of many sensors side by side, and the ones outside the fleet's range.
"""

from __future__ import annotations

import streamlit as st

from dashboard.sections import fleet
from dashboard.widgets import guarded, how_it_works
from noisevar.batch.fleet import DEFAULT_THRESHOLD, MAD_TO_SD, fleet_report

HOW_IT_WORKS = (
    "**One row per sensor and channel.** `noisevar batch 'logs/**/*.csv' --out noise.parquet` "
    "(or the buttons above) estimates the noise of every channel of every file; each file is "
    "one sensor. The page compares the sensors of each channel with each other.",
    "**Robust z-score.** On a log scale (twice as noisy and half as noisy are equally unusual), "
    "with $x_i = \\log_{10}\\hat\\sigma_i$, the fleet's median $\\tilde x$ and its median "
    "absolute deviation (MAD):",
    f"$$z_i = \\frac{{x_i - \\tilde x}}{{\\mathrm{{MAD}}/{MAD_TO_SD:.4f}}},\\qquad "
    "\\mathrm{MAD} = \\operatorname{median}_i |x_i - \\tilde x|$$",
    "The MAD is barely moved by the outliers being looked for, unlike the standard deviation. "
    f"A sensor with $|z_i| > {DEFAULT_THRESHOLD:g}$ (Iglewicz and Hoaglin's cut-off) is flagged; "
    "the band on the "
    "figure is each channel's normal range.",
)

st.title("Fleet")
fleet.source_panel()
frame, label = fleet.current_table()
if frame is None:
    st.info("No batch table yet: run the example fleet, load a table, or run a batch above.")
else:
    threshold = fleet.threshold_input()
    regimes = fleet.regime_choice(frame)
    with guarded():
        report = fleet_report(frame, threshold, regimes)
        fleet.summary(report, frame, label)
        fleet.figures(report)
        fleet.open_sensor(report)
        fleet.table(report, frame)
how_it_works(*HOW_IT_WORKS)

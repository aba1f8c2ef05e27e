"""The Streamlit side of noisevar: page registry, state, cached calls, widgets, page sections.

Pages ask, call :mod:`noisevar` and draw; no number is computed here. :mod:`noisevar`
never imports this package.
"""

import plotly.io as pio
import streamlit  # noqa: F401 - on import, it makes its own template plotly's default

# Figures carry no template: the page draws them with its own neutral colours
# (dashboard.widgets.display_spec), and the exports apply plotly's (noisevar.figures).
pio.templates.default = None

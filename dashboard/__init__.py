"""The Streamlit side of noisevar: page registry, state, cached calls, widgets, page sections.

Pages ask, call :mod:`noisevar` and draw; no number is computed here. :mod:`noisevar`
never imports this package.
"""

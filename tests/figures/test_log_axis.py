"""The project's log axis: labels on decades, and 1-2-5 labels when the data span little."""

from __future__ import annotations

import numpy as np

from noisevar.figures.budget import log_axis
from noisevar.figures.kalman import state_label


def test_a_short_range_gets_more_than_one_label():
    axis = log_axis("ratio", np.array([0.03, 0.05, 0.2]))
    assert axis["tickvals"] == [0.05, 0.1, 0.2] and axis["ticktext"] == ["0.05", "0.1", "0.2"]
    assert "dtick" not in axis
    narrow = log_axis("ratio", [0.5, 0.9])["tickvals"]
    assert len(narrow) >= 2


def test_a_long_range_labels_decades_only():
    axis = log_axis("variance", [1e-4, 3e-1])
    assert axis["dtick"] == 1 and "tickvals" not in axis
    assert log_axis("variance")["dtick"] == 1  # no values: decades


def test_position_states_are_named_with_their_unit():
    assert state_label("pE") == "east position pE (m)"
    assert state_label("v") == "v"


def test_a_level_profile_within_a_decade_labels_more_than_one_level():
    """A parked GNSS record's profile spans 0.0017-0.01: one decade label (``10⁻²``) alone
    left its levels unreadable (seen in a browser screenshot of the Noise panel)."""
    import noisevar
    from noisevar.diagnostics.panel import noise_panel_data
    from noisevar.figures.noise import level_profile_plot

    rng = np.random.default_rng(0)
    z = 0.05 * rng.normal(size=600)
    est = noisevar.estimate(z)
    fig = level_profile_plot(noise_panel_data(z, est.diagnostics))
    assert len(fig.layout.yaxis.tickvals) >= 2


def test_the_channels_figure_labels_its_log_axis_by_decades_or_1_2_5():
    """An RTKLIB record's channels (std 0.5-10 m) were labelled 4, 5, ..., 9, 1, 2, ... by
    Plotly's default minor labels (seen in a browser screenshot of the Signal page)."""
    import noisevar
    from noisevar.figures.fleet import channels_figure

    rng = np.random.default_rng(1)
    z = rng.normal(size=(4, 800)) * np.array([[5.3], [5.7], [9.5], [0.54]])
    fig = channels_figure(noisevar.estimate(z, axis=1), ["e", "n", "u", "ns"])
    axis = fig.layout.yaxis
    assert axis.dtick == 1 or len(axis.tickvals) >= 2
    assert axis.exponentformat == "power"


def test_labels_outside_a_narrow_range_are_brought_into_view():
    """One channel's noise std with its interval (0.00158-0.00183, an ISMN soil-moisture
    station) drew a log axis with no label: the 1-2-5 values around it lay outside
    Plotly's own range (seen in a browser screenshot of the Signal page)."""
    import math

    axis = log_axis("noise std", [0.0017, 0.00158, 0.00183])
    lo, hi = axis["range"]
    shown = [t for t in axis["tickvals"] if lo <= math.log10(t) <= hi]
    assert len(shown) >= 2 and len(set(axis["tickvals"])) == len(axis["tickvals"])
    assert "range" not in log_axis("ratio", [0.03, 0.05, 0.2])  # labels inside the data

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

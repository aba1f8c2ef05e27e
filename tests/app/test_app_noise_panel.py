"""AppTest: the Noise panel draws for a heavy-tailed and a coloured record (issue 13)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))


def _panel_app(kind: str, param: str, value: float) -> None:
    import sys as _sys

    import numpy as np
    import streamlit as st

    _sys.path.insert(0, st.session_state["root"])
    from dashboard.sections.noise_panel import render_assumptions, render_noise_panel
    from noisevar import estimate, synth

    n = 6000
    z = synth.noise(kind, n, rng=11, **{param: value}).values + np.sin(np.arange(n) / 500.0)
    est = estimate(z)
    render_noise_panel(z, est)
    render_assumptions([est, estimate(z, method="mle-level")])


@pytest.mark.parametrize(
    ("kind", "param", "value", "words"),
    [
        ("student_t", "dof", 3.0, "heavy-tailed"),
        ("ar1", "phi", 0.7, "coloured"),
    ],
)
def test_noise_panel_draws(kind: str, param: str, value: float, words: str) -> None:
    at = AppTest.from_function(_panel_app, args=(kind, param, value), default_timeout=120)
    at.session_state["root"] = str(ROOT)
    at.run()
    assert not at.exception, [e.value for e in at.exception]
    assert not at.error, [e.value for e in at.error]
    shown = [m.value for m in (*at.info, *at.warning)]
    assert any(words in s for s in shown), shown
    if kind == "ar1":
        assert at.warning, "a coloured record's verdict is a warning"
    # lazy: a closed expander computes and sends no figure; open, only the open tab's
    assert not at.tabs and not at.get("plotly_chart")
    at.session_state["np_open"] = True
    at.run()
    assert not at.exception, [e.value for e in at.exception]
    assert len(at.tabs) == 4
    assert len(at.get("plotly_chart")) == 1
    at.session_state["np_tab"] = "Level profile"
    at.run()
    assert not at.exception, [e.value for e in at.exception]
    charts = at.get("plotly_chart")
    assert len(charts) == 1 and "level" in charts[0].proto.spec.lower()
    frame = at.dataframe[0].value
    assert list(frame["Method"]) == ["auto", "mle-level"]
    # the coloured record fails the white-noise assumption of auto
    if kind == "ar1":
        assert "white noise" in frame["Fails"].iloc[0]

"""AppTest of the Noise model page's Kalman section (``render_fit``), through from_function."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))


@pytest.fixture(autouse=True)
def _no_pool(monkeypatch):
    """The fits run on this thread: a worker pool started under ``from_function`` would
    re-run the generated script as its main module (app.py guards its own)."""
    from dashboard import workers

    monkeypatch.setattr(workers, "WORKERS", 0)


def _page(n: int, rate: float, seed: int) -> None:
    import numpy as np

    from dashboard.sections.noise_model_fit import render_fit

    rng = np.random.default_rng(seed)
    v = np.cumsum(rng.normal(0, 0.3, n))
    z = np.cumsum(v) / rate + rng.normal(0, 1.0, n)
    render_fit(z, rate)


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]
    assert not at.error, [e.value for e in at.error]


def test_models_compared_and_the_tuned_filter_shown():
    at = AppTest.from_function(_page, args=(3000, 10.0, 1), default_timeout=120).run()
    _clean(at)
    table = at.dataframe[0].value
    assert list(table["model"]) == ["rw", "cv", "ca"]
    assert at.selectbox(key="nmf_model").value == "cv"
    assert bool(table.set_index("model").loc["cv", "best (BIC)"])
    assert at.success and "fits this record" in at.success[0].value
    assert any("Suggested **q" in m.value for m in at.markdown)
    # the tuned filter's run (three figures) is run and sent only once its expander is open
    from dashboard.sections.noise_model_fit import RUN_KEY, RUN_LABEL

    assert any(e.label == RUN_LABEL for e in at.expander)
    assert not at.get("plotly_chart"), "a closed expander's figures cost the browser"
    at.session_state[RUN_KEY] = True
    at.run()
    _clean(at)
    keys = [c.key for c in at.get("plotly_chart")]
    assert keys == ["nmf_run", "nmf_nis", "nmf_acf"]
    # the snippet's code block is sent only once its expander is opened (issue 29)
    from dashboard.sections.noise_model_fit import SNIPPET_KEY

    assert any(e.label == "The tuned filter in filterpy" for e in at.expander)
    assert not at.code, "a closed expander's code block loads the browser's highlighter"
    at.session_state[SNIPPET_KEY] = True
    at.run()
    _clean(at)
    assert any("KalmanFilter" in c.value for c in at.code)


def test_switching_model_and_coloured_fit():
    at = AppTest.from_function(_page, args=(3000, 10.0, 2), default_timeout=180).run()
    at.selectbox(key="nmf_model").set_value("rw").run()
    _clean(at)
    # a random walk cannot follow a constant-velocity track: the page says so
    assert at.warning and "does not fit" in at.warning[0].value
    at.button(key="nmf_col_btn").click().run()
    _clean(at)
    assert len(at.dataframe) == 2 and any("Chosen by BIC" in m.value for m in at.markdown)


def test_bad_rate_is_one_error():
    at = AppTest.from_function(_page, args=(500, -1.0, 3), default_timeout=60).run()
    assert not at.exception
    assert len(at.error) == 1 and "rate" in at.error[0].value


def _level_page() -> None:
    import numpy as np

    from dashboard.sections.noise_model_fit import render_fit

    rng = np.random.default_rng(3)
    e = rng.normal(0, 1.0, 4000)
    e[2000:] *= 3.0  # the noise level changes: a still R to use beside r
    render_fit(np.cumsum(rng.normal(0, 0.1, 4000)) + e, 10.0)


def test_r_is_said_beside_the_records_answer():
    at = AppTest.from_function(_page, args=(3000, 10.0, 1), default_timeout=120).run()
    _clean(at)
    assert any("r and the record's R (method auto)" in i.value for i in at.info)
    assert any("r agrees with the record's R" in i.value for i in at.info)
    at = AppTest.from_function(_level_page, default_timeout=120).run()
    _clean(at)
    said = [w.value for w in at.warning if "r and the record's R" in w.value]
    assert said and "one noise level" in said[0] and "--regimes still" in said[0]
    assert any(m.value.startswith("R to use: **") for m in at.markdown)


def test_the_models_table_says_r_against_the_records_r():
    at = AppTest.from_function(_level_page, default_timeout=120).run()
    _clean(at)
    table = at.dataframe[0].value.set_index("model")
    ratio = table["r / record's R"]
    assert ratio.notna().all() and ((ratio > 0.9) & (ratio < 1.1)).all()

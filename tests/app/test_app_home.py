"""AppTest: the home page (app.py), the frame every page shares."""

from __future__ import annotations

import sys
from pathlib import Path

from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def test_home_runs_with_defaults_and_links_every_page(how_it_works_opens):
    at = AppTest.from_file(APP, default_timeout=60).run()
    _clean(at)
    assert not at.error
    assert at.title[0].value.startswith("noisevar")
    labels = {p.label for p in at.get("page_link")}
    assert {"Signal", "Estimator", "Compare", "Two sensors"} <= labels
    assert how_it_works_opens(at), "the how-it-works expander shows equations"


def test_home_quick_start_loads_a_signal_for_every_page():
    at = AppTest.from_file(APP, default_timeout=60).run()
    at.button(key="home_generate").click().run()
    _clean(at)
    assert "Quick estimate" in at.success[0].value
    # the quick R comes with the record's verdict, as on every page showing one (issue 28)
    boxes = [b.value for b in [*at.info, *at.warning]]
    assert any("The record's answer (Estimator page): " in b for b in boxes), boxes
    sig = at.session_state["nv_signal"]
    assert sig.n == 6000 and sig.source == "generated"
    assert at.query_params.get("sig", "").startswith("gen:fast-slow")


def test_home_sample_button():
    at = AppTest.from_file(APP, default_timeout=60).run()
    at.button(key="home_sample").click().run()
    _clean(at)
    assert at.session_state["nv_signal"].label == "fast_slow.csv"

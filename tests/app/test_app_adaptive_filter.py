"""AppTest: the Adaptive filter page (scenarios with truth, loaded data, Table 1)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PAGE = "app_pages/Adaptive_filter.py"


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def _table(at: AppTest):
    return at.dataframe[0].value


@pytest.fixture
def at() -> AppTest:
    app = AppTest.from_file(APP, default_timeout=120)
    # a short gps-circle keeps the test fast; the default is the paper's 3000 s
    app.query_params["af_duration"] = "600"
    app.switch_page(PAGE).run()
    _clean(app)
    return app


def test_scenario_with_defaults(at, how_it_works_opens):
    assert not at.error
    table = _table(at)
    assert list(table["filter"]) == ["oracle", "somd-online", "rae", "sage-husa", "vb"]
    rmse = table.set_index("filter")["RMSE position (m)"]
    assert rmse["somd-online"] < 1.2 * rmse["oracle"]
    assert at.get("plotly_chart") and how_it_works_opens(at)


def test_each_main_widget_changes_the_result(at):
    before = _table(at).to_dict()
    at.multiselect(key="af_strats").set_value(["oracle", "fixed"]).run()
    _clean(at)
    assert list(_table(at)["filter"]) == ["oracle", "fixed"]
    for kind, key, value in (
        ("number_input", "af_seed", 4),
        ("slider", "af_duration", 800),
        ("toggle", "af_huber", True),
    ):
        before = _table(at).to_dict()
        getattr(at, kind)(key=key).set_value(value).run()
        _clean(at)
        assert _table(at).to_dict() != before, key
    at.selectbox(key="af_scenario").set_value("noise-step").run()
    _clean(at)
    before = _table(at).to_dict()
    at.slider(key="af_factor").set_value(6.0).run()
    _clean(at)
    assert _table(at).to_dict() != before


def test_every_figure_renders(at):
    for view in ["States", "R estimates", "Innovations and NIS", "Track"]:
        at.segmented_control(key="af_view").set_value(view).run()
        _clean(at)
        assert not at.error, view
        assert at.get("plotly_chart"), view


def test_loaded_multichannel_data(at):
    at.radio(key="af_source").set_value("Loaded signal").run()
    _clean(at)
    assert any("No signal loaded" in i.value for i in at.info)
    at.button(key="offer_gps_circle.csv").click().run()
    _clean(at)
    assert not at.error
    table = _table(at)
    assert "oracle" not in set(table["filter"])
    assert (table["channels m"] == 2).all()
    # each channel's record answer (verdict, R as the Estimator page), and why the filters differ
    boxes = [b.value for b in [*at.info, *at.warning]]
    assert sum("The record's answer (Estimator page): R = " in b for b in boxes) == 2
    assert any("The filters' R differ" in c.value for c in at.caption)
    before = table.to_dict()
    at.select_slider(key="af_r0").set_value(1.0).run()
    _clean(at)
    assert _table(at).to_dict() != before


def test_table1_on_demand(at):
    at.number_input(key="t1_runs").set_value(1)
    at.button(key="t1_go").click().run(timeout=180)
    _clean(at)
    table = at.dataframe[1].value
    rows = list(table["row"])
    assert rows[:3] == ["true", "paper SOMD", "paper RAE"]
    assert "somd" in rows and "rae" in rows

"""AppTest: the Noise model page's temperature model and datasheet overlay (§E9)."""

from __future__ import annotations

import importlib.util
import json
import math
import sys
from pathlib import Path

from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PAGE = "app_pages/Noise_model.py"
SIG = "sample:imu_temperature.csv;col=gyro_x"


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def _open() -> AppTest:
    app = AppTest.from_file(APP, default_timeout=120)
    app.query_params["sig"] = SIG
    app.switch_page(PAGE).run()
    _clean(app)
    return app


def _names(at: AppTest, i: int) -> list[str]:
    fig = json.loads(at.get("plotly_chart")[i].proto.spec)
    return [t.get("name") for t in fig["data"]]


def test_temperature_column_datasheet_overlay_and_a_flat_column():
    at = _open()
    assert not at.error
    charts = len(at.get("plotly_chart"))
    assert any("temperature column" in c.value for c in at.caption)
    at.selectbox(key="nm_temp_col").set_value("temp_c").run()
    _clean(at)
    assert not at.error
    table = next(d.value for d in at.dataframe if "warm-up τ" in list(d.value.get("term", [])))
    rows = table.set_index("term")
    # the sample file's truth: b = 0.01 deg/s/°C, warm-up 0.2 deg/s with tau 120 s
    assert math.isclose(rows.loc["b", "value"], 0.01, rel_tol=0.05)
    assert math.isclose(rows.loc["warm-up τ", "value"], 120.0, rel_tol=0.2)
    assert len(at.get("plotly_chart")) == charts + 2
    assert any("A exp(-t/τ)" in (n or "") for n in _names(at, charts + 1))
    assert "TemperatureBias" in at.code[-1].value
    # the datasheet: 0.3 °/√h and 5 °/h against the data in deg/s
    at.selectbox(key="nm_ds_unit").set_value("deg/s")
    at.number_input(key="nm_ds_n").set_value(0.3)
    at.number_input(key="nm_ds_b").set_value(5.0).run()
    _clean(at)
    assert not at.error
    names = _names(at, len(at.get("plotly_chart")) - 1)
    assert any((n or "").startswith("datasheet: ARW 0.3") for n in names)
    sheet = at.dataframe[-1].value.set_index("term")
    assert math.isclose(sheet.loc["N", "datasheet"], 0.3 / 60.0, rel_tol=1e-9)
    assert math.isclose(sheet.loc["B", "datasheet"], 5.0 / 3600.0, rel_tol=1e-9)

    # a column that varies by less than 0.5 °C: one error, the rest of the page stays
    at.selectbox(key="nm_temp_col").set_value("gyro_y").run()
    _clean(at)
    assert len(at.error) == 1 and "0.5 °C" in at.error[0].value


def test_composite_model_opens_on_demand():
    at = _open()
    charts = len(at.get("plotly_chart"))
    at.session_state["nm_gmwm_open"] = True
    at.run()
    _clean(at)
    assert not at.error
    if importlib.util.find_spec("noisevar.noise_model.gmwm") is None:  # before the merge
        assert any("not installed" in c.value for c in at.caption)
        return
    assert len(at.get("plotly_chart")) == charts + 1
    names = _names(at, charts)
    assert "Haar wavelet variance" in names and any(n.startswith("sum: ") for n in names)
    tables = [d.value for d in at.dataframe]
    assert any("chosen" in t.columns and t["chosen"].sum() == 1 for t in tables)
    params = next(t for t in tables if "parameter" in t.columns)
    assert (params["low"] <= params["value"]).all() and (params["value"] <= params["high"]).all()
    assert any("K_eq = " in c.value and "the exports take" in c.value for c in at.caption)

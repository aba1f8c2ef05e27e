"""AppTest: the Two sensors page (redundant SOMD with two or three sensors)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PAGE = "app_pages/Two_sensors.py"


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def _variances(at: AppTest) -> dict[str, float]:
    return {  # the number before its unit ("0.07313 (W/m²)²")
        m.label.split(":")[0]: float(m.value.split(" (")[0])
        for m in at.metric
        if "noise variance" in m.label
    }


def _open() -> AppTest:
    app = AppTest.from_file(APP, default_timeout=60)
    app.switch_page(PAGE).run()
    _clean(app)
    return app


def test_without_sensors_offers_the_sample_files(how_it_works_opens):
    at = _open()
    assert any("No signal" in i.value for i in at.info)
    assert {"ts_two", "ts_three", "ts_sim"} <= {b.key for b in at.button}
    assert how_it_works_opens(at)


def test_two_sensors_sum_and_delay_toggle(how_it_works_opens):
    at = _open()
    at.button(key="ts_two").click().run()
    _clean(at)
    assert not at.error
    v = _variances(at)
    assert set(v) == {"sensor_a", "sensor_b"}
    # the headlines are per sensor (1 and 16), not the sum two sensors determine
    assert v["sensor_a"] == pytest.approx(1.0, rel=0.25)
    assert v["sensor_b"] == pytest.approx(16.0, rel=0.25)
    total = next(m for m in at.metric if m.label.startswith("sensor_a + sensor_b"))
    assert float(total.value) == pytest.approx(17.0, rel=0.1)
    assert any("sum of the single-signal values" in c.value for c in at.caption)
    # the table's redundant column holds the pair's sum on each row: said in its header
    head = [c for c in at.dataframe[0].value.columns if c.startswith("redundant")]
    assert head == ["redundant SOMD variance (≤ the pair's sum)"]
    at.toggle(key="ts_align").set_value(True).run()
    _clean(at)
    assert at.info or at.success
    assert at.get("plotly_chart") and how_it_works_opens(at)


def test_three_sensors_each_variance_and_column_choice():
    at = _open()
    at.button(key="ts_three").click().run()
    _clean(at)
    v = _variances(at)
    assert v["sensor_a"] == pytest.approx(1.0, rel=0.15)
    assert v["sensor_b"] == pytest.approx(4.0, rel=0.15)
    assert v["sensor_c"] == pytest.approx(9.0, rel=0.15)
    assert "redundant SOMD variance" in at.dataframe[0].value.columns  # three separate them
    at.multiselect(key="ts_cols").set_value(["sensor_a", "sensor_c"]).run()
    _clean(at)
    assert set(_variances(at)) == {"sensor_a", "sensor_c"}
    at.multiselect(key="ts_cols").set_value(["sensor_a"]).run()
    _clean(at)
    assert any("at least two" in i.value for i in at.info)


def test_simulated_sensors():
    at = _open()
    at.button(key="ts_sim").click().run()
    _clean(at)
    v = _variances(at)
    assert list(v.values()) == pytest.approx([1.0, 4.0, 9.0], rel=0.15)


def test_single_column_signal_is_explained():
    at = AppTest.from_file(APP, default_timeout=60)
    at.query_params["sig"] = "sample:fast_slow.csv"
    at.switch_page(PAGE).run()
    _clean(at)
    assert any("single column" in i.value for i in at.info)


def _ghi_page(header: str, lead: str, seed: int) -> AppTest:
    """The page on two co-located pyranometers (GHI a, b) after ``lead`` columns, as NREL
    MIDC's logger writes them (real_audit5)."""
    from dashboard.state import SIGNAL_KEY, make_signal
    from noisevar.io import load_table

    rng = np.random.default_rng(seed)
    ghi = 500 + np.cumsum(rng.normal(0, 1, 1440))
    body = header + "GHI a [W/m^2],GHI b [W/m^2]\n" + "".join(
        f"{lead}{g + rng.normal(0, 0.3):.4f},{g + rng.normal(0, 0.5):.4f}\n" for g in ghi
    )
    table = load_table(body.encode(), "midc.csv")
    at = AppTest.from_file(APP, default_timeout=60)
    at.session_state[SIGNAL_KEY] = make_signal(
        table, "GHI a [W/m^2]", table.sample_period, "upload", None
    )
    at.switch_page(PAGE).run()
    _clean(at)
    return at


def test_a_loggers_constant_columns_are_not_the_default_sensors():
    """NREL MIDC's logger CSV (real_audit5) starts with an index, the year and the day of
    year, all constant: the page opened on those three and showed "noise variance 0" for
    each. It opens on the table's signals."""
    at = _ghi_page("Unnamed: 0,Year,DOY,", "0,2018,291,", seed=5)
    assert at.multiselect(key="ts_cols").value == ["GHI a [W/m^2]", "GHI b [W/m^2]"]
    assert all(v > 0 for v in _variances(at).values())


def test_each_sensors_variance_is_written_in_its_unit():
    """As the Estimator and Noise model pages write R (real_audit5: the metrics had none)."""
    at = _ghi_page("", "", seed=6)
    shown = [m.value for m in at.metric if "noise variance" in m.label or "two sensors" in m.label]
    assert len(shown) == 3 and all("(W/m²)²" in v for v in shown), shown

"""AppTest: the Fleet page (example fleet, flagged sensor, open it on the Estimator page)."""

from __future__ import annotations

import re
import sys
from pathlib import Path

import numpy as np
import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PAGE = "app_pages/Fleet.py"

import noisevar as nv  # noqa: E402
from dashboard.sections.fleet import _clicked  # noqa: E402
from noisevar.batch.fleet import fleet_report  # noqa: E402


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def _open() -> AppTest:
    app = AppTest.from_file(APP, default_timeout=120)
    app.switch_page(PAGE).run()
    _clean(app)
    return app


def _example(at: AppTest) -> AppTest:
    at.button(key="fl_example").click().run()
    _clean(at)
    assert not at.error, [e.value for e in at.error]
    return at


def test_without_a_table_the_page_says_what_to_do(how_it_works_opens):
    at = _open()
    assert any("No batch table" in i.value for i in at.info)
    assert at.button(key="fl_example") and how_it_works_opens(at)


def test_example_fleet_flags_the_faulty_unit():
    at = _example(_open())
    metrics = {m.label: m.value for m in at.metric}
    assert metrics["Sensors (files)"] == "12" and metrics["Channels"] == "3"
    assert metrics["Flagged"] == "1" and metrics["Rows with an error"] == "0"
    (warning,) = at.warning
    assert "imu_04.csv · ay" in warning.value and "times noisier" in warning.value
    frame = at.session_state["nv_fleet_table"]
    report = fleet_report(frame)
    assert [(Path(s.file).name, s.channel) for s in report.flagged] == [("imu_04.csv", "ay")]
    assert f"{report.flagged[0].z:+.1f}" in warning.value  # the page shows noisevar's number
    assert len(at.get("plotly_chart")) == 2
    assert at.selectbox(key="fl_sensor").value.startswith("imu_04.csv · ay")


def test_a_higher_threshold_clears_the_flag():
    at = _example(_open())
    top = fleet_report(at.session_state["nv_fleet_table"]).flagged[0].z
    at.number_input(key="fl_threshold").set_value(float(np.ceil(abs(top))) + 1.0).run()
    _clean(at)
    assert not at.warning and any("No sensor is outside" in s.value for s in at.success)


def test_open_the_flagged_sensor_on_the_estimator_page():
    at = _example(_open())
    frame = at.session_state["nv_fleet_table"]
    at.button(key="fl_open").click().run()
    _clean(at)
    sig = at.session_state["nv_signal"]
    assert Path(sig.table.name).name == "imu_04.csv" and sig.column == "ay"
    row = frame[(frame["file"].str.endswith("imu_04.csv")) & (frame["channel"] == "ay")]
    assert nv.estimate(sig.z).variance == row["variance"].iat[0]
    assert at.title[0].value == "Estimator"


@pytest.mark.parametrize(
    ("event", "expected"),
    [
        (
            {"selection": {"points": [{"customdata": ["/x/imu_01.csv", "az"]}]}},
            ("/x/imu_01.csv", "az"),
        ),
        ({"selection": {"points": []}}, None),
        (None, None),
    ],
)
def test_a_clicked_point_names_its_sensor(event, expected, monkeypatch):
    import streamlit as st

    monkeypatch.setattr(st, "session_state", {"fl_dist": event})
    assert _clicked("fl_dist") == expected


def test_the_example_fleet_spread_is_the_one_generated(tmp_path):
    from noisevar.batch.example import EXAMPLE_CHANNELS, write_example_fleet

    files = write_example_fleet(tmp_path, n_sensors=6, noisy=())
    report = fleet_report(nv.batch(files, progress=False))
    typical = {c.channel: c.median_std for c in report.channels}
    np.testing.assert_allclose(
        [typical[c] for c in EXAMPLE_CHANNELS], list(EXAMPLE_CHANNELS.values()), rtol=0.15
    )


def test_fleet_tables_show_no_none_cell():
    at = _example(_open())
    from dashboard.widgets import blank_frame

    frames = [d.value for d in at.dataframe]
    batch = [f for f in frames if "still_variance" in f.columns]
    assert batch and all("still_note" in f.columns for f in batch)
    assert all(f["variance"].dtype == float for f in batch)  # sorted by value, not as text
    for f in frames:  # drawn through blank_frame's Styler: a missing cell reads "—"
        cells = re.findall(r"<td[^>]*>(.*?)</td>", blank_frame(f).to_html())
        assert not {c.strip() for c in cells} & {"None", "nan", "NaN", "&lt;NA&gt;"}

"""AppTest: several channels of the loaded table side by side on the Signal page."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")

import noisevar as nv  # noqa: E402
from dashboard.widgets import blank_frame  # noqa: E402
from noisevar.io import load_table, pick_column  # noqa: E402


def _signal_page(sample: str) -> AppTest:
    at = AppTest.from_file(APP, default_timeout=120)
    at.switch_page("app_pages/Signal.py").run()
    at.button(key=f"sample_{sample}").click().run()
    assert not at.exception, [e.value for e in at.exception]
    return at


def _channel_table(at: AppTest):
    (frame,) = [d.value for d in at.dataframe if "channel" in d.value.columns]
    return frame


def test_three_sensors_side_by_side_equal_per_column_estimates():
    at = _signal_page("three_sensors.csv")
    assert "Channels side by side" in [s.value for s in at.subheader]
    frame = _channel_table(at)
    assert list(frame["channel"]) == ["sensor_a", "sensor_b", "sensor_c"]
    table = load_table(ROOT / "sample_data" / "three_sensors.csv")
    for _, row in frame.iterrows():
        est = nv.estimate(pick_column(table, row["channel"]))
        assert row["variance"] == pytest.approx(est.variance, rel=1e-12)
        assert row["ci95_high"] == pytest.approx(est.ci95[1], rel=1e-12)
    (ms,) = [m for m in at.multiselect if m.label == "Channels"]
    ms.set_value(["sensor_c", "sensor_a"]).run()
    assert list(_channel_table(at)["channel"]) == ["sensor_c", "sensor_a"]


def test_a_single_column_file_has_no_channel_picker():
    at = _signal_page("fast_slow.csv")
    assert "Channels side by side" not in [s.value for s in at.subheader]
    assert not [m for m in at.multiselect if m.label == "Channels"]


def test_channels_table_says_why_a_still_r_is_absent_and_never_none():
    at = _signal_page("three_sensors.csv")
    frame = _channel_table(at)
    for c in ("still_variance", "still_ci95_low", "still_ci95_high", "other_still_levels"):
        assert frame[c].isna().all(), c  # absent: drawn "—" (below), never "None"
    assert all("one still regime" in n for n in frame["still_note"])
    assert frame["variance"].dtype == float  # numbers stay numbers: the table sorts by value
    shown = blank_frame(frame).to_html()  # what the page draws: blank_frame's Styler
    assert "—" in shown and not {"None", "nan", "NaN", "&lt;NA&gt;"} & set(_cells(shown))
    assert at.get("download_button")  # the table's CSV


def _cells(html: str) -> list[str]:
    import re

    return [c.strip() for c in re.findall(r"<td[^>]*>(.*?)</td>", html)]


def test_a_tiny_value_is_written_whole_at_its_significant_digits():
    """A latitude's R of 5.7e-15 read "0.000000" (a per-column format reset every column
    to pandas' default); every float is written at the table's significant digits."""
    import pandas as pd

    frame = pd.DataFrame({"variance": [5.692e-15, 1897.404971], "dof": [36.6, None]})
    for styled in (
        blank_frame(frame, digits=4),
        blank_frame(frame, digits=4, formats={"dof": "%.1f"}),
    ):
        cells = _cells(styled.to_html())
        assert cells[0] == "5.692e-15" and cells[2] == "1897", cells
        assert "—" in cells

"""AppTest: a log uploaded on the Signal page: pick its topic, then its column."""

from __future__ import annotations

import sys
from pathlib import Path

from logfiles import imu_values, write_bag
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PX4 = ROOT / "tests" / "data" / "px4_sample_log_small.ulg"


def _page() -> AppTest:
    at = AppTest.from_file(APP, default_timeout=120)
    at.switch_page("app_pages/Signal.py").run()
    assert not at.exception, [e.value for e in at.exception]
    return at


def _topic_box(at: AppTest):
    return next(s for s in at.selectbox if s.label == "Topic")


def test_uploaded_bag_offers_its_topics(tmp_path):
    z = imu_values(400)
    mcap = next(write_bag(tmp_path / "b", z, "mcap").glob("*.mcap"))
    at = _page()
    at.file_uploader(key="upload").set_value(("robot.mcap", mcap.read_bytes(), "")).run()
    assert not at.exception, [e.value for e in at.exception]
    box = _topic_box(at)
    assert [o.split(" ")[0] for o in box.options] == ["/imu", "/level"]
    assert box.options[0] == "/imu (sensor_msgs/msg/Imu, 400 records, 400 Hz)"
    sig = at.session_state["nv_signal"]
    assert sig.table.kind == "rosbag" and "angular_velocity.x" in sig.table.data_columns
    assert abs(sig.sample_period - 1 / 400) < 1e-12
    box.set_value("/level").run()
    assert not at.exception and not at.error
    assert at.session_state["nv_signal"].table.data_columns == ["data"]


def test_uploaded_ulog_and_a_corrupt_log(tmp_path):
    at = _page()
    at.file_uploader(key="upload").set_value(("flight.ulg", PX4.read_bytes(), "")).run()
    assert not at.exception  # its first topic's column has no estimate: no traceback either
    _topic_box(at).set_value("sensor_combined").run()
    assert not at.exception and not at.error
    assert at.session_state["nv_signal"].table.n_rows == 1298
    at.file_uploader(key="upload").set_value(("cut.mcap", b"\x89MCAP0\r\n" + b"\0" * 64, "")).run()
    assert not at.exception
    assert len(at.error) == 1 and "MCAP file cut short" in at.error[0].value
    assert at.session_state["nv_signal"].table.n_rows == 1298  # the previous signal stays

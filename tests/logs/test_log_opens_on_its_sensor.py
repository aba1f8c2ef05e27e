"""A log opens where an engineer would: on its IMU's topic (not the first topic by name) and on
a sensor channel of it, never on a frame counter with drops."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from streamlit.testing.v1 import AppTest

from noisevar.io.logs import TopicInfo, default_topic, list_topics
from noisevar.io.table import LoadedTable

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PX4 = ROOT / "tests" / "data" / "px4_sample_log_small.ulg"


def _t(name: str, units: dict[str, str], fields: tuple[str, ...] = ("a", "b")) -> TopicInfo:
    return TopicInfo(name, "m", 10, 1.0, fields, units)


def test_default_topic_prefers_an_imu():
    markers = _t("/markers", {})
    odom = _t("/odom", {"a": "rad/s", "b": "m/s"})
    imu = _t("/zz/imu", {"a": "rad/s", "b": "m/s**2"})
    empty = TopicInfo("/aa", "m", 0, None, ("a",))
    assert default_topic([empty, markers, odom, imu]) is imu
    assert default_topic([markers, odom]) is odom
    assert default_topic([empty, markers]) is markers
    assert default_topic([empty]) is None


def test_px4_log_opens_on_sensor_combined():
    assert default_topic(list_topics(PX4)).name == "sensor_combined"
    at = AppTest.from_file(APP, default_timeout=180)
    at.switch_page("app_pages/Signal.py").run()
    at.file_uploader(key="upload").set_value(("flight.ulg", PX4.read_bytes(), "")).run()
    assert next(s for s in at.selectbox if s.label == "Topic").value == "sensor_combined"
    assert at.session_state["nv_signal"].column == "gyro_rad[0]"


def test_a_frame_counter_with_drops_is_not_the_first_signal():
    rng = np.random.default_rng(0)
    frames = np.cumsum(1 + (rng.random(500) < 0.05))  # rises by 1, by 2 where a frame dropped
    table = LoadedTable("m.csv", {"frame_number": frames.astype(float), "x": rng.normal(size=500)},
                        "text")  # fmt: skip
    assert table.first_signal == "x" and table.signals == ["x"]
    encoder = np.cumsum(rng.integers(0, 3, 500)).astype(float)  # holds and jumps: a signal
    table = LoadedTable("e.csv", {"ticks": encoder}, "text")
    assert table.first_signal == "ticks"

"""AppTest of issue 27's several-topic flow: upload a PX4 log, pick its gyroscope FIFO as the
signal and its accelerometer FIFO beside it, choose both sensors' columns on the Noise
model page and download a PX4 file with EKF2_GYR_NOISE and EKF2_ACC_NOISE."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest
from logfiles import write_ulog_imu_fifos
from streamlit.runtime.memory_media_file_storage import MemoryMediaFileStorage
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PX4 = ROOT / "tests" / "data" / "px4_sample_log_small.ulg"
GYRO, ACCEL = "sensor_gyro_fifo", "sensor_accel_fifo"


@pytest.fixture
def downloads(monkeypatch) -> dict[str, bytes]:
    """Every file the page hands a download button, by file name."""
    files: dict[str, bytes] = {}
    keep = MemoryMediaFileStorage.load_and_get_id

    def load_and_get_id(self, data, mimetype, kind, filename=None):
        if filename is not None and isinstance(data, bytes | str):
            files[filename] = data.encode() if isinstance(data, str) else data
        return keep(self, data, mimetype, kind, filename)

    monkeypatch.setattr(MemoryMediaFileStorage, "load_and_get_id", load_and_get_id)
    return files


def _ok(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]
    assert not at.error, [e.value for e in at.error]


def test_two_fifo_topics_to_a_px4_file(tmp_path, downloads):
    path = tmp_path / "flight.ulg"
    truth = write_ulog_imu_fifos(path, PX4, seconds=20.0, rates=(800.0, 400.0), seed=3)
    at = AppTest.from_file(APP, default_timeout=180)
    at.switch_page("app_pages/Signal.py").run()
    at.file_uploader(key="upload").set_value(("flight.ulg", path.read_bytes(), "")).run()
    next(s for s in at.selectbox if s.label == "Topic").set_value(GYRO).run()
    _ok(at)
    more = next(m for m in at.multiselect if m.label.startswith("More topics"))
    assert GYRO not in more.options and ACCEL in [o.split(" ")[0] for o in more.options]
    more.set_value([ACCEL]).run()
    _ok(at)
    sig = at.session_state["nv_signal"]
    assert list(sig.topics.tables) == [GYRO, ACCEL]

    at.switch_page("app_pages/Noise_model.py").run()
    _ok(at)
    gyro_box = at.multiselect(key="nm_gyro")
    assert gyro_box.options == [f"{t}/{a}" for t in (GYRO, ACCEL) for a in "xyz"]
    assert any("sensor_gyro_fifo 800 Hz, sensor_accel_fifo 400 Hz" in c.value for c in at.caption)
    gyro_box.set_value([f"{GYRO}/{a}" for a in "xyz"])
    at.multiselect(key="nm_accel").set_value([f"{ACCEL}/{a}" for a in "xyz"]).run()
    _ok(at)
    text = downloads["px4_ekf2.params"].decode()
    values = {r.split("\t")[2]: float(r.split("\t")[3]) for r in text.splitlines() if r[:1] == "1"}
    ekf = 100.0**0.5  # discrete at 1/EKF2_PREDICT_US = 100 Hz, as the file says
    assert values["EKF2_GYR_NOISE"] == pytest.approx(truth[GYRO] * ekf, rel=0.05)
    assert values["EKF2_ACC_NOISE"] == pytest.approx(truth[ACCEL] * ekf, rel=0.05)
    assert "the gyroscope was sampled at 800 Hz, the accelerometer at 400 Hz" in text

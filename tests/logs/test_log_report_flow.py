"""AppTest of issue 27's flow: upload a log, pick its topic, see the Allan fit, choose best
fit or conservative, download every consumer file, their zip and the HTML report."""

from __future__ import annotations

import html
import io
import sys
import zipfile
from pathlib import Path

import numpy as np
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PX4 = ROOT / "tests" / "data" / "px4_sample_log_small.ulg"
GYRO = [f"gyro_rad[{i}]" for i in range(3)]
ACCEL = [f"accelerometer_m_s2[{i}]" for i in range(3)]


def _flow() -> AppTest:
    at = AppTest.from_file(APP, default_timeout=120)
    at.switch_page("app_pages/Signal.py").run()
    at.file_uploader(key="upload").set_value(("flight.ulg", PX4.read_bytes(), "")).run()
    next(s for s in at.selectbox if s.label == "Topic").set_value("sensor_combined").run()
    assert not at.exception and not at.error
    at.switch_page("app_pages/Noise_model.py").run()
    assert not at.exception and not at.error
    at.multiselect(key="nm_gyro").set_value(GYRO)
    at.multiselect(key="nm_accel").set_value(ACCEL).run()
    assert not at.exception and not at.error
    return at


def test_log_to_every_consumer_file_and_the_report():
    from dashboard.sections.filter_configs import report_html
    from noisevar.io import pick_column
    from noisevar.noise_model import exports, inertial_noise

    at = _flow()
    assert at.text_input(key="nm_gyro_unit").value == "rad/s"  # the log's own unit
    assert at.get("plotly_chart"), "no Allan figure"
    keys = {b.key for b in at.get("download_button")}
    assert {f"nm_dl_{k}" for k in exports.CONSUMERS} | {"nm_dl_zip", "nm_dl_report"} <= keys
    at.radio(key="nm_variant").set_value("conservative").run()
    assert not at.exception and not at.error
    assert any("factors over the best fit" in c.value for c in at.caption)

    # the report the button builds, from the page's own signal
    sig = at.session_state["nv_signal"]
    rate = at.number_input(key="nm_rate").value
    fits = {
        c: inertial_noise(np.asarray(pick_column(sig.table, c), float), rate, unit=u)
        for cols, u in ((GYRO, "rad/s"), (ACCEL, "m/s^2"))
        for c in cols
    }
    model = exports.imu_model(
        [fits[c] for c in GYRO], [fits[c] for c in ACCEL], variant="conservative"
    )
    files = exports.export(model, "all")
    names = {f.filename for f in files}
    with zipfile.ZipFile(io.BytesIO(exports.zip_exports(files))) as z:
        assert set(z.namelist()) == names
    axes = [("gyroscope", c, fits[c]) for c in GYRO] + [
        ("accelerometer", c, fits[c]) for c in ACCEL
    ]
    text = report_html(sig, model, files, axes)
    assert text.count("Verdict, ") == 6 and "CONSERVATIVE" in text
    assert html.escape(sig.label) in text.split("</h1>", 1)[0]
    for f in files:
        assert html.escape(f.filename) in text
        for v in f.values:  # each value's unit, kind and conversion line, in its row
            row = f"<td>{html.escape(v.name)}</td>"
            assert row in text, v.name
            tail = text.split(row, 1)[1].split("</tr>", 1)[0]
            assert html.escape(v.unit) in tail and html.escape(v.how) in tail


def test_a_flight_logs_parameters_reach_the_filter_files():
    """The Filter configs' files take the EKF's step from the flight log, as ``noisevar imu
    --export`` does: before, the page wrote EKF3's names at 83.3 Hz for a 50 Hz EKF2 Plane
    (``SCHED_LOOP_RATE`` 50, ``AHRS_EKF_TYPE`` 2) that the command line wrote as EKF2's."""
    from dashboard.state import reselect

    log = ROOT / "tests" / "data" / "ardupilot_pymavlink_test.BIN"
    at = AppTest.from_file(APP, default_timeout=120)
    at.switch_page("app_pages/Signal.py").run()
    at.file_uploader(key="upload").set_value(("flight.BIN", log.read_bytes(), "")).run()
    next(s for s in at.selectbox if s.label == "Topic").set_value("IMU").run()
    assert not at.exception and not at.error
    sig = at.session_state["nv_signal"]
    assert sig.log_params["SCHED_LOOP_RATE"] == 50.0
    assert sig.log_params["AHRS_EKF_TYPE"] == 2.0
    other = next(c for c in sig.table.data_columns if c != sig.column)
    assert reselect(sig, other, sig.sample_period).log_params == sig.log_params

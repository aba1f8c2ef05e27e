"""AppTest: the Noise model page's filter configs (every consumer's file, best or conservative)."""

from __future__ import annotations

import sys
from pathlib import Path

from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PAGE = "app_pages/Noise_model.py"
SIG = "gen:noise-step;n=4000;seed=1"


def _open() -> AppTest:
    app = AppTest.from_file(APP, default_timeout=90)
    app.query_params["sig"] = SIG
    app.switch_page(PAGE).run()
    assert not app.exception
    return app


def test_every_consumer_file_best_then_conservative():
    at = _open()
    cols = at.multiselect(key="nm_gyro").options
    at.multiselect(key="nm_gyro").set_value([cols[0]])
    at.multiselect(key="nm_accel").set_value([cols[0]]).run()
    assert not at.exception and not at.error
    keys = {b.key for b in at.get("download_button")}
    assert {"nm_dl_px4", "nm_dl_kalibr", "nm_dl_vins", "nm_dl_zip"} <= keys
    assert any("N " in c.value and "rad/s/√Hz" in c.value for c in at.caption)
    at.radio(key="nm_variant").set_value("conservative").run()
    assert not at.exception and not at.error
    assert any("factors over the best fit" in c.value for c in at.caption)


def test_a_bad_unit_is_one_error():
    at = _open()
    cols = at.multiselect(key="nm_gyro").options
    at.multiselect(key="nm_gyro").set_value([cols[0]])
    at.multiselect(key="nm_accel").set_value([cols[0]])
    at.text_input(key="nm_gyro_unit").set_value("furlong/").run()
    assert not at.exception
    assert len(at.error) == 1 and "unknown unit 'furlong/'" in at.error[0].value

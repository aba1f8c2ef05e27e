"""AppTest: one answer on every page (issue 28 item 4).

The record's verdict and R (method auto, as the Estimator page) appear on Compare, Noise
model and Two sensors with the same sentence; a page whose own R is another quantity says
why; Two sensors flags columns that do not measure the same quantity.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")

import noisevar  # noqa: E402
from dashboard.state import SIGNAL_KEY, UNITS_KEY, make_signal  # noqa: E402
from noisevar.estimators.answer import WHY_DIFFERENT, record_answer  # noqa: E402
from noisevar.io import load_table  # noqa: E402

RATE, N = 100.0, 4000


def _imu(seed: int = 5) -> dict[str, np.ndarray]:
    """Three axes of one accelerometer (not three sensors of one quantity)."""
    rng = np.random.default_rng(seed)
    k = np.arange(N)
    return {
        "Acc_X": np.sin(2 * np.pi * k / 400) + 0.05 * rng.standard_normal(N),
        "Acc_Y": 0.5 * np.cos(2 * np.pi * k / 300) + 0.05 * rng.standard_normal(N),
        "Acc_Z": 9.81 + 0.05 * rng.standard_normal(N),
    }


def _open(columns: dict[str, np.ndarray], page: str, unit: str = "") -> AppTest:
    frame = pd.DataFrame({"t": np.arange(N) / RATE, **columns})
    table = load_table(frame.to_csv(index=False).encode(), "imu.csv")
    at = AppTest.from_file(APP, default_timeout=180)
    at.session_state[SIGNAL_KEY] = make_signal(table, None, 1.0 / RATE, "upload", None)
    if unit:
        at.session_state[UNITS_KEY] = unit
    at.switch_page(page).run()
    assert not at.exception, [e.value for e in at.exception]
    return at


def _boxes(at: AppTest) -> list[str]:
    return [b.value for b in [*at.info, *at.warning]]


def test_the_same_answer_on_compare_noise_model_and_two_sensors() -> None:
    cols = _imu()
    sentence = record_answer(noisevar.estimate(cols["Acc_X"])).sentence("m/s^2")
    for page in ("app_pages/Compare.py", "app_pages/Noise_model.py"):
        at = _open(cols, page, unit="m/s^2")
        assert any(f"The record's answer (Estimator page): {sentence}" in b for b in _boxes(at)), (
            page
        )
    at = _open(cols, "app_pages/Compare.py")
    assert any(WHY_DIFFERENT["method"] in c.value for c in at.caption)


def test_two_sensors_flags_three_axes_as_not_one_quantity() -> None:
    at = _open(_imu(), "app_pages/Two_sensors.py")
    # three axes of one sensor are not picked for the user (their samples do not correlate)
    assert at.multiselect(key="ts_cols").value == []
    assert any("No two columns of this table follow the same signal" in b for b in _boxes(at))
    at.multiselect(key="ts_cols").set_value(["Acc_X", "Acc_Y", "Acc_Z"]).run()
    (flag,) = [w.value for w in at.warning if "may not measure the same quantity" in w.value]
    assert "Acc_X and Acc_Z differ in level" in flag and "varies" in flag
    assert any(WHY_DIFFERENT["redundant"] in c.value for c in at.caption)
    assert any(b.startswith("**Acc_Z**: ") for b in _boxes(at))  # each sensor's own answer


def test_two_sensors_of_one_quantity_are_not_flagged() -> None:
    rng = np.random.default_rng(9)
    s = np.cumsum(rng.normal(0, 0.05, N))
    cols = {"a": s + rng.normal(0, 1.0, N), "b": s + rng.normal(0, 2.0, N)}
    at = _open(cols, "app_pages/Two_sensors.py")
    # a walk under noise twice its size: too little signal to be picked for the user
    assert at.multiselect(key="ts_cols").value == []
    at.multiselect(key="ts_cols").set_value(["a", "b"]).run()
    assert at.metric, "no estimate drawn"
    assert not any("may not measure the same quantity" in w.value for w in at.warning)


def test_the_files_unit_is_every_pages_unit_unless_the_user_gives_one() -> None:
    """A CSV header's ``[unit]`` (a log's field unit) reaches the pages as it reaches
    ``noisevar estimate``: the answer box says it; a unit typed on the Signal page wins."""
    cols = _imu()
    cols = {"Acc_X [m/s^2]": cols["Acc_X"]}
    sentence = record_answer(noisevar.estimate(cols["Acc_X [m/s^2]"])).sentence("m/s^2")
    at = _open(cols, "app_pages/Compare.py")
    assert any(sentence in b for b in _boxes(at))
    other = record_answer(noisevar.estimate(cols["Acc_X [m/s^2]"])).sentence("g")
    at = _open(cols, "app_pages/Compare.py", unit="g")
    assert any(other in b for b in _boxes(at)) and not any(sentence in b for b in _boxes(at))

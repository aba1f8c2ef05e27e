"""AppTest: other still levels shown as data where a user chooses R (issue 26 item 5, pages26c).

A record resting at two levels (a short rest at the floor, a long one at 2.2x: another
posture) has its second level in ``NoiseDiagnostics.other_still``. The Estimator's noise
panel, the Noise model, Two sensors and Fleet pages show it as a small table (stretch, share
of the record, level and interval over the still R, the R there), the rows of
:meth:`~noisevar.estimators.answer.RecordAnswer.still_level_rows`.
"""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")

import noisevar  # noqa: E402
from dashboard.state import SIGNAL_KEY, make_signal  # noqa: E402
from noisevar import synth  # noqa: E402
from noisevar.estimators.answer import STILL_LEVELS_NOTE, record_answer  # noqa: E402
from noisevar.io import load_table  # noqa: E402

RATE = 100.0

#: the whole motion record's r interval reaches past a float (an infinite upper bound)
pytestmark = pytest.mark.filterwarnings("ignore:overflow encountered in exp:RuntimeWarning")


def postures(seed: int, raised: float = 2.2) -> np.ndarray:
    """Two still levels, motion between (:func:`noisevar.synth.postures`)."""
    return synth.postures(raised, rest=1500, rng=seed)


def _csv(columns: dict[str, np.ndarray]) -> bytes:
    n = len(next(iter(columns.values())))
    return pd.DataFrame({"t": np.arange(n) / RATE, **columns}).to_csv(index=False).encode()


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def _open_with(columns: dict[str, np.ndarray], page: str) -> AppTest:
    table = load_table(_csv(columns), "postures.csv")
    at = AppTest.from_file(APP, default_timeout=180)
    at.session_state[SIGNAL_KEY] = make_signal(table, None, 1.0 / RATE, "upload", None)
    at.switch_page(page).run()
    _clean(at)
    return at


def _level_tables(at: AppTest) -> list[pd.DataFrame]:
    return [d.value for d in at.dataframe if "Level (x still R)" in d.value.columns]


def _expected(z: np.ndarray) -> list[dict[str, str]]:
    rows = record_answer(noisevar.estimate(z)).still_level_rows("")
    assert len(rows) == 1  # the seeded record has its second level
    return rows


@pytest.fixture(scope="module")
def record() -> np.ndarray:
    return postures(0)


def test_noise_model_shows_the_other_still_level(record) -> None:
    at = _open_with({"gyro": record}, "app_pages/Noise_model.py")
    (table,) = _level_tables(at)
    assert table.to_dict("records") == _expected(record)
    assert any(c.value == STILL_LEVELS_NOTE for c in at.caption)


def test_two_sensors_show_each_sensors_levels() -> None:
    cols = {"a": postures(2), "b": postures(3)}
    at = _open_with(cols, "app_pages/Two_sensors.py")
    _clean(at.multiselect(key="ts_cols").set_value(["a", "b"]).run())  # noise: picked by hand
    tables = _level_tables(at)
    assert [t.to_dict("records") for t in tables] == [_expected(z) for z in cols.values()]
    assert any(c.value == f"**a**: {STILL_LEVELS_NOTE}" for c in at.caption)


def test_estimator_noise_panel_shows_the_other_still_level(record) -> None:
    at = _open_with({"gyro": record}, "app_pages/Estimator.py")
    assert _level_tables(at) == []  # SOMD (the page's default) has no still R
    at.selectbox(key="est_method").select("auto").run()
    _clean(at)
    (table,) = _level_tables(at)
    assert table.to_dict("records") == _expected(record)


def test_one_level_shows_no_table() -> None:
    at = _open_with({"gyro": postures(0, raised=1.0)}, "app_pages/Noise_model.py")
    assert _level_tables(at) == []
    assert not any(c.value == STILL_LEVELS_NOTE for c in at.caption)


def test_fleet_shows_the_moving_sensors_levels(tmp_path) -> None:
    rng = np.random.default_rng(7)
    paths = []
    for i in range(5):
        z = postures(0) if i == 4 else rng.normal(0.0, 1.0, 2900)
        path = tmp_path / f"imu_{i}.csv"
        path.write_bytes(_csv({"ax": z}))
        paths.append(str(path))
    frame = noisevar.batch(paths, progress=False)
    at = AppTest.from_file(APP, default_timeout=180)
    at.session_state["nv_fleet_table"] = frame
    at.session_state["nv_fleet_label"] = "five IMUs"
    at.switch_page("app_pages/Fleet.py").run()
    _clean(at)
    (table,) = _level_tables(at)
    expected = [{"Sensor": "imu_4.csv · ax"} | r for r in _expected(postures(0))]
    assert table.to_dict("records") == expected

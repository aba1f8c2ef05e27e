"""AppTest: the regime warning and "use the still regimes only" on the Noise model, Two sensors
and Fleet pages (issue 26, item 5): the R shown is the estimate's, or its ``.still``'s."""

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
from dashboard.sections.regimes import STILL_LABEL  # noqa: E402
from dashboard.state import SIGNAL_KEY, make_signal  # noqa: E402
from dashboard.widgets import fmt  # noqa: E402
from noisevar.io import load_table  # noqa: E402

RATE = 100.0
STILL = 2000
N = 6000

#: the whole motion record's r interval reaches past a float (an infinite upper bound)
pytestmark = pytest.mark.filterwarnings("ignore:overflow encountered in exp:RuntimeWarning")


def still_then_motion(seed: int, n: int = N) -> np.ndarray:
    """White noise of std 0.15, still for 2000 samples, then a large oscillation (motion)."""
    rng = np.random.default_rng(seed)
    z = 0.15 * rng.standard_normal(n)
    k = np.arange(STILL, n)
    z[STILL:] += 3.0 * np.sin(2 * np.pi * k / 7.0) * (1 + 0.5 * rng.standard_normal(k.size))
    return z


def _csv(columns: dict[str, np.ndarray]) -> bytes:
    t = np.arange(N) / RATE
    frame = pd.DataFrame({"t": t, **columns})
    return frame.to_csv(index=False).encode()


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def _open_with(columns: dict[str, np.ndarray], page: str) -> AppTest:
    """The page with a table of these columns loaded as the session's signal."""
    table = load_table(_csv(columns), "moving.csv")
    at = AppTest.from_file(APP, default_timeout=180)
    at.session_state[SIGNAL_KEY] = make_signal(table, None, 1.0 / RATE, "upload", None)
    at.switch_page(page).run()
    _clean(at)
    return at


def _warnings(at: AppTest) -> list[str]:
    return [w.value for w in at.warning]


def _tick(at: AppTest, key: str) -> AppTest:
    box = at.checkbox(key=key)
    assert box.label == STILL_LABEL and not box.value
    box.check().run()
    _clean(at)
    return at


def test_noise_model_warns_and_fits_the_still_stretch() -> None:
    z = still_then_motion(1)
    est = noisevar.estimate(z)
    assert est.diagnostics.level_varies and est.still is not None
    at = _open_with({"gyro": z}, "app_pages/Noise_model.py")
    assert any(est.diagnostics.verdict in w for w in _warnings(at))
    r = next(m for m in at.metric if m.label == "Noise variance R")
    assert r.value == fmt(est.variance)
    # no fit says it ran on the still stretch yet (the IEEE-952 misfit note may advise it)
    assert not any(c.value.startswith("regimes='still'") for c in at.caption)
    assert any("do not describe the Allan deviation" in w for w in _warnings(at))
    _tick(at, "nm_regimes")
    r = next(m for m in at.metric if m.label == "Noise variance R")
    assert r.value == fmt(est.still.variance)
    assert any("still regimes only" in c.value for c in at.caption)  # why it differs
    # the Allan deviation, the terms and the Kalman fits say which stretch they used
    notes = [c.value for c in at.caption if c.value.startswith("regimes='still'")]
    assert len(notes) >= 2 and all("longest still stretch" in n for n in notes)
    from dashboard.sections.noise_model_fit import SNIPPET_KEY

    at.session_state[SNIPPET_KEY] = True  # the filterpy snippet, sent once opened
    at.run()
    assert any("regimes='still'" in c.value for c in at.code)


def test_noise_model_offers_no_choice_for_one_regime() -> None:
    z = 0.15 * np.random.default_rng(3).standard_normal(N)
    at = _open_with({"gyro": z}, "app_pages/Noise_model.py")
    assert not any(STILL_LABEL == c.label for c in at.checkbox)
    r = next(m for m in at.metric if m.label == "Noise variance R")
    assert r.value == fmt(noisevar.estimate(z).variance)


def test_two_sensors_warn_per_sensor_and_quote_the_still_r() -> None:
    cols = {"a": still_then_motion(1), "b": still_then_motion(2)}
    est = {c: noisevar.estimate(z) for c, z in cols.items()}
    at = _open_with(cols, "app_pages/Two_sensors.py")
    for c, e in est.items():
        assert any(w.startswith(f"**{c}**: {e.diagnostics.verdict}") for w in _warnings(at))

    def shown() -> dict[str, str]:
        return {m.label.split(":")[0]: m.value for m in at.metric if "noise variance" in m.label}

    assert shown() == {c: fmt(e.variance) for c, e in est.items()}
    _tick(at, "ts_regimes")
    assert shown() == {c: fmt(e.still.variance) for c, e in est.items()}
    table = at.dataframe[0].value
    np.testing.assert_allclose(
        table["single-signal estimate (auto)"], [e.still.variance for e in est.values()]
    )


@pytest.fixture(scope="module")
def fleet_table(tmp_path_factory) -> tuple[pd.DataFrame, Path]:
    """Six IMUs of one channel, std 0.15; the sixth moved after a still start."""
    folder = tmp_path_factory.mktemp("fleet")
    rng = np.random.default_rng(7)
    paths = []
    for i in range(6):
        z = still_then_motion(11) if i == 5 else 0.15 * rng.standard_normal(N)
        path = folder / f"imu_{i}.csv"
        path.write_bytes(_csv({"ax": z}))
        paths.append(path)
    return noisevar.batch([str(p) for p in paths], progress=False), paths[5]


def test_fleet_warns_and_compares_the_still_regimes(fleet_table) -> None:
    frame, moved = fleet_table
    z = np.asarray(pd.read_csv(moved)["ax"], dtype=float)
    est = noisevar.estimate(z)
    at = AppTest.from_file(APP, default_timeout=180)
    at.session_state["nv_fleet_table"] = frame
    at.session_state["nv_fleet_label"] = "six IMUs"
    at.switch_page("app_pages/Fleet.py").run()
    _clean(at)
    (warning,) = [w for w in _warnings(at) if "noise level varies" in w]
    assert f"imu_5.csv · ax: {est.diagnostics.verdict}" in warning
    metrics = {m.label: m.value for m in at.metric}
    assert metrics["Flagged"] == "1"  # the moving unit, on its whole record

    def std_of_moved() -> float:
        scores = at.dataframe[0].value
        return float(scores.loc[scores["file"] == str(moved), "std"].iloc[0])

    assert std_of_moved() == pytest.approx(np.sqrt(est.variance), rel=1e-9)
    _tick(at, "fl_regimes")
    assert std_of_moved() == pytest.approx(np.sqrt(est.still.variance), rel=1e-9)
    assert {m.label: m.value for m in at.metric}["Flagged"] == "0"


def test_noise_model_still_too_short_says_so() -> None:
    """A still start too short for R's method: ticking the box shows an error and the page
    stays on the whole record's R, never that R as the still one (issue 26)."""
    rng = np.random.default_rng(0)
    t = np.arange(500)
    z = 0.03 * rng.normal(size=500)  # still for 64 samples, then motion
    z[64:] += 2.0 * np.sin(2 * np.pi * t[64:] / 25.0) + 0.3 * rng.normal(size=436)
    est = noisevar.estimate(z)
    gap = noisevar.estimators.regimes.why_no_still(est)
    assert gap is not None and est.diagnostics.level_varies
    csv = pd.DataFrame({"t": t / RATE, "gyro": z}).to_csv(index=False).encode()
    at = AppTest.from_file(APP, default_timeout=180)
    table = load_table(csv, "short.csv")
    at.session_state[SIGNAL_KEY] = make_signal(table, None, 1.0 / RATE, "upload", None)
    at.switch_page("app_pages/Noise_model.py").run()
    _clean(at)
    _tick(at, "nm_regimes")
    assert any(gap in e.value for e in at.error), [e.value for e in at.error]
    r = next(m for m in at.metric if m.label == "Noise variance R")
    assert r.value == fmt(est.variance)

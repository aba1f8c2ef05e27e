"""One record, one answer on every page and in every export (issue 26 item 5).

Three seeded records, each a CSV with a time column: a signal with a gap in its time column,
a motion record with a still start (:func:`noisevar.synth.still_start`) and a record resting
at two still levels (the record of ``test_app_still_levels.py``). Each surface that quotes
the record's R (the whole record's, its still regimes', the verdict) is read as a user reads
it: the Estimator page (method auto) and its exports, the Compare page's auto row, the
Signal page's channels table, Two sensors, the Fleet page on one file, the Noise model page,
``noisevar estimate --format json``, ``noisevar batch`` and Python ``noisevar.estimate(z,
t=t)``. They run one code path, so the floats must be bit-identical (a formatted value must
be the format of that float).
"""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
import pandas as pd
import pytest
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")

import noisevar as nv  # noqa: E402
from dashboard import cache  # noqa: E402
from dashboard.sections.estimator_results import EXPORT_KEY, estimate_csv  # noqa: E402
from dashboard.state import SIGNAL_KEY, make_signal  # noqa: E402
from dashboard.widgets import fmt  # noqa: E402
from noisevar import synth  # noqa: E402
from noisevar.cli import main  # noqa: E402
from noisevar.estimators.answer import record_answer  # noqa: E402
from noisevar.io import load_table  # noqa: E402

RATE = 100.0

#: a motion record's r interval reaches past a float (an infinite upper bound)
pytestmark = pytest.mark.filterwarnings("ignore:overflow encountered in exp:RuntimeWarning")


def _gap_record(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A slow signal in white noise, 2 s missing from its time column."""
    n = 3000
    t = np.arange(n) / RATE
    t[n // 2 :] += 2.0
    return t, np.sin(t) + rng.normal(0, 0.1, n)


def _still_start(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """Still for its first 800 samples, then motion."""
    return np.arange(3000) / RATE, synth.still_start(800, n=3000, rng=rng, sigma=0.03)


def _postures(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray]:
    """A short rest at σ² = 1, a long one at 2.2 (another posture), motion between."""
    parts = []
    for kind, n in (("s", 300), ("m", 400), ("r", 1500), ("m", 400), ("s", 300)):
        k = np.arange(n)
        if kind == "m":
            parts.append(30 * np.sin(2 * np.pi * k / 40) * np.hanning(n) + rng.normal(0, 30, n))
        else:
            parts.append(rng.normal(0.0, np.sqrt(2.2 if kind == "r" else 1.0), n))
    z = np.concatenate(parts)
    return np.arange(z.size) / RATE, z


RECORDS = {"gap": _gap_record, "still_start": _still_start, "postures": _postures}


def _clean(at: AppTest) -> AppTest:
    assert not at.exception, [e.value for e in at.exception]
    return at


def _first_clause(verdict: str) -> str:
    return verdict.split(":")[0]


@pytest.fixture(scope="module", params=list(RECORDS))
def record(request, tmp_path_factory):
    """The record's file (columns t, z and a second sensor w), its z, t and Python answer."""
    t, z = RECORDS[request.param](np.random.default_rng(26))
    w = 1.5 * z + np.random.default_rng(27).normal(0, 0.05, z.size)
    path = tmp_path_factory.mktemp(request.param) / f"{request.param}.csv"
    pd.DataFrame({"t": t, "z": z, "w": w}).to_csv(path, index=False)
    est = nv.estimate(z, t=t)
    if request.param != "gap":
        assert est.still is not None and est.diagnostics.level_varies
    if request.param == "postures":
        assert est.diagnostics.other_still
    return {"name": request.param, "path": path, "t": t, "z": z, "est": est}


def _page(record, page: str, **state) -> AppTest:
    table = load_table(record["path"])
    at = AppTest.from_file(APP, default_timeout=180)
    at.session_state[SIGNAL_KEY] = make_signal(table, "z", table.sample_period, "upload", None)
    for key, value in state.items():
        at.session_state[key] = value
    at.switch_page(page).run()
    return _clean(at)


def _boxes(at: AppTest) -> list[str]:
    return [b.value for b in [*at.info, *at.warning, *at.success, *at.error]]


def _says(at: AppTest, text: str) -> bool:
    return any(text in b for b in _boxes(at))


def _still(est) -> float | None:
    return None if est.still is None else float(est.still.variance)


def test_python_command_line_and_batch(record, capsys, tmp_path) -> None:
    est = record["est"]
    assert main(["estimate", str(record["path"]), "--column", "z", "--format", "json"]) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["variance"] == est.variance
    assert (out["ci95_low"], out["ci95_high"]) == est.ci95
    assert out["still_variance"] == _still(est)
    assert out["diagnostics"]["verdict"] == est.diagnostics.verdict
    rows_path = tmp_path / "rows.csv"
    assert main(["batch", str(record["path"]), "--out", str(rows_path), "--quiet"]) == 0
    row = pd.read_csv(rows_path).set_index("channel").loc["z"]
    assert row["variance"] == est.variance
    still = row["still_variance"]
    assert (None if pd.isna(still) else float(still)) == _still(est)
    assert _first_clause(str(row["verdict"])) == _first_clause(est.diagnostics.verdict)
    assert row["verdict"] == est.diagnostics.verdict
    # the other still levels (a second posture), the same numbers in JSON and in the row
    levels = [
        {"start": s.start, "stop": s.stop, "ratio": s.ratio, "ci95_low": s.lo, "ci95_high": s.hi}
        for s in est.diagnostics.other_still
    ]
    assert out["diagnostics"].get("other_still_levels", []) == levels
    in_row = row.get("other_still_levels")
    assert (json.loads(in_row) if isinstance(in_row, str) else []) == levels


def test_dashboard_functions_and_exports(record) -> None:
    est = record["est"]
    table = load_table(record["path"])
    sig = make_signal(table, "z", table.sample_period, "upload", None)
    shown = cache.estimate(sig, "auto", {})
    assert shown.variance == est.variance and _still(shown) == _still(est)
    assert cache.column_estimate(sig, "z").variance == est.variance
    assert cache.fast_rows(sig, ["auto"], {})[0].estimate.variance == est.variance
    rows = dict(
        line.split(",", 1) for line in estimate_csv(shown, None).splitlines()[1:] if "," in line
    )
    assert float(rows["variance"]) == est.variance  # read back, the same float
    assert float(rows["ci95_high"]) == est.ci95[1]
    assert record_answer(est).sentence() in estimate_csv(shown, None)


def test_estimator_page_and_its_config(record) -> None:
    est = record["est"]
    at = _page(record, "app_pages/Estimator.py", est_method="auto", **{EXPORT_KEY: True})
    metrics = {m.label: m.value for m in at.metric}
    assert metrics["Noise variance"] == fmt(est.variance)
    assert _says(at, est.diagnostics.verdict)
    (cfg,) = [json.loads(c.value) for c in at.code if c.value.lstrip().startswith("{")]
    assert cfg["method"] == "auto"
    assert cfg["record"]["answer"] == record_answer(est).sentence()


def test_compare_and_channels_tables(record) -> None:
    est = record["est"]
    at = _page(record, "app_pages/Compare.py")
    (table,) = [d.value for d in at.dataframe if "95 % low" in d.value.columns]
    auto = table.set_index("method").loc["auto"]
    assert auto["variance"] == est.variance and auto["95 % low"] == est.ci95[0]
    assert _says(at, record_answer(est).sentence())
    at = _page(record, "app_pages/Signal.py")
    assert {m.label: m.value for m in at.metric}["Noise std (auto)"] == fmt(est.std)
    assert _says(at, record_answer(est).sentence())
    (channels,) = [d.value for d in at.dataframe if "channel" in d.value.columns]
    row = channels.set_index("channel").loc["z"]
    assert row["variance"] == est.variance
    still = row["still_variance"]
    assert (None if still == "—" or pd.isna(still) else float(still)) == _still(est)
    assert _says(_page(record, "app_pages/Home.py"), record_answer(est).sentence())


def test_two_sensors_page(record) -> None:
    est = record["est"]
    at = _page(record, "app_pages/Two_sensors.py")
    # picked by hand where the page picks none (a record of noise regimes: no signal to follow)
    _clean(at.multiselect(key="ts_cols").set_value(["z", "w"]).run())
    metrics = {m.label: m.value for m in at.metric}
    assert metrics["z: noise variance"] == fmt(est.variance)
    (table,) = [d.value for d in at.dataframe if "sensor" in d.value.columns]
    assert table.set_index("sensor").loc["z", "single-signal estimate (auto)"] == est.variance
    assert any(b.startswith(f"**z**: {est.diagnostics.verdict}") for b in _boxes(at))
    assert _says(at, record_answer(est).sentence())
    if est.still is not None:
        at.checkbox(key="ts_regimes").check().run()
        _clean(at)
        metrics = {m.label: m.value for m in at.metric}
        assert metrics["z: noise variance"] == fmt(est.still.variance)
        (table,) = [d.value for d in at.dataframe if "sensor" in d.value.columns]
        still = table.set_index("sensor").loc["z", "single-signal estimate (auto)"]
        assert still == est.still.variance


def test_fleet_page_on_one_file(record) -> None:
    est = record["est"]
    frame = nv.batch([str(record["path"])], progress=False)
    at = AppTest.from_file(APP, default_timeout=180)
    at.session_state["nv_fleet_table"] = frame
    at.session_state["nv_fleet_label"] = "one file"
    at.switch_page("app_pages/Fleet.py").run()
    _clean(at)
    (batch,) = [d.value for d in at.dataframe if "still_variance" in d.value.columns]
    row = batch.set_index("channel").loc["z"]
    assert row["variance"] == est.variance
    still = row["still_variance"]
    assert (None if still == "—" or pd.isna(still) else float(still)) == _still(est)
    if est.diagnostics.level_varies:
        (warning,) = [w.value for w in at.warning if "noise level varies" in w.value]
        assert f"· z: {est.diagnostics.verdict}" in warning
        at.checkbox(key="fl_regimes").check().run()
        _clean(at)
        (scores,) = [d.value for d in at.dataframe if "sentence" in d.value.columns]
        scores = scores.set_index("channel")
        assert scores.loc["z", "std"] == pytest.approx(np.sqrt(est.still.variance), rel=1e-12)


def test_noise_model_page(record) -> None:
    from noisevar.format import eng

    est = record["est"]
    at = _page(record, "app_pages/Noise_model.py")
    r = next(m for m in at.metric if m.label == "Noise variance R")
    assert r.value == fmt(est.variance)
    assert _says(at, est.diagnostics.verdict)
    # the Kalman fit's check quotes the same R: it read the record without its times (its
    # gaps not split), 26.46 beside the page's 27.95 m² on an RTKLIB record
    (check,) = [b for b in _boxes(at) if "r and the record's R" in b]
    assert f"the record's R = {eng(est.variance)} " in check, check
    if est.still is not None:
        at.checkbox(key="nm_regimes").check().run()
        _clean(at)
        r = next(m for m in at.metric if m.label == "Noise variance R")
        assert r.value == fmt(est.still.variance)


def test_the_files_unit_is_the_pages_unit(tmp_path, capsys) -> None:
    """A column that declares its unit (``z [m]``) is in metres on the pages and in their
    exports, as ``noisevar estimate`` says it (before, the pages said no unit unless one was
    typed on the Signal page)."""
    t, z = _gap_record(np.random.default_rng(26))
    path = tmp_path / "metres.csv"
    pd.DataFrame({"t": t, "z [m]": z}).to_csv(path, index=False)
    est = nv.estimate(z, t=t)
    assert main(["estimate", str(path), "--format", "json"]) == 0
    assert json.loads(capsys.readouterr().out)["unit"] == "m"
    sentence = record_answer(est).sentence("m")
    table = load_table(path)
    for page, state in (("Signal", {}), ("Estimator", {"est_method": "auto", EXPORT_KEY: True})):
        at = AppTest.from_file(APP, default_timeout=180)
        at.session_state[SIGNAL_KEY] = make_signal(
            table, "z [m]", table.sample_period, "upload", None
        )
        for key, value in state.items():
            at.session_state[key] = value
        at.switch_page(f"app_pages/{page}.py").run()
        _clean(at)
        if page == "Signal":
            assert _says(at, sentence)
        else:
            (cfg,) = [json.loads(c.value) for c in at.code if c.value.lstrip().startswith("{")]
            assert cfg["record"]["answer"] == sentence
    # a unit typed on the Signal page wins over the file's
    at.session_state["units"] = "cm"
    at.run()
    (cfg,) = [json.loads(c.value) for c in at.code if c.value.lstrip().startswith("{")]
    assert cfg["record"]["answer"] == record_answer(est).sentence("cm")


def test_the_noise_model_report_quotes_the_records_answer(record) -> None:
    """The Noise model page's IMU report quotes each column's record answer: the one the
    page's box shows (the record split at its time column's gap, not spliced)."""
    from dashboard.sections.filter_configs import _said

    table = load_table(record["path"])
    sig = make_signal(table, "z", table.sample_period, "upload", None)
    for regimes in ("all", "still"):
        assert _said(sig, "z", regimes) == record_answer(record["est"], regimes)

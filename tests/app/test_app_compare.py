"""AppTest: the Compare page (every method; Monte Carlo with progress)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

from noisevar.estimators.compare import monte_carlo, run_monte_carlo

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PAGE = "app_pages/Compare.py"


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


@pytest.fixture
def at() -> AppTest:
    app = AppTest.from_file(APP, default_timeout=90)
    app.query_params["sig"] = "gen:fast-slow;n=4000;seed=5;noise_std=5.0"
    app.switch_page(PAGE).run()
    _clean(app)
    return app


def test_opened_first_without_a_signal(how_it_works_opens):
    app = AppTest.from_file(APP, default_timeout=60)
    app.switch_page(PAGE).run()
    _clean(app)
    assert any("No signal loaded" in i.value for i in app.info)
    assert how_it_works_opens(app)


def test_every_method_side_by_side(at, how_it_works_opens):
    assert not at.error
    table = at.dataframe[0].value
    assert {"auto", "somd", "somd-paper", "rice", "diff2"} <= set(table["method"])
    assert "rel. error" in table.columns and "CI covers truth" in table.columns
    assert table["variance"].between(15, 35).all()
    # the peers' rows arrive after the first view; once the run ends every row is in
    assert {"mle-level", "mle-trend"} <= set(table["method"])
    assert "computing..." not in set(table["note"])
    assert not any("still computing" in c.value for c in at.caption)
    assert any(b.label == "Comparison (CSV)" for b in at.get("download_button"))
    # the figure, drawn in the first view and again once every row is in (not at each
    # peer's arrival between, issue 29), shows every row, the peers' included
    (chart,) = at.get("plotly_chart")
    assert chart.key == "cmp_chart"
    drawn = {m for t in json.loads(chart.proto.spec)["data"] for m in t.get("y") or []}
    assert set(table["method"]) <= drawn
    assert at.get("plotly_chart") and how_it_works_opens(at)
    at.multiselect(key="cmp_methods").set_value(["auto", "rice"]).run()
    _clean(at)
    assert list(at.dataframe[0].value["method"]) == ["auto", "rice"]


def test_tuned_estimator_parameters_reach_the_comparison(at):
    somd_before = at.dataframe[0].value.set_index("method").loc["somd", "variance"]
    at.switch_page("app_pages/Estimator.py").run()
    at.select_slider(key="h_s").set_value("0.0003").run()
    at.switch_page(PAGE).run()
    _clean(at)
    assert any("tuned on the Estimator page" in c.value for c in at.caption)
    somd_after = at.dataframe[0].value.set_index("method").loc["somd", "variance"]
    assert somd_after != somd_before


def test_monte_carlo_runs_and_each_widget_changes_it(at):
    at.number_input(key="mc_runs").set_value(8)
    at.number_input(key="mc_n").set_value(2000)
    at.multiselect(key="mc_methods").set_value(["auto", "diff2", "somd"])
    at.button(key="mc_go").click().run()
    _clean(at)
    assert any("done: 8 runs" in s.value for s in at.success)
    summary = at.dataframe[-1].value
    assert list(summary["method"]) == ["auto", "diff2", "somd"]
    first = summary["RMSE"].tolist()
    for key, value in (("mc_seed", 1), ("mc_std", 2.0)):
        at.number_input(key=key).set_value(value)
        at.button(key="mc_go").click().run()
        _clean(at)
        now = at.dataframe[-1].value["RMSE"].tolist()
        assert now != first, key
        first = now
    at.selectbox(key="mc_signal").set_value("steps-ramps")
    at.button(key="mc_go").click().run()
    _clean(at)
    assert "steps-ramps" in at.markdown[-1].value or any(
        "steps-ramps" in m.value for m in at.markdown
    )


def test_monte_carlo_generator_can_be_cancelled():
    gen = monte_carlo("fast-slow", runs=50, methods=["diff2"], n=1000)
    snaps = [next(gen) for _ in range(3)]
    gen.close()
    assert snaps[-1].runs_done == 3 and not snaps[-1].finished
    assert snaps[-1].relative_errors["diff2"].size == 3
    res = run_monte_carlo(
        "fast-slow", runs=20, methods=["diff2"], n=1000, callback=lambda s: s.runs_done < 5
    )
    assert res.runs_done == 5 and not res.finished
    assert res.cr_floor == pytest.approx((2 / 1000) ** 0.5)


def test_monte_carlo_names_the_tuned_parameters_and_reports_failed_runs() -> None:
    """Gamma_amp = 0.05 set on the Estimator: SOMD fails most runs (issue 28 item 5)."""
    app = AppTest.from_file(APP, default_timeout=90)
    app.query_params["sig"] = "gen:fast-slow;n=2000;seed=5;noise_std=5.0"
    app.session_state["nv_tuned"] = {"gamma_amp": 0.05}
    app.switch_page(PAGE).run()
    app.number_input(key="mc_runs").set_value(10)
    app.number_input(key="mc_n").set_value(2000)
    app.multiselect(key="mc_methods").set_value(["diff2", "somd"])
    app.button(key="mc_go").click().run()
    _clean(app)
    assert any("somd: gamma_amp=0.05" in c.value for c in app.caption)
    summary = app.dataframe[-1].value.set_index("method")
    assert summary.loc["somd", "status"].startswith("failed ")
    assert summary.loc["somd", "status"].split(":")[0].endswith("/10")
    assert summary[["bias", "sd", "RMSE"]].loc["somd"].isna().all()
    assert summary.loc["diff2", "parameters"] == "defaults"
    assert summary[["bias", "sd", "RMSE"]].loc["diff2"].notna().all()


def test_a_peer_row_is_one_task_for_every_session(monkeypatch):
    """Issue 29: a slow peer's row is a task on the pool, started once for every session
    asking for the same record and parameters; its row equals the estimate."""
    import concurrent.futures as cf
    from types import SimpleNamespace

    import noisevar as nv
    from dashboard import cache, workers

    sig = SimpleNamespace(
        digest="issue29-peer", z=nv.generate("fast-slow", n=2000, seed=3).measured, times=None
    )
    assert cache.peer_row(sig, "mle-level", {}, start=False) is None
    first = cache.peer_row(sig, "mle-level", {})
    assert cache.peer_row(sig, "mle-level", {}) is first  # a second session: the same task
    assert first.result().variance == nv.estimate(sig.z, method="mle-level").variance
    assert first.status() and cache.peer_row(sig, "mle-level", {}, start=False) is first

    broken: cf.Future = cf.Future()
    broken.set_exception(RuntimeError("a broken pool"))
    real = workers.start_batch
    monkeypatch.setattr(workers, "start_batch", lambda *a, **k: workers.Started(-1, broken))
    other = SimpleNamespace(digest="issue29-broken", z=sig.z, times=None)
    assert cache.peer_row(other, "mle-level", {}).future is broken
    monkeypatch.setattr(workers, "start_batch", real)
    again = cache.peer_row(other, "mle-level", {})  # forgotten, started anew
    assert again.future is not broken and again.result().error is None


def test_a_failed_or_waiting_method_reads_a_dash_never_none() -> None:
    """A method that failed (or is still computing) has no numbers: its cells read "—"."""
    import re

    import numpy as np

    from dashboard.sections.compare import comparison_frame
    from noisevar.estimators.compare import MethodResult, comparison_of, run_method

    z = np.random.default_rng(3).normal(size=2000)
    ok = run_method(z, "diff2")
    failed = MethodResult("somd", "somd", "", None, "gamma_amp too small", 0.01)
    styler = comparison_frame(comparison_of(z.size, [ok, failed], 1.0), waiting=["mle-level"])
    cells = re.findall(r"<td[^>]*>(.*?)</td>", styler.to_html())
    assert not {"None", "nan", "NaN", "<NA>"} & set(cells), cells
    assert cells.count("—") >= 2 * 8  # the failed and the waiting rows' numbers
    assert "gamma_amp too small" in cells and "computing..." in cells
    assert any(re.fullmatch(r"\d+\.\d\d %", c) for c in cells)  # the percent columns

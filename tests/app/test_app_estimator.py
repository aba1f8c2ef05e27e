"""AppTest: the Estimator page (every main widget changes the shown result)."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import pytest
from streamlit.testing.v1 import AppTest

from dashboard.sections.estimator_results import EXPORT_KEY
from dashboard.widgets import GRID, fmt

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PAGE = "app_pages/Estimator.py"
SIG = "gen:fast-slow;n=6000;seed=2;noise_std=5.0"


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def _metric(at: AppTest, label: str) -> str:
    return next(m.value for m in at.metric if m.label == label)


def _shown(at: AppTest) -> tuple:
    """Everything the page reports about the result."""
    return tuple((m.label, m.value) for m in at.metric) + tuple(e.value for e in at.error)


@pytest.fixture
def at() -> AppTest:
    """The page opened first by its URL, with a generated signal named in the link."""
    app = AppTest.from_file(APP, default_timeout=60)
    app.query_params["sig"] = SIG
    app.session_state[EXPORT_KEY] = True  # the exports (and the JSON config) are shown
    app.switch_page(PAGE).run()
    _clean(app)
    return app


def test_opened_first_without_a_signal_offers_sample_data(how_it_works_opens):
    app = AppTest.from_file(APP, default_timeout=60)
    app.switch_page(PAGE).run()
    _clean(app)
    assert any("No signal loaded" in i.value for i in app.info)
    assert any(b.key == "offer_fast_slow.csv" for b in app.button)
    assert how_it_works_opens(app), "how it works is shown before a signal is loaded"
    app.button(key="offer_fast_slow.csv").click().run()
    _clean(app)
    assert _metric(app, "Noise variance")


def test_runs_with_defaults(at, how_it_works_opens):
    assert not at.error
    assert float(_metric(at, "Noise variance")) == pytest.approx(25.0, rel=0.1)
    assert _metric(at, "True variance") == "25"
    kept, total = _metric(at, "Windows kept").split(" / ")
    assert 0 < int(kept) <= int(total)
    assert how_it_works_opens(at)
    assert at.get("plotly_chart")


@pytest.mark.parametrize(
    ("kind", "key", "value"),
    [
        ("select_slider", "h_s", "5e-05"),
        ("multiselect", "h_more", ["3e-05", "0.0001"]),
        ("select_slider", "ht_ratio", 10),
        ("slider", "win", 60),
        ("slider", "g_amp", 0.3),
        ("slider", "g_ang", 2.0),
        ("radio", "angle", "paper"),
        ("toggle", "select", False),
        ("selectbox", "est_method", "somd-paper"),
        ("selectbox", "est_method", "diff2"),
    ],
)
def test_each_main_widget_changes_the_result(at, kind, key, value):
    before = _shown(at)
    getattr(at, kind)(key=key).set_value(value).run()
    _clean(at)
    assert _shown(at) != before, key


def test_tracking_filter_by_value(at):
    before = _shown(at)
    at.radio(key="ht_mode").set_value("value").run()
    at.select_slider(key="h_t").set_value("0.0001").run()
    _clean(at)
    assert _shown(at) != before


def test_step_view_sent_only_once_chosen(at):
    # issue 29: each Plotly figure costs the browser CPU when the page opens and again on
    # every slider step; the main figure is drawn, the step view waits for a choice
    keys = [c.key for c in at.get("plotly_chart")]
    assert keys == ["est_chart"]
    assert at.segmented_control(key="est_view").value is None
    assert any("Choose a step" in c.value for c in at.caption)
    at.segmented_control(key="est_view").set_value("Window tests").run()
    _clean(at)
    assert [c.key for c in at.get("plotly_chart")] == ["est_chart", "est_detail"]
    at.slider(key="g_amp").set_value(0.5).run()  # the choice stays on a control's change
    _clean(at)
    assert [c.key for c in at.get("plotly_chart")] == ["est_chart", "est_detail"]


def test_every_step_view_renders(at):
    for view in ["Envelopes and |V|", "h scan", "Per-window variance", "Window tests"]:
        at.segmented_control(key="est_view").set_value(view).run()
        _clean(at)
        assert not at.error, view
        keys = [c.key for c in at.get("plotly_chart")]
        # the main figure and the step view's; the Noise panel's figures wait for its expander
        assert len([k for k in keys if not k.startswith("est_np")]) == 2, view
        assert not [k for k in keys if k.startswith("est_np")], view
        if view == "h scan":
            assert any("chosen h" in c.value or "closest" in c.value for c in at.caption)


def test_no_window_kept_says_what_to_relax(at):
    at.slider(key="g_amp").set_value(0.05).run()
    at.slider(key="g_ang").set_value(0.5).run()
    _clean(at)
    assert len(at.error) == 1
    assert "relax gamma_amp" in at.error[0].value
    assert any("Γ_amp" in i.value for i in at.info)
    assert at.get("plotly_chart"), "the window tests are still drawn"


def test_stretch_estimate(at):
    at.number_input(key="s0").set_value(1000).run()
    at.number_input(key="s1").set_value(4000).run()
    _clean(at)
    assert _metric(at, "Samples in stretch") == "3,000"
    assert float(_metric(at, "Stretch variance")) > 0
    at.button(key="clear_stretch").click().run()
    _clean(at)
    assert not any(m.label == "Samples in stretch" for m in at.metric)


def test_refused_stretch_shows_no_whole_record_number_as_its_own(at):
    """A stretch too short to estimate: its row says refused and the headline says whole
    record (issue 28 §8: the metrics kept the whole record's values beside the stretch)."""
    at.number_input(key="s0").set_value(1000).run()
    at.number_input(key="s1").set_value(1010).run()
    _clean(at)
    assert any("Stretch 1000–1009" in e.value for e in at.error)
    assert _metric(at, "Stretch variance") == "refused"
    assert _metric(at, "Noise variance (whole record)")
    assert not any(m.label == "Noise variance" for m in at.metric)


def test_exported_config_matches_the_widgets_and_loads_back(at):
    at.slider(key="win").set_value(48).run()
    at.slider(key="g_amp").set_value(0.7).run()
    cfg = json.loads(at.code[0].value)
    assert cfg["method"] == "somd" and cfg["window"] == 48 and cfg["gamma_amp"] == 0.7
    cfg.update(window=64, gamma_ang=4.0, h_smooth=[3e-05, 0.0001])
    at.file_uploader(key="est_config_upload").set_value(
        ("tuned.json", json.dumps(cfg).encode(), "application/json")
    )
    at.run()
    _clean(at)
    back = json.loads(at.code[0].value)
    assert back["window"] == 64 and back["gamma_ang"] == 4.0
    assert back["h_smooth"] == [3e-05, 0.0001]
    at.file_uploader(key="est_config_upload").set_value(
        ("bad.json", b'{"method": "somd", "window": 3}', "application/json")
    )
    at.run()
    _clean(at)
    assert any("window" in e.value for e in at.error)


def test_config_round_trip_carries_the_column_and_the_cli_agrees(tmp_path, capsys):
    from noisevar.cli import main

    app = AppTest.from_file(APP, default_timeout=60)
    app.query_params["sig"] = "sample:two_sensors.csv"
    app.session_state[EXPORT_KEY] = True
    app.switch_page(PAGE).run()
    _clean(app)
    page_variance = _metric(app, "Noise variance")
    cfg = json.loads(app.code[0].value)
    column = cfg["column"]
    assert column in ("sensor_a", "sensor_b")
    hint = next(c.value for c in app.caption if "noisevar estimate --config" in c.value)
    assert f"--column {column} two_sensors.csv" in hint
    params = {k: v for k, v in cfg.items() if k != "column"}  # the CLI's own config reader
    path = tmp_path / "noisevar-config.json"
    path.write_text(json.dumps(params))
    data = ROOT / "sample_data" / "two_sensors.csv"
    code = main(
        ["estimate", str(data), "--config", str(path), "--column", column, "--format", "json"]
    )
    assert code == 0
    cli = json.loads(capsys.readouterr().out)
    assert fmt(cli["variance"]) == page_variance
    # the exported file as it is (it names its column): the same number; another column
    # is refused in one line (issue 28: a wrong column is refused)
    path.write_text(json.dumps(cfg))
    assert main(["estimate", str(data), "--config", str(path), "--format", "json"]) == 0
    assert fmt(json.loads(capsys.readouterr().out)["variance"]) == page_variance
    other = "sensor_b" if column == "sensor_a" else "sensor_a"
    assert main(["estimate", str(data), "--config", str(path), "--column", other]) == 2
    err = capsys.readouterr().err
    assert f"tuned on column {column!r}, not {other!r}" in err and err.count("\n") == 1, err
    # loading the exported config back switches to its column
    app.file_uploader(key="est_config_upload").set_value(
        ("tuned.json", json.dumps({**cfg, "column": other}).encode(), "application/json")
    )
    app.run()
    _clean(app)
    assert json.loads(app.code[0].value)["column"] == other
    assert any(other in i.value for i in app.info)


def test_h_scan_suggestion_can_be_applied(at):
    at.segmented_control(key="est_view").set_value("h scan").run()
    _clean(at)
    caption = next(c.value for c in at.caption if "suggests h =" in c.value)
    suggested = caption.split("suggests h = ")[1].split(" ")[0]
    at.button(key="scan_apply").click().run()
    _clean(at)
    assert float(at.select_slider(key="h_s").value) == pytest.approx(float(suggested), rel=0.3)


def test_html_report_holds_the_numbers_and_the_figure():
    import numpy as np

    import noisevar
    from dashboard.widgets import html_report
    from noisevar.figures.estimator import estimate_rows, somd_figure

    z = np.random.default_rng(5).normal(0.0, 2.0, 3000)
    est = noisevar.estimate(z, "somd")
    text = html_report("noise <of> z", estimate_rows(est), [somd_figure(z, est)], ["cmd --x"])
    assert "noise &lt;of&gt; z" in text and "cmd --x" in text
    assert fmt(est.variance, 6) in text and "plotly" in text.lower()


def test_report_download_is_offered(at):
    assert any(b.label.startswith("Report of this analysis") for b in at.get("download_button"))


def test_a_tuning_change_inside_the_fragment_updates_the_result_and_keeps_the_page(
    at, how_it_works_opens
):
    """Tuning controls and their results are one fragment; the rest of the page stays."""
    kept = _metric(at, "Windows kept")
    variance = _metric(at, "Noise variance")
    at.slider(key="g_amp").set_value(0.3).run()
    _clean(at)
    assert _metric(at, "Windows kept") != kept
    assert _metric(at, "Noise variance") != variance
    assert at.title[0].value == "Estimator"
    assert how_it_works_opens(at), "how it works (outside the fragment) is still shown"
    assert at.sidebar.get("page_link"), "the sidebar (outside the fragment) is still shown"
    assert json.loads(at.code[0].value)["gamma_amp"] == pytest.approx(0.3)


def test_noise_panel_figures_are_drawn_when_opened(at):
    assert not [c for c in at.get("plotly_chart") if c.key.startswith("est_np")]
    at.session_state["est_np_open"] = True
    at.run()
    _clean(at)
    assert [c.key for c in at.get("plotly_chart") if c.key.startswith("est_np")] == ["est_np_hist"]
    at.session_state["est_np_tab"] = "Autocorrelation"
    at.run()
    _clean(at)
    assert [c.key for c in at.get("plotly_chart") if c.key.startswith("est_np")] == ["est_np_acf"]


def test_a_figure_is_built_once_per_inputs():
    import plotly.graph_objects as go

    from dashboard import cache

    calls = []

    def build() -> go.Figure:
        calls.append(1)
        return go.Figure()

    first = cache.figure("test", {"digest": "abc", "gamma": 0.5}, build)
    again = cache.figure("test", {"gamma": 0.5, "digest": "abc"}, build)
    other = cache.figure("test", {"digest": "abc", "gamma": 0.55}, build)
    assert first is again and other is not first
    assert len(calls) == 2


def test_window_tests_figure_draws_at_most_the_page_budget_and_counts_every_window():
    import noisevar
    from dashboard.sections.estimator_results import WINDOW_MARKERS
    from noisevar.figures.windows import window_tests_figure

    z = noisevar.generate("fast-slow", n=40_000, seed=3, noise_std=5.0).measured
    sel = noisevar.estimate(z, method="somd").details.selection
    fig = window_tests_figure(sel, 0.5, 10.0, max_markers=WINDOW_MARKERS)
    drawn = sum(len(tr.x) for tr in fig.data)
    counted = sum(int(tr.name.rsplit("(", 1)[1].rstrip(")")) for tr in fig.data)
    assert drawn <= WINDOW_MARKERS < counted
    assert counted == sel.starts.size


def test_the_exports_are_sent_only_when_their_expander_is_opened():
    app = AppTest.from_file(APP, default_timeout=60)
    app.query_params["sig"] = SIG
    app.switch_page(PAGE).run()
    _clean(app)
    assert any(e.label.startswith("Export") for e in app.expander)
    assert not app.code, "a closed expander's code block loads the browser's highlighter"
    assert not any(b.key == "dl_report" for b in app.get("download_button"))
    app.session_state[EXPORT_KEY] = True
    app.run()
    _clean(app)
    assert json.loads(app.code[0].value)["method"] == "somd"


def test_figures_reach_the_browser_without_what_makes_plotly_draw_them_twice(at):
    # Streamlit hands a remounted chart to plotly twice; the second pass is a no-op only
    # without a template, without base64 arrays and with a datarevision (display_spec).
    at.segmented_control(key="est_view").set_value("Window tests").run()
    charts = at.get("plotly_chart")
    assert len(charts) >= 2
    for chart in charts:
        spec = json.loads(chart.proto.spec)
        assert chart.proto.theme == ""
        assert "template" not in spec["layout"] and "bdata" not in chart.proto.spec
        assert spec["layout"]["datarevision"] == 1
        assert spec["layout"]["paper_bgcolor"] == "rgba(0,0,0,0)"


def test_display_spec_keeps_every_value_as_plain_lists():
    import numpy as np
    import plotly.graph_objects as go

    from dashboard.widgets import display_spec

    y = np.array([1.5, np.nan, -2.0, np.inf])
    custom = np.arange(8.0).reshape(4, 2)
    fig = go.Figure(go.Scatter(y=y, customdata=custom, marker={"color": np.arange(4)}))
    fig.update_layout(title="t", xaxis={"minor": {"showgrid": True}})
    spec = display_spec(fig)
    trace = spec["data"][0]
    assert trace["y"] == [1.5, None, -2.0, None]
    assert trace["customdata"] == custom.tolist()
    assert trace["marker"]["color"] == [0, 1, 2, 3]
    assert spec["layout"]["title"]["text"] == "<b>t</b>"
    assert spec["layout"]["xaxis"]["minor"] == {"showgrid": True, "gridcolor": GRID}
    assert "minor" not in spec["layout"]["yaxis"]  # a minor container draws a minor grid
    json.dumps(spec, allow_nan=False)  # plain JSON: no NaN, no arrays left


def test_plotly_preload_names_the_chunk_streamlit_itself_imports():
    # the preload is useful only at the URL Streamlit's own lazy import resolves to
    import streamlit

    from dashboard.widgets import _plotly_chunk

    chunk = _plotly_chunk()
    assert chunk is not None and chunk.startswith("PlotlyChart.")
    js = Path(streamlit.__file__).parent / "static" / "static" / "js"
    assert any(f"import(`./{chunk}`)" in f.read_text() for f in js.glob("index.*.js"))


def test_html_report_carries_the_verdict_regimes_units_and_human_labels():
    """Issue 28 item 6: the report's first lines are the verdict and the regime warning."""
    import html

    import numpy as np

    import noisevar
    from dashboard.sections.estimator_results import report
    from dashboard.state import make_signal
    from noisevar.estimators.answer import REGIME_WARNING, record_answer
    from noisevar.figures.estimator import signal_figure
    from noisevar.io import table_from_arrays

    rng = np.random.default_rng(1)
    z = 0.15 * rng.standard_normal(6000)
    k = np.arange(2000, 6000)
    z[2000:] += 3.0 * np.sin(2 * np.pi * k / 7.0) * (1 + 0.5 * rng.standard_normal(k.size))
    sig = make_signal(table_from_arrays("walk.csv", {"gyro": z}), None, 0.01, "upload", None)
    est = noisevar.estimate(z, "somd")
    auto = noisevar.estimate(z)
    text = report(sig, est, None, signal_figure(z), "rad/s")
    assert est.diagnostics.verdict.split(":")[0] in text
    assert est.diagnostics.level_varies and auto.diagnostics.level_varies
    assert html.escape(f"Regime warning: {REGIME_WARNING}") in text
    assert "95 % interval, low [(rad/s)²]" in text and "noise variance R [(rad/s)²]" in text
    for code in ("ci95_low", "windows_failed_amplitude", "param_h_smooth", "n_used"):
        assert f"<td>{code}</td>" not in text
    assert "windows refused by the amplitude test" in text
    # the Estimate CSV ends with the same verdict and regime warning (issue 28: exports)
    import csv
    import io

    from dashboard.sections.estimator_results import estimate_csv

    rows = {r["quantity"]: r["value"] for r in csv.DictReader(io.StringIO(estimate_csv(est, None)))}
    assert rows["verdict"] == record_answer(est).verdict and rows["verdict"] in text
    assert rows["regime warning"] == REGIME_WARNING
    assert rows["record's answer"] == record_answer(est).sentence("")


def test_each_note_is_shown_once():
    """A quantised record's grid note: under the noise panel's flags, not also above the
    verdict (issue 28 §8)."""
    import numpy as np

    from dashboard.state import SIGNAL_KEY, make_signal
    from noisevar.io import table_from_arrays

    rng = np.random.default_rng(4)
    z = np.round(np.sin(np.arange(4000) / 300) * 40 + rng.normal(0, 2.0, 4000))  # grid step 1
    app = AppTest.from_file(APP, default_timeout=120)
    table = table_from_arrays("grid.csv", {"z": z}, sample_period=0.01)
    app.session_state[SIGNAL_KEY] = make_signal(table, None, 0.01, "upload", None)
    app.switch_page(PAGE).run()
    _clean(app)
    texts = [c.value.removeprefix("Note: ") for c in app.caption]
    grid = [t for t in texts if "sit on a grid of step" in t]
    assert len(grid) == 1, grid


def test_select_all_smoothing_filters_keeps_the_sliders_h_s(at):
    """'Select all' extra filters: h_S (the slider) stays the smallest h, which sets h_T
    (issue 28 §8: the estimate silently moved to the smallest h)."""
    at.select_slider(key="h_s").set_value("5e-05").run()
    box = at.multiselect(key="h_more")
    assert box.options and all(float(h) > 5e-05 for h in box.options)
    box.set_value(list(box.options)).run()
    _clean(at)
    hs = at.session_state["nv_tuned"]["h_smooth"]
    assert hs[0] == 5e-05 and min(hs) == 5e-05 and len(hs) == len(box.options) + 1

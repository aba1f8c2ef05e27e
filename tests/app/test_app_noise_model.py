"""AppTest: the Noise model page (Allan deviation, IEEE-952 terms, simulation, Kalibr)."""

from __future__ import annotations

import sys
from pathlib import Path

import numpy as np
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))
APP = str(ROOT / "app.py")
PAGE = "app_pages/Noise_model.py"
SIG = "gen:noise-step;n=4000;seed=1"


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def _open(sig: str | None = SIG) -> AppTest:
    app = AppTest.from_file(APP, default_timeout=90)
    if sig:
        app.query_params["sig"] = sig
    app.switch_page(PAGE).run()
    _clean(app)
    return app


def _figure_names(at: AppTest) -> list[str]:
    import json

    fig = json.loads(at.get("plotly_chart")[0].proto.spec)
    return [t.get("name") for t in fig["data"]]


def test_without_a_signal_offers_sample_data(how_it_works_opens):
    at = _open(None)
    assert any("No signal loaded" in i.value for i in at.info)
    assert how_it_works_opens(at)


def test_rate_data_fits_the_terms_and_simulates():
    at = _open()
    assert not at.error
    table = at.dataframe[0].value
    assert list(table["symbol"]) == ["Q", "N", "B", "K", "R"]
    assert (table["low"] <= table["value"]).all() and (table["value"] <= table["high"]).all()
    names = _figure_names(at)
    assert "overlapping ADEV" in names and "sum" in names
    assert "simulated from the fit" not in names
    # the config's reader is named, with the column it replays (issue 28 item 3)
    assert any(
        "noisevar fit FILE --config" in c.value and "'measured'" in c.value for c in at.caption
    )
    at.button(key="nm_simulate").click().run()
    _clean(at)
    assert "simulated from the fit" in _figure_names(at)


def test_phase_data_and_other_deviations_draw_without_terms():
    at = _open()
    at.radio(key="nm_data").set_value("phase").run()
    _clean(at)
    # no table of IEEE-952 terms (the Kalman fit's table below has no "term" column)
    assert not any("term" in d.value.columns for d in at.dataframe)
    assert any("fitted to the overlapping ADEV" in c.value for c in at.caption)
    at.selectbox(key="nm_kind").set_value("mdev").run()
    _clean(at)
    assert "MDEV" in _figure_names(at)


def test_a_bad_rate_is_one_error_and_a_good_one_recovers():
    at = _open()
    at.number_input(key="nm_rate").set_value(0.0).run()
    _clean(at)
    assert len(at.error) == 1 and "positive" in at.error[0].value
    at.number_input(key="nm_rate").set_value(10.0).run()
    _clean(at)
    assert not at.error and at.dataframe


def test_kalibr_export_from_chosen_columns():
    at = _open()
    cols = at.multiselect(key="nm_gyro").options
    at.multiselect(key="nm_gyro").set_value([cols[0]])
    at.multiselect(key="nm_accel").set_value([cols[0]])
    at.number_input(key="nm_inflation").set_value(3.0).run()
    _clean(at)
    text = at.code[0].value
    lines = [line for line in text.splitlines() if not line.startswith("#")]
    values = dict(line.split("#")[0].split(":", 1) for line in lines)
    gyro = float(values["gyroscope_noise_density"])
    n_table = at.dataframe[0].value.set_index("symbol").loc["N", "value"]
    # the same column with the default unit: three times the fitted N, or three times
    # the white level sigma(tau0) sqrt(tau0) when that is larger, with a note (issue 26)
    assert gyro >= 3.0 * n_table * (1 - 1e-9)
    if gyro > 3.0 * n_table * (1 + 1e-9):
        assert "# note: gyroscope_noise_density: raised from N" in text
    assert np.isfinite(float(values["update_rate"]))


def test_the_data_kind_defaults_as_the_command_line_does(tmp_path, capsys):
    """The Signal page's unit decides phase or rate here as `noisevar allan` decides it
    (:func:`noisevar.noise_model.allan.default_data`): a time or an angle is phase data."""
    from noisevar.cli import main
    from noisevar.noise_model.allan import default_data

    for unit, kind in (("ns", "phase"), ("deg", "phase"), ("rad/s", "rate"), ("", "rate")):
        assert default_data(unit) == kind
        app = AppTest.from_file(APP, default_timeout=90)
        app.query_params["sig"] = SIG
        app.session_state["units"] = unit  # as the Signal page's unit box sets it
        app.switch_page(PAGE).run()
        _clean(app)
        assert app.radio(key="nm_data").value == kind, unit
    path = tmp_path / "clock.csv"
    rng = np.random.default_rng(2)
    path.write_text("x [ns]\n" + "\n".join(f"{v:.6f}" for v in np.cumsum(rng.normal(size=600))))
    assert main(["allan", str(path), "--rate", "1"]) == 0
    out = capsys.readouterr().out
    assert "(phase data," in out and "deviations in ns/s" in out


def test_a_log_that_drops_samples_gets_the_command_lines_terms():
    """The page fitted a log that drops samples as uniform at its median rate while `noisevar
    imu` places it on its sample grid (noise_model.allan_gaps): two answers for one record."""
    from noisevar.io import load_table, record_times
    from noisevar.noise_model import inertial_noise

    rng = np.random.default_rng(5)
    n = 6000
    keep = np.sort(rng.choice(n, size=int(0.65 * n), replace=False))
    t = keep / 400.0
    z = rng.normal(0.0, 0.01, n)[keep] + np.cumsum(rng.normal(0.0, 2e-4, n))[keep]
    body = "time,gyro\n" + "\n".join(f"{a:.6f},{b:.9f}" for a, b in zip(t, z, strict=True))
    app = AppTest.from_file(APP, default_timeout=120)
    app.switch_page("app_pages/Signal.py").run()
    app.file_uploader(key="upload").set_value(("drops.csv", body.encode(), "text/csv")).run()
    app.switch_page(PAGE).run()
    _clean(app)
    shown = app.dataframe[0].value.set_index("symbol")
    tab = load_table(body.encode(), "drops.csv")
    cli = inertial_noise(tab.columns["gyro"], 1 / tab.sample_period, t=record_times(tab))
    for sym in ("N", "B", "K"):
        assert shown.loc[sym, "value"] == cli.term(sym).value
        assert shown.loc[sym, "high"] == cli.term(sym).interval[1]


def test_r_is_written_with_the_files_unit_as_on_the_estimator_page():
    """NREL MIDC's ``Global Horiz (tracker) [W/m^2]`` (real_audit5): the Estimator page
    wrote R as "0.07313 (W/m²)²", the Noise model page as "0.07313", no unit."""
    from dashboard.state import SIGNAL_KEY, make_signal
    from dashboard.widgets import fmt
    from noisevar import estimate
    from noisevar.format import squared
    from noisevar.io import load_table

    rng = np.random.default_rng(7)
    z = np.sin(np.arange(2000) / 50.0) + rng.normal(0, 0.1, 2000)
    body = "GHI [W/m^2]\n" + "".join(f"{v:.6f}\n" for v in z)
    table = load_table(body.encode(), "ghi.csv")
    at = AppTest.from_file(APP, default_timeout=90)
    at.session_state[SIGNAL_KEY] = make_signal(table, "GHI [W/m^2]", None, "upload", None)
    at.switch_page(PAGE).run()
    _clean(at)
    r = next(m.value for m in at.metric if m.label == "Noise variance R")
    est = estimate(table.columns["GHI [W/m^2]"])
    assert r == fmt(est.variance, unit=squared("W/m^2"))


def test_a_moving_records_terms_say_they_are_not_the_sensors():
    """The IEEE-952 terms of a record with motion describe the motion too: the fit's regime
    warning is shown under them (it was in ``InertialNoise.notes`` only: a flight's gyro
    showed B 0.177 rad/s, interval 0.174-0.180, with no word under the table), and goes with
    the still regimes ticked."""
    from dashboard.state import SIGNAL_KEY, make_signal
    from noisevar.io import load_table

    rng = np.random.default_rng(4)
    n = 20000
    z = rng.normal(0, 0.01, n)
    for c in (4000, 11000, 16000):
        z[c : c + 1500] += rng.normal(0, 0.2, 1500)  # handling: 20x the noise
    csv = "gyro [rad/s]\n" + "\n".join(f"{v:.6g}" for v in z) + "\n"
    table = load_table(csv.encode(), "handled.csv")
    at = AppTest.from_file(APP, default_timeout=120)
    at.session_state[SIGNAL_KEY] = make_signal(table, None, 0.01, "upload", None)
    at.switch_page(PAGE).run()
    _clean(at)
    assert any("this fit is of the whole record, motion included" in w.value for w in at.warning)
    at.checkbox(key="nm_regimes").check().run()
    _clean(at)
    assert not any("this fit is of the whole record" in w.value for w in at.warning)


def test_a_note_of_the_deviation_is_shown_once():
    """A logger's dropped samples were said twice, under the rate and under the terms (seen in
    a browser screenshot of pvanalytics' RMIS weather file): the fit carries its deviation's
    notes."""
    at = AppTest.from_file(APP, default_timeout=120)
    at.switch_page("app_pages/Signal.py").run()
    rng = np.random.default_rng(3)
    keep = np.ones(3000, bool)
    keep[rng.choice(np.arange(10, 2990), 40, replace=False)] = False
    t = 0.02 * np.arange(3000)[keep]
    x = rng.normal(size=t.size)
    body = "time,x\n" + "\n".join(f"{a:.2f},{b:.6f}" for a, b in zip(t, x, strict=True))
    at.file_uploader(key="upload").set_value(("dropped.csv", body.encode(), "text/csv")).run()
    _clean(at)
    at.switch_page(PAGE).run()
    _clean(at)
    said = [c.value for c in at.caption if "samples dropped" in c.value]
    assert len(said) == 1, said

"""AppTest: the Signal page's time-unit control, and the config it exports: one answer on
the page, in Python and on the command line (real_audit19: Kepler's ``times`` in days,
no unit stated, read a period of 0.0204 s with no way to say "days").

Before: the Signal page had no such control and the exported config no ``time_unit``."""

from __future__ import annotations

import json
import sys
from pathlib import Path

import numpy as np
from streamlit.testing.v1 import AppTest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from dashboard.sections.estimator_results import EXPORT_KEY  # noqa: E402
from dashboard.widgets import fmt  # noqa: E402

APP = str(ROOT / "app.py")
STEP_D = 0.0204338  # Kepler's long cadence (29.4 min), in days


def _light_curve(tmp_path) -> Path:
    rng = np.random.default_rng(4)
    t = 120.5590984 + STEP_D * np.arange(3000)
    y = 1 + 1e-4 * rng.normal(size=t.size)
    p = tmp_path / "koi.csv"
    p.write_text(
        "times,flux\n"
        + "".join(f"{a!r},{b!r}\n" for a, b in zip(t.tolist(), y.tolist(), strict=True))
    )
    return p


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def test_the_unit_stated_on_the_signal_page_reaches_the_config_and_the_cli(tmp_path, capsys):
    import noisevar
    from noisevar.cli import main
    from noisevar.io import channel_record, load_table

    p = _light_curve(tmp_path)
    at = AppTest.from_file(APP, default_timeout=60)
    at.switch_page("app_pages/Signal.py").run()
    at.selectbox(key="upload_time_unit").set_value("d").run()
    at.file_uploader(key="upload").set_value((p.name, p.read_bytes(), "text/csv")).run()
    _clean(at)
    assert not at.error, [e.value for e in at.error]
    sig = at.session_state["nv_signal"]
    table = load_table(p, time_unit="d")  # Python
    assert sig.time_unit == "d" and sig.sample_period == table.sample_period
    assert abs(sig.sample_period - STEP_D * 86400) < 1e-3  # 1765.48 s, not 0.0204 s
    at.session_state[EXPORT_KEY] = True
    at.switch_page("app_pages/Estimator.py").run()
    _clean(at)
    cfg = json.loads(at.code[0].value)
    assert cfg["time_unit"] == "d" and cfg["column"] == "flux", cfg
    page = next(m.value for m in at.metric if m.label == "Noise variance")
    z, t = channel_record(table, "flux")
    assert fmt(noisevar.estimate(z, method=cfg["method"], t=t).variance) == page
    path = tmp_path / "noisevar-config.json"
    path.write_text(json.dumps(cfg))
    assert main(["estimate", str(p), "--config", str(path), "--format", "json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert fmt(cli["variance"]) == page
    assert any("in d (the time unit given)" in n for n in cli["notes"]), cli["notes"]
    # the config's unit against a name that states another: refused in one line
    named = tmp_path / "named.csv"
    named.write_text(p.read_text().replace("times,", "time_s,", 1))
    assert main(["estimate", str(named), "--config", str(path)]) == 2
    err = capsys.readouterr().err
    assert "states its unit, s (its name)" in err and err.count("\n") == 1, err

"""AppTest: the Signal page's series picker, offered when an upload stacks several series
(the long format), and the config it exports: one answer on the page, in Python and on the
command line.

Before: the upload was refused ("give one series ... saved as their own file") with no way
on the dashboard to read one, and the exported config had no ``series``."""

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
SIGMAS = {"Subject 1": 0.5, "Subject 2": 2.0, "Subject 3": 1.0}


def _stacked(tmp_path) -> Path:
    """Three subjects' records one after the other (times starting again at each)."""
    rng = np.random.default_rng(24)
    rows = ["id,time,gl"]
    for label, sigma in SIGMAS.items():
        for i, v in enumerate((100 + sigma * rng.normal(size=800)).tolist()):
            rows.append(f"{label},{i * 300},{v!r}")
    p = tmp_path / "cgm.csv"
    p.write_text("\n".join(rows) + "\n")
    return p


def _clean(at: AppTest) -> None:
    assert not at.exception, [e.value for e in at.exception]


def test_a_picked_series_is_the_signal_and_the_config_and_the_cli_read_it(tmp_path, capsys):
    import noisevar
    from noisevar.cli import main
    from noisevar.io import channel_record, load_table

    p = _stacked(tmp_path)
    at = AppTest.from_file(APP, default_timeout=60)
    at.switch_page("app_pages/Signal.py").run()
    at.file_uploader(key="upload").set_value((p.name, p.read_bytes(), "text/csv")).run()
    _clean(at)
    said = " ".join(e.value for e in at.error)
    assert "stacks 3 series" in said and "Series to read" in said, said
    assert "nv_signal" not in at.session_state  # nothing picked: no signal read yet
    picker = at.selectbox(key="upload_series")
    assert list(picker.options) == list(SIGMAS), picker.options
    picker.set_value("Subject 2").run()
    _clean(at)
    assert not at.error, [e.value for e in at.error]
    sig = at.session_state["nv_signal"]
    table = load_table(p, series="Subject 2")  # Python
    assert sig.series == "Subject 2" and sig.n == 800 == table.n_rows
    z, t = channel_record(table, "gl")
    assert np.array_equal(sig.z, z)
    at.session_state[EXPORT_KEY] = True
    at.switch_page("app_pages/Estimator.py").run()
    _clean(at)
    cfg = json.loads(at.code[0].value)
    assert cfg["series"] == "Subject 2" and cfg["column"] == "gl", cfg
    page = next(m.value for m in at.metric if m.label == "Noise variance")
    assert fmt(noisevar.estimate(z, method=cfg["method"], t=t).variance) == page
    path = tmp_path / "noisevar-config.json"
    path.write_text(json.dumps(cfg))
    assert main(["estimate", str(p), "--config", str(path), "--format", "json"]) == 0
    cli = json.loads(capsys.readouterr().out)
    assert fmt(cli["variance"]) == page
    assert any("read the rows of id = 'Subject 2'" in n for n in cli["notes"]), cli["notes"]

"""Every exported config carries the record's answer (issue 28, "Done when": the verdict
and the regime warning in the exports), for the reader: it is checked and never applied.
"""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar import estimate
from noisevar.cli import main
from noisevar.config import config_to_json, filter_config_json, params_to_config, parse_config
from noisevar.errors import NoisevarError
from noisevar.estimators.answer import REGIME_WARNING, record_answer
from noisevar.noise_model import fit_kalman


@pytest.fixture(scope="module")
def burst():
    """White noise with a noisier stretch (vibration): the level varies, the regime warning
    is due."""
    rng = np.random.default_rng(7)
    z = rng.normal(0.0, 1.0, 20_000)
    z[8000:11_000] += rng.normal(0.0, 6.0, 3000)
    return z


def test_the_summary_has_the_verdict_the_answer_and_the_regime_warning(burst):
    summary = record_answer(estimate(burst)).summary("m")
    assert summary["verdict"] and summary["answer"].startswith("R = ")
    assert summary["regime_warning"] == REGIME_WARNING


def test_an_estimator_config_carries_the_record_and_reads_back_without_it(burst):
    est = estimate(burst)
    text = config_to_json(
        params_to_config(est.method, est.params), "x", record_answer(est).summary("m")
    )
    cfg = json.loads(text)
    assert cfg["record"]["verdict"] == est.diagnostics.verdict
    read = parse_config(text)
    assert "record" not in read and read["method"] == est.method  # never applied


def test_a_filter_config_carries_the_record_and_is_still_applied(burst, tmp_path, capsys):
    rec = record_answer(estimate(burst)).summary()
    tuning = fit_kalman(burst, model="rw", rate=10.0)
    path = tmp_path / "tuned.json"
    path.write_text(filter_config_json(tuning, "x", "", rec), encoding="utf-8")
    assert json.loads(path.read_text())["record"] == rec
    data = tmp_path / "x.csv"
    np.savetxt(data, burst[:, None], header="x", comments="")
    assert main(["fit", str(data), "--config", str(path), "--rate", "10"]) == 0


@pytest.mark.parametrize(
    "bad", [{"verdict": 3}, {"nonsense": "x"}, ["verdict"], {"answer": "x" * 5000}]
)
def test_a_bad_record_is_refused_in_one_error(bad):
    with pytest.raises(NoisevarError, match="record"):
        parse_config(json.dumps({"method": "auto", "record": bad}))


def test_fit_save_config_writes_the_record(burst, tmp_path, capsys):
    data = tmp_path / "x.csv"
    np.savetxt(data, burst[:, None], header="x", comments="")
    out = tmp_path / "saved.json"
    assert main(["fit", str(data), "--rate", "10", "--save-config", str(out)]) == 0
    capsys.readouterr()
    rec = json.loads(out.read_text())["record"]
    assert rec["regime_warning"] == REGIME_WARNING and rec["answer"].startswith("R = ")

"""Fleet statistics (robust z of log std) and the diagnostics' way into batch rows and the CLI."""

from __future__ import annotations

import json

import numpy as np
import pandas as pd
import pytest

import noisevar as nv
from noisevar.batch.fleet import MAD_TO_SD, fleet_report, robust_z
from noisevar.cli import main
from noisevar.errors import NoisevarError


def _table(stds: dict[str, list[float]]) -> pd.DataFrame:
    rows = [
        {"file": f"/fleet/unit{i:02d}.csv", "channel": ch, "std": s}
        for ch, values in stds.items()
        for i, s in enumerate(values)
    ]
    rows.append({"file": "/fleet/broken.csv", "channel": None, "std": None, "error": "bad"})
    return pd.DataFrame(rows)


def test_robust_z_is_the_distance_in_mad_units():
    x = np.array([1.0, 2.0, 3.0, 4.0, 100.0])
    z, med, scale = robust_z(x)
    assert med == 3.0 and scale == pytest.approx(1.0 / MAD_TO_SD)
    np.testing.assert_allclose(z, (x - 3.0) * MAD_TO_SD)
    z_same, _, scale_same = robust_z(np.full(6, 2.0))
    assert scale_same == 0.0 and not z_same.any()
    z_most, _, scale_most = robust_z(np.array([1.0, 1.0, 1.0, 1.0, 5.0]))  # MAD zero
    assert scale_most == pytest.approx(0.8 / 0.7978845608028654)
    assert z_most[-1] > 3.5


def test_one_noisy_and_one_quiet_sensor_are_flagged_in_words():
    rng = np.random.default_rng(5)
    ax = list(1.0 + rng.uniform(-0.05, 0.05, 20))
    ay = list(2.0 + rng.uniform(-0.1, 0.1, 20))
    ax[3], ay[7] = 3.0, 0.5
    report = fleet_report(_table({"ax": ax, "ay": ay}))
    assert report.n_errors == 1
    assert [(s.file[-10:], s.channel) for s in report.flagged] == [
        ("unit07.csv", "ay"),  # 4x quieter: further out on a log scale than 3x noisier
        ("unit03.csv", "ax"),
    ]
    quiet, noisy = report.flagged
    assert quiet.z < -3.5 < 3.5 < noisy.z
    assert "times quieter than" in quiet.sentence and "check this sensor" in quiet.sentence
    assert "3.0 times noisier than the fleet's typical 1" in noisy.sentence
    spread = {c.channel: c for c in report.channels}
    assert spread["ax"].low < 1.0 < spread["ax"].high < 3.0 and spread["ax"].n_flagged == 1
    json.dumps(report.to_dict(), allow_nan=False)
    assert len(report.to_frame()) == 40


def test_few_sensors_are_not_judged_and_bad_input_is_refused(tmp_path):
    report = fleet_report(_table({"ax": [1.0, 5.0]}))
    assert not report.channels and not report.flagged
    assert report.notes and "too few" in report.notes[0]
    assert all(s.z is None for s in report.sensors)
    with pytest.raises(NoisevarError, match="positive"):
        fleet_report(_table({"ax": [1.0, 2.0, 3.0]}), threshold=0)
    with pytest.raises(NoisevarError, match="no std column"):
        fleet_report(pd.DataFrame({"file": ["a"], "channel": ["x"]}))
    (tmp_path / "t.csv").write_text("a,b\n1,2\n")
    with pytest.raises(NoisevarError, match="not a batch table"):
        fleet_report(tmp_path / "t.csv")


def test_diagnostics_reach_batch_rows_and_the_cli(tmp_path, capsys):
    rng = np.random.default_rng(2)
    z = np.column_stack([rng.normal(0.0, 1.0, 4000), rng.standard_t(3, 4000)])
    np.save(tmp_path / "a.npy", z)
    frame = nv.batch(tmp_path, progress=False)
    assert frame["verdict"].iloc[0].startswith("white Gaussian noise")
    assert "heavy-tailed" in frame["verdict"].iloc[1]
    assert list(frame["flag_heavy_tailed"]) == [False, True]
    assert frame["core_variance"].iloc[1] < 0.9 * frame["variance"].iloc[1]  # tails left out
    assert main(["estimate", str(tmp_path / "a.npy")]) == 0
    assert "verdict   white Gaussian noise" in capsys.readouterr().out
    assert main(["estimate", str(tmp_path / "a.npy"), "--format", "json"]) == 0
    diag = json.loads(capsys.readouterr().out)["diagnostics"]
    assert diag["verdict"].startswith("white Gaussian") and diag["flags"]["white"]
    assert main(["estimate", str(tmp_path / "a.npy"), "--columns", "all"]) == 0
    assert "[col1] verdict   white heavy-tailed noise" in capsys.readouterr().out

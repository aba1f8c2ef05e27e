"""``inertial_noise(estimates=)``: the axes' estimates made once (issue 26 item 5, pages26c).

``noisevar imu --export`` estimated each column twice: once inside ``inertial_noise`` for its
regime warning (or its still stretch) and once for the files' verdicts. The estimates are
now made once and given to the fit; the fit must be the same, to the last bit.
"""

from __future__ import annotations

import json
import traceback
from pathlib import Path

import numpy as np
import pytest

import noisevar
import noisevar.estimators
from noisevar.cli import main
from noisevar.errors import NoisevarError
from noisevar.noise_model import inertial_noise

#: the whole motion record's fits reach past a float in an interval (as test_regimes_choice)
pytestmark = pytest.mark.filterwarnings("ignore:overflow encountered in exp:RuntimeWarning")

RATE = 100.0


def _axes(seed: int = 3, n: int = 6000) -> np.ndarray:
    """Two axes (time x axes): still for 2000 samples then motion; the second in small units
    (scaled by 2**-30, so the fit's own rescaling path runs)."""
    rng = np.random.default_rng(seed)
    k = np.arange(2000, n)
    cols = []
    for scale in (1.0, 2.0**-30):
        z = 0.15 * rng.standard_normal(n)
        z[2000:] += 3.0 * np.sin(2 * np.pi * k / 7.0) * (1 + 0.5 * rng.standard_normal(k.size))
        cols.append(z * scale)
    return np.column_stack(cols)


@pytest.fixture(scope="module")
def axes() -> np.ndarray:
    return _axes()


@pytest.mark.parametrize("regimes", ["all", "still"])
def test_given_estimates_give_the_same_fit(axes, regimes) -> None:
    ests = [noisevar.estimate(c) for c in axes.T]
    alone = inertial_noise(axes, RATE, axis=0, regimes=regimes)
    given = inertial_noise(axes, RATE, axis=0, regimes=regimes, estimates=ests)
    for a, b in zip(alone, given, strict=True):
        assert a.to_dict() == b.to_dict()  # every term, interval and note, bit for bit
    assert any(n.startswith(f"regimes='{regimes}'") for n in given[0].notes)
    one = inertial_noise(axes[:, 1], RATE, regimes=regimes, estimates=ests[1])
    assert one.to_dict() == alone[1].to_dict()


def test_given_estimates_are_not_made_again(axes, monkeypatch) -> None:
    ests = [noisevar.estimate(c) for c in axes.T]
    calls = []
    real = noisevar.estimators.estimate
    monkeypatch.setattr(
        noisevar.estimators, "estimate", lambda *a, **k: calls.append(1) or real(*a, **k)
    )
    inertial_noise(axes, RATE, axis=0, estimates=ests)
    inertial_noise(axes, RATE, axis=0, regimes="still", estimates=ests)
    assert calls == []
    inertial_noise(axes, RATE, axis=0)
    assert len(calls) == 2  # without them, one per axis


@pytest.mark.parametrize("bad", [[], "x", [None, None], 1.0])
def test_wrong_estimates_are_refused(axes, bad) -> None:
    with pytest.raises(NoisevarError, match="estimates must be"):
        inertial_noise(axes, RATE, axis=0, estimates=bad)


def test_imu_export_estimates_each_column_once(axes, tmp_path, monkeypatch, capsys) -> None:
    path = tmp_path / "imu.csv"
    np.savetxt(path, axes, delimiter=",", header="g,a", comments="")
    argv = ["imu", str(path), "--rate", "100", "--gyro", "g", "--accel", "a", "--format", "json"]
    export = [*argv, "--export", "kalibr", "--out", str(tmp_path / "out"), "--no-report"]
    assert main(argv) == 0
    before = json.loads(capsys.readouterr().out)
    callers = []
    real = noisevar.estimators.estimate

    def counted(*a, **k):
        callers.append({f"{Path(f.filename).name}:{f.name}" for f in traceback.extract_stack()})
        return real(*a, **k)

    monkeypatch.setattr(noisevar.estimators, "estimate", counted)
    assert main(export) == 0
    out = json.loads(capsys.readouterr().out)
    assert out["columns"] == before["columns"]  # the same fits as without --export
    # one estimate per column (was two: the IEEE-952 fit's and the files' verdicts); the
    # composite fit's motion note (gmwm.motion_note, on a fit it cannot explain) is its own
    ours = [c for c in callers if "__init__.py:motion_note" not in c]
    assert len(ours) == 2 and all("_imu_report.py:one" in c for c in ours)

"""``fit_imu_model`` on records with motion (issues 26 and 30, real_audit.py reproduction C).

On moving records the composite fit ran white noise down to its bound: N = 1e-56 .. 1e-15
with a zero-width interval and no note, where the white level sigma/sqrt(fs) is far above;
nothing said the record was not still; a misfit could give the wavelet variance an inf
interval. Each test fails on main before issue 26's imufit26 branch.
"""

from __future__ import annotations

import numpy as np
from test_gmwm_no_warnings import moving_axes

import noisevar
from noisevar.noise_model.gmwm.fitting import MAX_LOG_HALF_WIDTH, wv_band
from noisevar.noise_model.inertial import white_level

RATE = 50.0
TRUE_N = 0.01 / np.sqrt(RATE)


def still_then_motion(seed: int, n: int = 4000, still: int = 1500) -> np.ndarray:
    """White noise (std 0.01) still for ``still`` samples, then a sine and a random walk."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / RATE
    z = 0.01 * rng.normal(size=n)
    m = np.arange(n) >= still
    z[m] += 2.0 * np.sin(2 * np.pi * 1.3 * t[m]) + 0.05 * np.cumsum(rng.normal(size=m.sum()))
    return z


def test_n_at_its_bound_reaches_the_white_level() -> None:
    x = moving_axes(0)
    for i, fit in enumerate(noisevar.fit_imu_model(x, RATE)):
        n = fit.parameter("N")
        lo, hi = n.interval
        white = white_level(x[:, i], RATE)
        assert lo <= TRUE_N <= hi  # the truth (0.0014) is inside
        assert hi >= white * (1 - 1e-9)  # and so is the measured sigma/sqrt(fs)
        assert n.value == 0.0
        assert any(t.startswith("N is at its lower bound") for t in fit.notes)


def test_still_fit_keeps_n() -> None:
    z = 0.01 * np.random.default_rng(3).normal(size=4000)
    fit = noisevar.fit_imu_model(z, RATE)
    n = fit.parameter("N")
    assert abs(n.value / TRUE_N - 1) < 0.05 and n.interval[0] > 0
    assert not any("lower bound" in t or "level varies" in t for t in fit.notes)


def test_motion_is_noted_and_still_regimes_fit_the_sensor() -> None:
    z = still_then_motion(0)
    whole = noisevar.fit_imu_model(z, RATE)
    assert any("noise level varies" in t and "regimes='still'" in t for t in whole.notes)
    still = noisevar.fit_imu_model(z, RATE, regimes="still")
    assert still.notes[0].startswith("regimes='still': fitted on the record's longest")
    assert abs(still.parameter("N").value / TRUE_N - 1) < 0.1


def test_wv_interval_stays_finite() -> None:
    nu = np.array([1e-3, 1.0, 1e3])
    lo, hi = wv_band(nu, np.array([1.0, 800.0, np.inf]))
    assert np.all(np.isfinite(lo)) and np.all(np.isfinite(hi)) and np.all(lo > 0)
    assert hi[2] == nu[2] * np.exp(MAX_LOG_HALF_WIDTH)


def test_inertial_noise_says_the_level_varies() -> None:
    z = still_then_motion(1)
    whole = noisevar.inertial_noise(z, RATE)
    assert any(t.startswith("regimes='all': the noise level varies") for t in whole.notes)
    still = noisevar.inertial_noise(0.01 * np.random.default_rng(3).normal(size=4000), RATE)
    assert not any("level varies" in t for t in still.notes)


def test_cli_imu_prints_the_regime_warning(tmp_path, capsys) -> None:
    from noisevar.cli import main

    path = tmp_path / "imu.csv"
    np.savetxt(path, still_then_motion(2)[:, None], delimiter=",", header="g", comments="")
    for extra in ([], ["--model", "auto"]):
        assert main(["imu", str(path), "--rate", "50", *extra]) == 0
        assert "note: regimes='all': the noise level varies" in capsys.readouterr().out
    assert main(["imu", str(path), "--rate", "50", "--model", "auto", "--regimes", "still"]) == 0
    out = capsys.readouterr().out
    assert "note: regimes='still': fitted on the record's longest still stretch" in out
    assert "level varies" not in out


def test_pooled_records_name_the_one_that_moves() -> None:
    """``fit_imu_records`` had no motion check: a night with motion pooled with still ones
    gave a misfit and no word of which record moved."""
    still = [0.01 * np.random.default_rng(s).normal(size=4000) for s in (4, 5)]
    fit = noisevar.fit_imu_records([still[0], still_then_motion(0), still[1]], RATE)
    said = [t for t in fit.notes if "noise level varies" in t]
    assert len(said) == 1 and said[0].startswith("record 1: ")
    quiet = noisevar.fit_imu_records(still, RATE)
    assert not any("noise level varies" in t for t in quiet.notes)

"""The constant-velocity model for recorded data and the filter summary row."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.kalman import run_filter
from noisevar.kalman.evaluation import filter_summary
from noisevar.systems.scenarios import constant_velocity_model


def _record(seed: int = 0, n: int = 2000):
    rng = np.random.default_rng(seed)
    t = np.arange(n) * 0.1
    truth = np.column_stack([3.0 * t, 50.0 - 2.0 * t])
    z = truth + rng.normal(0.0, [1.0, 2.0], (n, 2))
    return t, truth, z


def test_constant_velocity_model_follows_two_ramps_with_the_right_noise():
    _, truth, z = _record()
    model = constant_velocity_model(z[0], 0.1, 1e-4, np.array([1.0, 4.0]), ["x", "y"])
    assert model.F.shape == (4, 4) and model.H.shape == (2, 4)
    res = run_filter(model, z)
    est = res.x[:, [0, 2]]
    err = est[200:] - truth[200:]
    # a constant-velocity filter on exact ramps: far below the raw noise, no lag
    assert np.all(np.sqrt(np.mean(err**2, axis=0)) < np.array([0.5, 1.0]))
    assert np.all(np.abs(np.mean(err, axis=0)) < 0.2)


def test_filter_summary_reports_rmse_nis_and_divergence():
    _, truth, z = _record(1)
    model = constant_velocity_model(z[0], 0.1, 1e-4, np.array([1.0, 4.0]), ["x", "y"])
    truth_states = np.column_stack(
        [truth[:, 0], np.full(len(z), 3.0), truth[:, 1], np.full(len(z), -2.0)]
    )
    res = run_filter(model, z[None], truth=truth_states[None])
    row = filter_summary(res, {"position": (0, 2)})
    assert row["channels m"] == 2
    # NIS of a consistent filter is chi-square with m = 2 degrees of freedom
    assert row["mean NIS"] == pytest.approx(2.0, rel=0.15)
    assert 0.0 < row["RMSE position"] < 1.5
    assert row["diverged"] == "no"

"""The stepwise model search fits each model once (docs/algorithms.md §E10, issue 30)."""

from __future__ import annotations

import collections

import pytest

from noisevar.noise_model.gmwm import estimator as est
from noisevar.noise_model.gmwm import fit_imu_model
from noisevar.noise_model.simulate import simulate_inertial


def test_the_search_fits_each_model_once(monkeypatch: pytest.MonkeyPatch) -> None:
    calls: collections.Counter = collections.Counter()
    fit = est.fit

    def counted(keys, starts, wv):  # noqa: ANN001, ANN202
        calls[keys] += 1
        return fit(keys, starts, wv)

    monkeypatch.setattr(est, "fit", counted)
    y = simulate_inertial(
        2**16, 200.0, quantization=1e-4, random_walk=1e-3, rate_random_walk=1e-4, seed=4
    )
    model = fit_imu_model(y, 200.0)
    assert max(calls.values()) == 1
    assert model.keys in calls
    assert len(model.table) == len(calls)  # one row per model fitted

"""Every kinematic model fitted to one record, the record's answer made once."""

import numpy as np

import noisevar.noise_model.kalman_run as kalman_run
from noisevar.noise_model import fit_kalman, fit_models
from noisevar.noise_model.kalman_fit import MODELS


def test_fit_models_is_each_models_fit_with_one_estimate(monkeypatch):
    rng = np.random.default_rng(4)
    z = np.cumsum(rng.normal(0, 0.05, 800)) + rng.normal(0, 0.5, 800)
    calls = []
    real = kalman_run.record_estimate
    monkeypatch.setattr(
        kalman_run, "record_estimate", lambda a, t=None: calls.append(1) or real(a, t)
    )
    seen = []
    fits = fit_models(z, rate=10.0, progress=seen.append)
    assert calls == [1]
    assert list(fits) == list(MODELS)
    for model, fit in fits.items():
        alone = fit_kalman(z, model, rate=10.0)
        assert fit.q == alone.q and fit.r == alone.r
        assert fit.record == alone.record
    assert seen and seen[-1] == 1.0 and all(0 <= f <= 1 for f in seen)

"""Exports: the filterpy snippet reproduces our filter; the config's 'kalman' entry round-trips."""

from __future__ import annotations

import json

import numpy as np
import pytest

from noisevar.config import parse_config, validate_config
from noisevar.errors import NoisevarError
from noisevar.noise_model import fit_kalman, run_tuned
from noisevar.noise_model.export import (
    check_kalman_config,
    filterpy_snippet,
    from_config,
    to_config,
)


@pytest.fixture(scope="module", params=["rw", "cv", "ca"])
def fitted(request, make_track):
    z = make_track(request.param, 3000, 10.0, 2.0, 1.0, seed=21) + 50.0
    return fit_kalman(z, model=request.param, rate=10.0), z


def test_filterpy_snippet_reproduces_our_estimates(fitted):
    tuning, z = fitted
    ns: dict = {}
    exec(filterpy_snippet(tuning), ns)  # noqa: S102 - the snippet is ours, that is the test
    kf = ns["kf"]
    xs = []
    for zk in z[tuning.start :]:
        kf.predict()
        kf.update(zk)
        xs.append(kf.x[:, 0].copy())
    ours = run_tuned(tuning, z).states
    assert np.max(np.abs(np.array(xs) - ours)) < 1e-10 * max(1.0, float(np.max(np.abs(z))))


def test_config_round_trip(fitted):
    tuning, _ = fitted
    cfg = validate_config(to_config(tuning, {"method": "auto"}))
    back = from_config(parse_config(json.dumps(cfg)))
    assert back["model"] == tuning.model and back["rate"] == 10.0
    assert back["q"] == tuning.q and back["r"] == tuning.r
    assert np.allclose(back["Q"], tuning.Q, rtol=1e-12) and np.allclose(back["F"], tuning.F)


def test_config_refuses_edited_matrices_and_bad_values(fitted):
    tuning, _ = fitted
    entry = to_config(tuning)["kalman"]
    with pytest.raises(NoisevarError, match="disagrees"):
        check_kalman_config({**entry, "Q": (2 * tuning.Q).tolist()})
    with pytest.raises(NoisevarError, match="positive"):
        check_kalman_config({**entry, "r": -1.0})
    with pytest.raises(NoisevarError, match="kalman.model"):
        check_kalman_config({**entry, "model": "jerk"})
    with pytest.raises(NoisevarError, match="unknown key"):
        check_kalman_config({**entry, "gain": 1})
    with pytest.raises(NoisevarError, match="no 'kalman'"):
        from_config({"method": "auto"})

"""Seeded kinematic tracks with white measurement noise, for the noise_model tests."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.noise_model.kalman_fit import kinematic_model


def track(model: str, n: int, rate: float, q: float, r: float, seed: int) -> np.ndarray:
    """Positions of a kinematic model driven by density ``q``, plus noise of variance ``r``."""
    rng = np.random.default_rng(seed)
    F, h, Q1 = kinematic_model(model, 1.0 / rate)
    L = np.linalg.cholesky(q * Q1)
    w = rng.standard_normal((n, F.shape[0])) @ L.T
    x = np.zeros(F.shape[0])
    pos = np.empty(n)
    for k in range(n):  # the simulation, not the code under test
        x = F @ x + w[k]
        pos[k] = x[0]
    return pos + rng.normal(0.0, np.sqrt(r), n)


@pytest.fixture(scope="session")
def make_track():
    """The :func:`track` simulator."""
    return track

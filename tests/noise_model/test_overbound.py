"""Conservative set (docs §E7.3): the overbound covers the upper bound at every fitted tau,
never lowers a term, and is tight (some tau touches the bound)."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.noise_model import inertial_noise
from noisevar.noise_model.overbound import overbound, upper_bound
from noisevar.noise_model.simulate import simulate_inertial


@pytest.fixture(scope="module")
def fit():
    y = simulate_inertial(
        60_000, 100.0, random_walk=1e-3, rate_random_walk=5e-5, bias_instability=2e-4, seed=3
    )
    return inertial_noise(y, 100.0, unit="rad/s")


@pytest.mark.parametrize("free", [("N", "K"), ("Q", "N", "B", "K", "R")])
def test_covers_the_bound_minimally(fit, free) -> None:
    ob = overbound(fit, free=free)
    up = upper_bound(fit)
    model = ob.model()
    assert np.all(model >= up * (1 - 1e-6))
    assert np.min(model / up) == pytest.approx(1.0, abs=1e-4)  # touches: not raised more
    for s in free:
        assert ob.values[s] >= ob.best[s] * (1 - 1e-9)
    assert all(ob.values[s] == 0.0 for s in "QNBKR" if s not in free)


def test_nk_covers_bias_instability_and_says_so(fit) -> None:
    ob = overbound(fit)
    assert ob.factors["K"] > 1.0
    assert any("bias instability" in c for c in ob.covers)
    assert ob.to_dict()["free"] == ["N", "K"]


def test_bad_arguments(fit) -> None:
    with pytest.raises(NoisevarError):
        overbound(fit, free=("X",))
    with pytest.raises(NoisevarError):
        upper_bound(fit, ci=1.0)

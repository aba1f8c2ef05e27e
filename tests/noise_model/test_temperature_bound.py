"""The Cramér-Rao bound of the temperature model (§E9): closed forms and the fit against it."""

from __future__ import annotations

import math

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.noise_model import temperature_model
from noisevar.noise_model.simulate import simulate_thermal
from noisevar.noise_model.temperature_bound import model_bound, temperature_bound

RATE = 10.0
N_WHITE, K_WALK = 1e-4, 4e-6


def _ramp(hours: float, updown: bool = False) -> np.ndarray:
    s = np.linspace(0.0, 1.0, int(hours * 3600 * RATE))
    return 10.0 + 30.0 * ((1.0 - np.abs(2.0 * s - 1.0)) if updown else s)


def test_white_noise_bound_is_ordinary_least_squares():
    temp = _ramp(1.0)
    bound = temperature_bound(temp, RATE, white=N_WHITE, block=1.0)
    d = temp.reshape(-1, 10).mean(axis=1)
    want = N_WHITE / math.sqrt(1.0 * np.sum((d - d.mean()) ** 2))
    assert bound.sd("b") == pytest.approx(want, rel=1e-6)
    assert bound.names == ("b",)


def test_random_walk_bound_is_the_walk_over_the_span():
    # on a monotone ramp a walk-dominated bias gives b to K sqrt(D) / span at best, however
    # the data are weighted: the walk's end-to-end spread over the temperature change
    temp = _ramp(10.0)
    bound = temperature_bound(temp, RATE, white=N_WHITE, walk=K_WALK)
    assert bound.sd("b") == pytest.approx(K_WALK * math.sqrt(36000.0) / 30.0, rel=0.02)
    # up and down crosses the span twice: half the spread
    updown = temperature_bound(_ramp(10.0, True), RATE, white=N_WHITE, walk=K_WALK)
    assert updown.sd("b") == pytest.approx(bound.sd("b") / 2.0, rel=0.05)


def test_warmup_adds_its_parameters_and_costs_information():
    temp = _ramp(2.0)
    plain = temperature_bound(temp, RATE, white=N_WHITE, walk=K_WALK)
    warm = temperature_bound(temp, RATE, white=N_WHITE, walk=K_WALK, warmup=(2e-3, 300.0))
    assert warm.names == ("b", "amplitude", "log_time_constant")
    assert warm.sd("b") > plain.sd("b")
    assert 0.0 < warm.sd("log_time_constant") < 1.0
    with pytest.raises(NoisevarError, match="No parameter"):
        warm.sd("c")


def test_the_bound_at_a_fit_is_near_the_bound_at_the_truth():
    temp = _ramp(2.0)
    warm = (1e-3, 600.0)
    y = simulate_thermal(
        temp,
        RATE,
        polynomial=(2e-3, 3e-4),
        warmup=warm,
        random_walk=N_WHITE,
        rate_random_walk=K_WALK,
        seed=3,
    )
    m = temperature_model(y, temp, RATE, order=1, warmup=True, bootstrap=10)
    at_fit = model_bound(m, temp)
    truth = temperature_bound(temp, RATE, white=N_WHITE, walk=K_WALK, warmup=warm)
    assert at_fit.names == truth.names
    assert at_fit.sd("b") == pytest.approx(truth.sd("b"), rel=0.25)
    assert at_fit.block == pytest.approx(m.block)
    with pytest.raises(NoisevarError, match="TemperatureModel"):
        model_bound((m,), temp)


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"white": 0.0}, "white"),
        ({"white": N_WHITE, "walk": -1.0}, "walk"),
        ({"white": N_WHITE, "order": 4}, "order"),
        ({"white": N_WHITE, "warmup": (1e-3, -5.0)}, "warmup"),
        ({"white": N_WHITE, "block": 1000.0}, "blocks"),
    ],
)
def test_bad_input_says_what_is_needed(kwargs, match):
    with pytest.raises(NoisevarError, match=match):
        temperature_bound(_ramp(1.0), RATE, **kwargs)


def test_the_fit_reaches_the_bound_under_a_random_walk():
    # 24 records of 2 h on a monotone ramp with a walk and a warm-up: the fit's errors over
    # the bound's standard deviation have an RMS near 1 for b and ln tau (efficient).
    # Measured: 0.95 and 0.84; ordinary least squares on the levels gives 1.03 and 1.32.
    temp = _ramp(2.0)
    warm = (1e-3, 600.0)
    bound = temperature_bound(temp, RATE, white=N_WHITE, walk=K_WALK, warmup=warm)
    z_b, z_tau = [], []
    for seed in range(24):
        y = simulate_thermal(
            temp,
            RATE,
            polynomial=(2e-3, 3e-4),
            warmup=warm,
            random_walk=N_WHITE,
            rate_random_walk=K_WALK,
            seed=seed,
        )
        m = temperature_model(y, temp, RATE, order=1, warmup=True, bootstrap=10, seed=seed)
        z_b.append((m.coefficient("b").value - 3e-4) / bound.sd("b"))
        z_tau.append(math.log(m.warmup.time_constant / warm[1]) / bound.sd("log_time_constant"))
    assert 0.6 < math.sqrt(np.mean(np.square(z_b))) < 1.3
    assert 0.6 < math.sqrt(np.mean(np.square(z_tau))) < 1.2

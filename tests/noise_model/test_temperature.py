"""The temperature model: bias(T), warm-up, noise(T), process noise, MATLAB export (§E9)."""

from __future__ import annotations

import math

import numpy as np
import pytest

from noisevar.errors import NoisevarError
from noisevar.noise_model import matlab_temperature_params, temperature_model
from noisevar.noise_model.simulate import simulate_thermal

RATE = 50.0
N_WHITE = 1e-3  # u/√Hz
A_TRUE, B_TRUE = 2e-3, 3e-4  # u, u/°C
WARM = (4e-3, 300.0)  # amplitude (u), time constant (s)


def _ramp(hours: float = 1.0, lo: float = 10.0, hi: float = 40.0, seed: int = 7) -> np.ndarray:
    n = int(hours * 3600 * RATE)
    rng = np.random.default_rng(seed)
    return np.linspace(lo, hi, n) + 0.02 * rng.standard_normal(n)


@pytest.fixture(scope="module")
def warm_fit():
    temp = _ramp()
    y = simulate_thermal(
        temp, RATE, polynomial=(A_TRUE, B_TRUE), warmup=WARM, random_walk=N_WHITE, seed=1
    )
    return temperature_model(y, temp, RATE, unit="rad/s", bootstrap=100)


def test_recovers_the_linear_coefficients_with_intervals(warm_fit):
    m = warm_fit
    assert m.order == 1
    b = m.coefficient("b")
    assert b.value == pytest.approx(B_TRUE, rel=0.03)
    assert b.interval[0] <= B_TRUE <= b.interval[1]
    assert m.coefficient("a").value == pytest.approx(A_TRUE, rel=0.03)
    assert b.unit == "rad/s/°C"
    assert sum(c.selected for c in m.candidates) == 1


def test_warmup_time_constant_and_amplitude(warm_fit):
    w = warm_fit.warmup
    assert w is not None
    assert w.time_constant == pytest.approx(WARM[1], rel=0.15)
    assert w.amplitude == pytest.approx(WARM[0], rel=0.1)
    lo, hi = w.time_constant_interval
    assert lo < w.time_constant < hi
    assert w.settled_after == pytest.approx(w.time_constant * math.log(100.0))


def test_no_warmup_is_found_where_there_is_none():
    temp = _ramp(0.5)
    y = simulate_thermal(temp, RATE, polynomial=(A_TRUE, B_TRUE), random_walk=N_WHITE, seed=2)
    m = temperature_model(y, temp, RATE, bootstrap=50)
    assert m.warmup is None
    assert m.coefficient("b").value == pytest.approx(B_TRUE, rel=0.05)


def test_quadratic_is_chosen_and_recovered():
    temp = _ramp(0.5, -10.0, 50.0)
    c_true = 2e-5
    y = simulate_thermal(
        temp, RATE, polynomial=(A_TRUE, B_TRUE, c_true), random_walk=N_WHITE, seed=3
    )
    m = temperature_model(y, temp, RATE, warmup=False, bootstrap=50)
    assert m.order == 2
    assert m.coefficient("c").value == pytest.approx(c_true, rel=0.05)
    assert m.coefficient("c").unit == "u/°C^2"


def test_axes_together_match_one_at_a_time():
    temp = _ramp(0.25)
    cols = [
        simulate_thermal(temp, RATE, polynomial=(0.0, b), random_walk=N_WHITE, seed=s)
        for s, b in enumerate((1e-4, -2e-4))
    ]
    both = temperature_model(np.column_stack(cols), temp, RATE, axis=0, warmup=False, bootstrap=30)
    one = temperature_model(cols[1], temp, RATE, warmup=False, bootstrap=30)
    assert len(both) == 2
    assert both[1].coefficient("b").value == pytest.approx(one.coefficient("b").value, rel=1e-12)
    out = matlab_temperature_params(both)
    assert out.temperature_bias[1] == pytest.approx(one.coefficient("b").value, rel=1e-9)
    assert out.temperature_scale_factor is None
    assert set(out.to_dict()) == {"ConstantBias", "TemperatureBias"}


def test_scale_factor_from_a_known_input_rate():
    temp = _ramp(0.25)
    n = temp.size
    w = 0.5 * np.sin(2 * np.pi * np.arange(n) / RATE / 60.0)  # a turntable's rate
    s0, s1 = 0.01, 2e-4
    y = simulate_thermal(temp, RATE, polynomial=(A_TRUE, B_TRUE), random_walk=N_WHITE, seed=4)
    y = y + (s0 + s1 * (temp - 25.0)) * w
    m = temperature_model(y, temp, RATE, input_rate=w, warmup=False, bootstrap=30)
    assert m.coefficient("scale_factor_slope").value == pytest.approx(s1, rel=0.05)
    assert matlab_temperature_params(m).temperature_scale_factor[0] == pytest.approx(
        100 * s1, rel=0.05
    )


def test_noise_by_temperature_and_process_noise_closed_form(warm_fit):
    m = warm_fit
    assert np.allclose(m.noise.level, N_WHITE, rtol=0.05)
    assert np.all(m.noise.interval[0] <= m.noise.level)
    p = m.process_noise
    b = abs(m.coefficient("b").value)
    span = p.temperature_range[1] - p.temperature_range[0]
    assert p.density == pytest.approx(b * math.sqrt(p.temperature_rate * span), rel=1e-12)
    # the ramp's own rate, 30 °C per hour, within the jitter of the temperature sensor
    assert p.temperature_rate == pytest.approx(30.0 / 3600.0, rel=0.2)
    assert p.per_step_variance == pytest.approx(p.density**2 / RATE)
    assert "°C/min" in p.assumption


def test_stated_range_and_rate_set_the_process_noise():
    temp = _ramp(0.25)
    y = simulate_thermal(temp, RATE, polynomial=(0.0, B_TRUE), random_walk=N_WHITE, seed=5)
    m = temperature_model(
        y, temp, RATE, order=1, warmup=False, temperature_range=(0, 60), temperature_rate=0.01
    )
    b = abs(m.coefficient("b").value)
    assert m.process_noise.density == pytest.approx(b * math.sqrt(0.01 * 60), rel=1e-12)


@pytest.mark.parametrize(
    ("change", "match"),
    [
        ({"temperature": "nan"}, "finite"),
        ({"temperature": "flat"}, "at least 0.5 °C"),
        ({"temperature": "short"}, "one value per sample"),
        ({"order": 7}, "order"),
        ({"warmup": "yes"}, "warmup"),
        ({"rate": 0.0}, "rate must be positive"),
        ({"n": 20}, "blocks"),
        ({"z": "nan"}, "finite"),
    ],
)
def test_bad_input_says_what_is_needed(change, match):
    n = change.get("n", 5000)
    temp = np.linspace(20.0, 30.0, n)
    z = np.random.default_rng(0).standard_normal(n)
    kind = change.get("temperature")
    if kind == "nan":
        temp[10] = np.nan
    elif kind == "flat":
        temp = np.full(n, 21.0)
    elif kind == "short":
        temp = temp[:-1]
    if change.get("z") == "nan":
        z[3] = np.nan
    kwargs = {k: v for k, v in change.items() if k in ("order", "warmup")}
    with pytest.raises(NoisevarError, match=match):
        temperature_model(z, temp, change.get("rate", RATE), **kwargs)


def test_a_random_walk_bias_is_weighted_not_mistaken_for_temperature():
    # up and down through 30 °C in 4 h at 10 Hz, with a rate random walk (Kalibr's bias
    # model) whose variance passes the white noise's after about 40 blocks
    rate, n = 10.0, 4 * 3600 * 10
    s = np.linspace(0.0, 1.0, n)
    temp = 10.0 + 30.0 * (1.0 - np.abs(2.0 * s - 1.0))
    white, k = 1e-4, 4e-6
    y = simulate_thermal(
        temp, rate, polynomial=(A_TRUE, B_TRUE), random_walk=white, rate_random_walk=k, seed=9
    )
    m = temperature_model(y, temp, rate, warmup=False, bootstrap=60)
    b = m.coefficient("b")
    half = (b.interval[1] - b.interval[0]) / 2.0
    assert abs(b.value - B_TRUE) <= 3.0 * half
    assert b.value == pytest.approx(B_TRUE, rel=0.1)
    assert m.residual_walk == pytest.approx(k, rel=0.3)
    assert m.residual_white == pytest.approx(white, rel=0.1)

"""Seeded signal generators: reproducibility, shapes, noise models, geometry, bad input."""

from __future__ import annotations

import inspect

import numpy as np
import pytest

import noisevar as nv
from noisevar.errors import NoisevarError
from noisevar.signals import GPS_CHANNELS, signal_spec

FAMILIES = nv.signal_names()


def test_the_families():
    assert set(FAMILIES) == {
        "fast-slow",
        "gps-circle",
        "random-jerk",
        "steps-ramps",
        "noise-step",
        "noise-ramp",
    }


@pytest.mark.parametrize("family", FAMILIES)
def test_generated_signal_shapes_and_fields(family):
    g = nv.generate(family, n=1500, seed=3)
    assert isinstance(g, nv.GeneratedSignal)
    assert g.name == family
    assert g.t.shape == g.clean.shape == g.noise_std.shape == g.measured.shape == (1500,)
    assert np.all(np.isfinite(g.measured))
    assert np.all(g.noise_std > 0)
    assert np.all(np.diff(g.t) > 0)
    assert g.sample_period == pytest.approx(g.t[1] - g.t[0])
    assert g.true_variance == pytest.approx(np.mean(g.noise_std**2))
    assert g.seed == 3
    assert g.params["n"] == 1500 and g.params["seed"] == 3


@pytest.mark.parametrize("family", FAMILIES)
def test_same_seed_same_signal_other_seed_other_noise(family):
    a = nv.generate(family, n=1000, seed=7)
    b = nv.generate(family, n=1000, seed=7)
    c = nv.generate(family, n=1000, seed=8)
    np.testing.assert_array_equal(a.measured, b.measured)
    np.testing.assert_array_equal(a.clean, b.clean)
    assert not np.array_equal(a.measured - a.clean, c.measured - c.clean)


@pytest.mark.parametrize("family", FAMILIES)
def test_noise_matches_the_stated_model(family):
    g = nv.generate(family, n=40_000, seed=1)
    noise = g.measured - g.clean
    standardised = noise / g.noise_std
    assert np.mean(standardised) == pytest.approx(0.0, abs=0.03)
    assert np.var(standardised) == pytest.approx(1.0, rel=0.03)
    # white: lag-1 autocorrelation near 0
    assert abs(np.corrcoef(standardised[:-1], standardised[1:])[0, 1]) < 0.03


@pytest.mark.parametrize("family", FAMILIES)
def test_monte_carlo_runs_share_the_clean_signal(family):
    g = nv.generate(family, n=800, seed=2, runs=5)
    assert g.measured.shape == (5, 800)
    assert g.clean.shape == (800,)
    noise = g.measured - g.clean
    assert np.all(np.std(noise, axis=1) > 0)
    assert not np.allclose(noise[0], noise[1])
    single = nv.generate(family, n=800, seed=2)
    np.testing.assert_array_equal(single.clean, g.clean)


def test_default_noise_is_the_papers_sigma_5():
    for family in ("fast-slow", "random-jerk", "steps-ramps"):
        g = nv.generate(family, n=500, seed=0)
        assert g.true_variance == pytest.approx(25.0)
    assert nv.generate("fast-slow", n=500, noise_std=2.0).true_variance == pytest.approx(4.0)


def test_gps_circle_geometry_of_spec_a9():
    """Radius 300 m, angular rate pi/100 rad/s, sample period 0.5 s."""
    east = nv.generate("gps-circle", n=2000, channel="east", seed=0)
    north = nv.generate("gps-circle", n=2000, channel="north", seed=0)
    speed = nv.generate("gps-circle", n=2000, channel="speed", seed=0)
    heading = nv.generate("gps-circle", n=2000, channel="heading", seed=0)
    assert east.sample_period == 0.5
    np.testing.assert_allclose(np.hypot(east.clean, north.clean), 300.0, rtol=1e-12)
    np.testing.assert_allclose(speed.clean, 300.0 * np.pi / 100.0)
    np.testing.assert_allclose(np.diff(heading.clean), np.pi / 100.0 * 0.5, rtol=1e-9)
    # the direction of motion is the heading
    ve, vn = np.gradient(east.clean, 0.5), np.gradient(north.clean, 0.5)
    course = np.arctan2(vn, ve)
    np.testing.assert_allclose(
        np.angle(np.exp(1j * (course[1:-1] - heading.clean[1:-1]))), 0.0, atol=1e-4
    )
    # paper's noise standard deviations
    assert GPS_CHANNELS == pytest.approx(
        {"east": 5.0, "north": 5.0, "speed": np.sqrt(2.0), "heading": 0.01}
    )
    assert east.true_variance == 25.0
    assert speed.true_variance == pytest.approx(2.0)
    assert heading.true_variance == pytest.approx(1e-4)
    assert nv.generate("gps-circle", n=500, noise_std=1.0).true_variance == 1.0


def test_noise_step_and_ramp_true_variance_is_the_record_mean():
    step = nv.generate("noise-step", n=6000, seed=0)
    assert step.noise_std[0] == 5.0 and step.noise_std[-1] == 15.0
    assert step.true_variance == pytest.approx((25.0 + 225.0) / 2.0)
    assert np.sum(step.noise_std == 5.0) == 3000
    ramp = nv.generate("noise-ramp", n=6000, seed=0, factor=2.0)
    assert ramp.noise_std[0] == pytest.approx(5.0) and ramp.noise_std[-1] == pytest.approx(10.0)
    assert np.all(np.diff(ramp.noise_std) > 0)
    assert ramp.true_variance == pytest.approx(np.mean(np.linspace(5.0, 10.0, 6000) ** 2))


def test_steps_ramps_has_the_requested_jumps():
    g = nv.generate("steps-ramps", n=6000, seed=4, n_steps=5)
    d = np.abs(np.diff(g.clean))
    jumps = d > 5.0 * g.noise_std[0]  # jumps are 10-40 sigma, ramps at most 0.3 sigma
    assert jumps.sum() == 5
    assert np.max(d[~jumps]) <= 0.3 * 5.0 + 1e-9


def test_smooth_families_are_smooth():
    """Per-sample change of the clean signal is small against the noise (SOMD's premise)."""
    for family in ("random-jerk", "noise-step", "noise-ramp"):
        g = nv.generate(family, n=6000, seed=5)
        assert np.std(np.diff(g.clean, 2)) < 0.05 * g.noise_std.min()


def test_fast_slow_has_a_fast_burst_and_slow_parts():
    g = nv.generate("fast-slow", n=6000, seed=0)
    d2 = np.abs(np.diff(g.clean, 2))
    burst = slice(int(0.42 * 6000), int(0.48 * 6000))
    slow = slice(int(0.05 * 6000), int(0.3 * 6000))
    assert np.max(d2[burst]) > 20 * np.max(d2[slow])


@pytest.mark.parametrize(
    ("name", "params", "phrase"),
    [
        ("sine", {}, "unknown signal 'sine'"),
        ("fast-slow", {"n": 50}, r"n=50 is out of range: it must be in \[100, "),
        ("fast-slow", {"runs": 0}, r"runs=0 is out of range: it must be in \[1, "),
        ("fast-slow", {"n": 1_000_000, "runs": 100}, "over the limit of 50,000,000"),
        ("fast-slow", {"colour": "red"}, r"signal .fast-slow. does not take parameter\(s\) colour"),
        ("gps-circle", {"channel": "altitude"}, "channel must be a string: one of east"),
        ("noise-step", {"factor": -1.0}, "factor=-1.0 is out of range"),
        ("gps-circle", {"sample_period": 0.0}, "sample_period=0.0 is out of range"),
        ("steps-ramps", {"n_steps": 2.5}, "n_steps must be an integer"),
        ("random-jerk", {"jerk_std": float("inf")}, "jerk_std must be finite"),
    ],
)
def test_bad_generator_input(name, params, phrase):
    with pytest.raises(NoisevarError, match=phrase):
        nv.generate(name, **params)


@pytest.mark.parametrize("family", FAMILIES)
def test_every_parameter_has_a_spec_whose_default_is_the_generators(family):
    spec = signal_spec(family)
    signature = inspect.signature(spec.func).parameters
    assert list(spec.param_specs) == [
        "n",
        "noise_std",
        "seed",
        "runs",
        *(p.name for p in spec.extras),
    ]
    assert set(spec.param_specs) == set(signature)
    for name, p in spec.param_specs.items():
        assert p.default == signature[name].default, name
        assert p.help, name
        if p.default is not None:
            assert p.validate(p.default) == p.default, name


def test_parameters_are_converted_to_their_kind_and_big_seeds_stay_exact():
    g = nv.generate("steps-ramps", n=1000.0, seed=2**62 + 1, n_steps=3.0)
    assert g.params["n"] == 1000 and isinstance(g.params["n"], int)
    assert g.params["seed"] == 2**62 + 1 and g.params["n_steps"] == 3
    np.testing.assert_array_equal(
        g.measured, nv.generate("steps-ramps", n=1000, seed=2**62 + 1, n_steps=3).measured
    )

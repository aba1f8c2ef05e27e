"""A vibration is not differenced data (issue 26; docs/algorithms.md §E2 *Vibration*).

EuRoC MH_01's hexacopter accelerometer (ADIS16448, 200 Hz) carries rotor vibration near the
Nyquist rate: its residual's autocorrelation alternates in sign lag after lag (-0.82, +0.68,
-0.61, ...). The MA(1) fit read -0.56 there and the record was flagged differenced (its R
multiplied by 0.53), while the verdict called it coloured and its still stretches
"low-passed by the sensor". Seeded: white noise with a sinusoid of period 2.1 samples.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv
from noisevar.diagnostics.verdict_parts import departure_cause
from noisevar.diagnostics.whiteness import WhitenessTest

N = 20_000


def _vibrating(seed: int, f: float = 0.47, a: float = 1.5, n: int = N) -> np.ndarray:
    t = np.arange(n)
    return np.random.default_rng(seed).normal(size=n) + a * np.sin(2 * np.pi * f * t + seed)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_vibration_near_nyquist_is_not_differenced(seed: int) -> None:
    est = nv.estimate(_vibrating(seed))
    d = est.diagnostics
    assert not d.differenced and d.flags["differenced"] is False
    assert d.noise_correlation is None
    # R is the variance per sample the filter sees (noise 1 + the sinusoid's 1.125), not
    # halved by a differenced-noise correction
    assert est.variance > 1.5, est.variance


@pytest.mark.parametrize("f", [0.47, 0.3, 0.13])
def test_the_verdict_names_the_oscillation_and_what_to_do(f: float) -> None:
    v = nv.estimate(_vibrating(3, f=f, a=0.7)).verdict
    assert f"oscillation at {f:.2f} of the sample rate" in v, v
    assert "notch or low-pass" in v
    assert "differenced" not in v and "low-passed by the sensor" not in v


def test_a_vibration_between_motion_and_rest_is_named_not_differenced() -> None:
    """Still at both ends, moving between, vibrating near Nyquist throughout (a multicopter)."""
    rng = np.random.default_rng(5)
    z = _vibrating(5)
    z[6000:14000] += rng.normal(0, 6, 8000) + 40 * np.sin(np.arange(8000) / 90)
    est = nv.estimate(z)
    assert not est.diagnostics.differenced
    assert "differenced" not in est.verdict and "low-passed by the sensor" not in est.verdict
    assert "oscillation at 0.47" in est.verdict, est.verdict


@pytest.mark.parametrize("kernel", [[1.0, -1.0], [0.5, 0.0, -0.5], [1, 1, 0, -1, -1]])
@pytest.mark.parametrize("n", [1000, N])
def test_differenced_and_derivative_noise_are_still_recognised(kernel: list, n: int) -> None:
    k = np.asarray(kernel, dtype=float)
    for seed in range(3):
        w = np.random.default_rng(100 + seed).normal(size=n + k.size - 1)
        slow = 20 * np.sin(np.arange(n) / 700)
        d = nv.estimate(np.convolve(w, k, mode="valid") + slow).diagnostics
        assert d.differenced and d.whiteness.oscillation is not None
        assert not d.whiteness.oscillation.found


def test_a_negative_still_correlation_is_not_called_a_low_pass() -> None:
    """A sensor's low-pass correlates neighbours positively; a negative excess is no low-pass."""
    acf = np.array([0.0, 0.0, -0.4, 0.0])
    w = WhitenessTest(acf, np.zeros(4), np.full(4, 0.05), 80.0, 1e-12, 1000)
    assert "low-passed" not in departure_cause(w, 2)
    up = WhitenessTest(-acf, np.zeros(4), np.full(4, 0.05), 80.0, 1e-12, 1000)
    assert "low-passed by the sensor" in departure_cause(up, 2)


@pytest.mark.parametrize("seed", range(5))
def test_low_passed_noise_is_not_named_an_oscillation(seed: int) -> None:
    """AR(1) and Butterworth low-passes: their residual's negative lobe is no vibration."""
    from scipy.signal import butter, lfilter

    rng = np.random.default_rng(seed)
    b, a = butter(2, 0.3)
    for z in (lfilter([1.0], [1.0, -0.5], rng.normal(size=N)), lfilter(b, a, rng.normal(size=N))):
        est = nv.estimate(z)
        o = est.diagnostics.whiteness.oscillation
        assert o is not None and not o.found and "oscillation" not in est.verdict

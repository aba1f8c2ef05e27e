"""The verdict says when the still stretches' own noise is not white (issue 26, real logs).

Lower-back IMU records (mobgap) are still for a third of their length, and their noise there
is low-passed (residual lag-1 autocorrelation +0.2 to +0.8): their still level is a white
part that depends on the bandwidth, and the verdict must say so instead of quoting it as the
sensor noise.
"""

from __future__ import annotations

import re

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar

N = 20000


def _record(seed: int, low_passed: bool) -> np.ndarray:
    rng = np.random.default_rng(seed)
    noise = rng.normal(size=N)
    if low_passed:
        noise = lfilter([1.0], [1.0, -0.6], noise)
    motion = np.zeros(N)
    motion[4000:16000] = 30.0 * np.sin(2.0 * np.pi * np.arange(12000) / 37.0)
    return noise + motion


@pytest.mark.parametrize("seed", [0, 1])
def test_low_passed_still_noise_is_named(seed: int) -> None:
    diag = noisevar.estimate(_record(seed, low_passed=True)).diagnostics
    assert diag.level_varies
    assert diag.still_whiteness is not None and not diag.still_whiteness.white
    assert "even there the noise is not white" in diag.verdict
    assert "depends on the bandwidth" in diag.verdict


@pytest.mark.parametrize("seed", [0, 1])
def test_white_still_noise_is_not_called_coloured(seed: int) -> None:
    diag = noisevar.estimate(_record(seed, low_passed=False)).diagnostics
    assert diag.level_varies
    assert diag.still_whiteness is not None and diag.still_whiteness.white
    assert "not white" not in diag.verdict


@pytest.mark.parametrize("low_passed", [False, True])
def test_still_whiteness_is_tested_across_a_gap(low_passed: bool) -> None:
    # a gap splits the record into two uniform segments; the still stretches' whiteness
    # is still tested (it was skipped on any record of more than one segment)
    t = np.arange(N) / 100.0
    t[9000:] += 0.5
    diag = noisevar.estimate(_record(0, low_passed), t=t).diagnostics
    assert len(diag.gaps) == 1
    assert diag.still_whiteness is not None
    assert diag.still_whiteness.white is (not low_passed)
    assert ("even there the noise is not white" in diag.verdict) is low_passed


@pytest.mark.parametrize("seed", [0, 1])
def test_a_still_stretch_too_short_to_test_is_said_to_be_untested(seed: int) -> None:
    # mobgap HA002 accelerometer Y (issue 26): its still stretch is 2 % of the record, too
    # short for the whiteness test; the verdict quoted its level as the sensor noise, silent
    rng = np.random.default_rng(seed)
    noise = lfilter([1.0], [1.0, -0.6], rng.normal(size=N))
    k = np.arange(N)
    motion = 10.0 * np.sin(2.0 * np.pi * k / 4.3) * (1.0 + 0.5 * np.sin(k / 900.0))
    motion[9000:9300] = 0.0  # 1.5 % still
    est = noisevar.estimate(noise + motion)
    diag = est.diagnostics
    assert diag.level_varies
    assert diag.still_whiteness is None
    assert "too short to test whether their noise is white" in diag.verdict
    assert "untested" in diag.verdict


def test_the_still_stretches_excess_autocorrelation_is_said_as_an_excess() -> None:
    """Strongly low-passed still noise (the IERS's UT1-UTC, real_audit7): the residual's lag-1
    autocorrelation beyond white noise's passes 1, and the verdict wrote it as an
    autocorrelation ("lag-1 autocorrelation +1.02:"), a value no autocorrelation takes."""
    rng = np.random.default_rng(7)
    poles = np.convolve(
        np.convolve([1.0, -0.85], [1.0, -0.85]), np.convolve([1.0, -0.85], [1.0, -0.85])
    )
    noise = lfilter([1.0], poles, rng.normal(size=N))  # four poles at 0.85: very smooth
    motion = np.zeros(N)
    motion[4000:16000] = 300.0 * noise.std() * np.sin(2.0 * np.pi * np.arange(12000) / 37.0)
    diag = noisevar.estimate(noise + motion).diagnostics
    assert diag.still_whiteness is not None and diag.still_whiteness.lag1 > 1
    said = re.findall(r"lag-1 autocorrelation ([+-][0-9.]+)( beyond white noise's)?", diag.verdict)
    assert said
    for value, excess in said:
        assert abs(float(value)) <= 1 or excess

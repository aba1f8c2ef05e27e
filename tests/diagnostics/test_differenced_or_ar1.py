"""AR(1) noise of φ = -1/2 is not differenced data (issue 26 item 3; docs/algorithms.md §E2
*Differenced or AR(1)*).

Both have a lag-1 correlation of -1/2; from lag 2 on AR(1) noise goes on (+1/4, -1/8, ...)
and differenced white noise is 0. The record was called differenced whatever its length.
Now the evidence decides (``WhitenessTest.ar1_evidence``): AR(1) noise is named with its φ
(99 of 100 seeded records of 1,000 samples), differenced data stay differenced, and a record
too short to tell them apart is said to be either.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar as nv


def _ar1(seed: int, n: int, phi: float = -0.5) -> np.ndarray:
    return lfilter([1.0], [1.0, -phi], np.random.default_rng(seed).normal(size=n))


def _diff(seed: int, n: int) -> np.ndarray:
    return np.diff(np.random.default_rng(seed).normal(size=n + 1))


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_ar1_noise_of_negative_phi_is_named_not_differenced(seed: int) -> None:
    est = nv.estimate(_ar1(seed, 20_000))
    d = est.diagnostics
    assert not d.differenced and d.flags["differenced"] is False
    assert d.ar1_phi == pytest.approx(-0.5, abs=0.06)
    assert f"AR(1) noise of φ = {d.ar1_phi:+.2f}" in est.verdict  # φ refined off the 0.05 grid
    assert "not differenced" in est.verdict
    assert "model AR(1) measurement noise" in est.verdict
    # R is the variance per sample the filter sees: 1 / (1 - φ²) for unit innovations
    assert est.variance == pytest.approx(4.0 / 3.0, rel=0.06), est.variance
    assert "differenced data, or AR(1)" in " ".join(est.notes)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_short_record_is_said_to_be_either(seed: int) -> None:
    """At 300 samples neither fits evidently better, for either kind of record."""
    for z in (_ar1(seed, 300, -0.4), _diff(seed, 300)):
        est = nv.estimate(z)
        d = est.diagnostics
        assert d.differenced and d.differenced_or_ar1
        assert "look differenced" in est.verdict and "or the noise is AR(1)" in est.verdict
        assert "too short to tell them apart" in est.verdict, est.verdict


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_long_differenced_data_stay_differenced(seed: int) -> None:
    est = nv.estimate(_diff(seed, 20_000))
    d = est.diagnostics
    assert d.differenced and not d.differenced_or_ar1 and d.ar1_phi is None
    assert d.whiteness.ar1_evidence < -25.0
    assert "AR(1)" not in est.verdict and "look differenced" in est.verdict
    assert est.variance == pytest.approx(2.0, rel=0.04)


#: Seeds (20000 on, 1,000 samples) whose AR(1) noise of φ = -0.7 main called an oscillation
#: (R 2.3-3.2 times the per-sample variance, uncorrected): its spectrum rises to the Nyquist
#: rate, which one slowly decaying oscillation fits at 0.48-0.49 of the rate.
CALLED_OSCILLATION = (20000, 20023, 20027, 20028, 20032)


@pytest.mark.parametrize("seed", CALLED_OSCILLATION)
def test_ar1_noise_of_phi_minus_07_is_not_a_vibration(seed: int) -> None:
    """The oscillation must lie apart from the Nyquist rate, where AR(1) noise of negative φ
    peaks (``Oscillation.apart``, docs/algorithms.md §E2 *Vibration*)."""
    est = nv.estimate(_ar1(seed, 1000, -0.7))
    d = est.diagnostics
    o = d.whiteness.oscillation
    assert o is not None and o.explains >= 0.8 and not o.found  # the fit alone would name it
    assert d.ar1_phi == pytest.approx(-0.7, abs=0.08)
    assert "oscillation" not in est.verdict and "AR(1) noise of φ" in est.verdict
    per_sample = 1.0 / (1.0 - 0.7**2)
    assert est.ci95[0] <= per_sample <= est.ci95[1], (est.variance / per_sample, est.ci95)


@pytest.mark.parametrize("phi", [-0.7])
def test_r_of_ar1_noise_is_its_variance_per_sample(phi: float) -> None:
    """R is corrected through the residual filter by the AR(1) fit's correlations (φ^k at
    every lag), not an MA(4) fit of them, which read φ = -0.7 26 % high (5,000 samples:
    1.26, 5-95 % 1.11-1.33); over 20 seeds of 5,000 samples R is within 3 % of
    1 / (1 - φ²) on average and its ci95 covers it in at least 17."""
    per_sample = 1.0 / (1.0 - phi**2)
    ests = [nv.estimate(_ar1(40_000 + s, 5000, phi)) for s in range(20)]
    ratio = np.array([e.variance for e in ests]) / per_sample
    assert abs(ratio.mean() - 1.0) < 0.03, ratio
    assert sum(e.ci95[0] <= per_sample <= e.ci95[1] for e in ests) >= 17

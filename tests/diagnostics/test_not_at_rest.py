"""Still stretches that do not measure the sensor at rest (issue 26; real_audit16, real_audit12).

A filter's smoothed output (RTKLIB's still RTK-float antennas: lag-1 +0.79 on the still
stretches) is smoother than any first-order low-pass leaves noise: its still level, 1e-5 of
the solver's own variance, was quoted as "the sensor noise". The calm stretches of a signal
that never stops moving (wind speed) depart from white noise as the whole record does: their
level was quoted as "the sensor noise" at 1.9-8.1x two anemometers' bound.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar
from noisevar.diagnostics.assumptions import ASSUMPTIONS

UNSMOOTHED = ASSUMPTIONS.get("unsmoothed", ("(not checked)",))[0]


def _smoothed_output(seed: int) -> np.ndarray:
    """A still antenna's position as a second-order smoother writes it, a move in between."""
    rng = np.random.default_rng(seed)
    n = 6000
    z = lfilter([0.05], [1.0, -0.95], lfilter([0.05], [1.0, -0.95], rng.normal(size=n)))
    z[3000:3600] += np.cumsum(rng.normal(size=600)) * 0.05  # carried a few metres
    return np.round(z, 4)


def _calm_and_gusts(seed: int) -> np.ndarray:
    """AR(1) turbulence whose level wanders (calm, then gusts): never at rest."""
    rng = np.random.default_rng(seed)
    n = 20000
    level = np.exp(np.cumsum(rng.normal(size=n)) * 0.02)
    return lfilter([1.0], [1.0, -0.7], rng.normal(size=n)) * level


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_smoothed_output_is_no_r_to_use(seed: int) -> None:
    """Before: "the sensor noise measured in its still stretches ... is 1.1e-8 ... its white
    part", the assumptions silent."""
    est = noisevar.estimate(_smoothed_output(seed))
    v = est.diagnostics.verdict
    assert est.still is not None, v
    assert "smoothed output" in v and "not an R to use" in v, v
    assert "sensor noise measured" not in v, v
    assert est.assumptions.get(UNSMOOTHED) is False


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_calm_stretches_bound_the_noise(seed: int) -> None:
    """Before: "the sensor noise measured in its still stretches (18% of it) is 2.3e-4"."""
    est = noisevar.estimate(_calm_and_gusts(seed))
    v = est.diagnostics.verdict
    assert est.diagnostics.level_varies and est.still is not None, v
    assert "only bounds the noise from above" in v, v
    assert "sensor noise" not in v, v
    assert est.assumptions.get(UNSMOOTHED) is True


def test_white_noise_at_rest_keeps_its_r_to_use() -> None:
    """White noise, at rest but for a third of it on a running machine: the still R is
    the sensor's, said as the R to use."""
    rng = np.random.default_rng(3)
    z = rng.normal(size=12000)
    z[4000:8000] += 20.0 * np.sin(np.arange(4000) / 3.0)  # a machine running
    est = noisevar.estimate(z)
    assert est.still is not None
    assert "bounds the noise" not in est.diagnostics.verdict
    assert est.assumptions.get(UNSMOOTHED, True) is True

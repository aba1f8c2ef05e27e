"""A record whose level varies and whose still noise is coloured: the verdict quotes the R
to use (the still R), not the whole record's R as "its white part".

The Pololu MinIMU's accelerometer X (real_audit) read "the noise is coloured ...; R = 74,680
is its white part", while the R to use, `est.still`, was 3,688: the coloured branch came
before the level change, and the sentence users read named another R than the one to use
(issue 26 item 4).
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import signal

import noisevar


def _record(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    n = 8000
    z = signal.lfilter([1.0], [1.0, -0.5], rng.normal(size=n))  # AR(1) noise everywhere
    k = np.arange(n)
    for start in (1500, 5200):  # two bursts of motion: 15 % of the record
        burst = slice(start, start + 600)
        z[burst] += 40.0 * np.sin(2 * np.pi * k[burst] / 9.0) * rng.normal(1.0, 0.3, 600)
    return z


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_the_verdict_quotes_the_still_r(seed: int) -> None:
    est = noisevar.estimate(_record(seed))
    assert est.still is not None and est.still.variance < est.variance / 5
    v = est.diagnostics.verdict
    assert v.startswith("the noise level changes along the record")
    assert noisevar.format.eng(est.still.variance) in v
    assert "even there the noise is not white" in v


def _track(seed: int) -> np.ndarray:
    """A walker's position: a random walk that stops twice, with the receiver's noise."""
    rng = np.random.default_rng(seed)
    steps = rng.normal(0.0, 3.0, 3000)
    steps[800:1000] = 0.0  # standing still
    steps[2000:2150] = 0.0
    return np.cumsum(steps) + rng.normal(0.0, 0.1, 3000)  # the receiver's noise: 0.01


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_walk_that_stops_quotes_its_still_noise(seed: int) -> None:
    """GPS tracks (real_audit3): "a random walk ... R is not a noise level", with no word of
    the still R 5.3e-11 deg² that was the R to use."""
    est = noisevar.estimate(_track(seed))
    v = est.diagnostics.verdict
    assert v.startswith("the record behaves like a random walk")
    assert est.still is not None and 0.007 < est.still.variance < 0.013  # 0.1²
    assert noisevar.format.eng(est.still.variance) in v
    assert "the noise where it stood still, the R to use" in v


def test_a_quiet_level_above_r_is_never_quoted_as_the_quiet_one() -> None:
    """A model ship's temperature (held 1-degree values, spikes to 255 degC; real_audit4):
    "its quiet stretches (6%) give 214.1" against R = 42.2."""
    from noisevar.diagnostics.verdict import make_verdict

    est = noisevar.estimate(_record(0))  # its level varies
    diag = est.diagnostics
    quiet = diag.quiet_variance  # the level the verdict quotes (the profile's is on another
    v = make_verdict(diag, 0.4 * quiet, still_gap="too short")  # residual): above this R
    assert "no stretch of it is measurably quieter" in v
    assert "quiet stretches (" not in v


@pytest.mark.parametrize("seed", [0, 1])
def test_a_still_r_apart_leads_whether_or_not_pelt_split_the_record(seed: int) -> None:
    """Pololu's accelerometer Z less 3 samples (real_audit): PELT's marginal change point
    gone (one regime), the still R 13,159 against R 129,693, and the verdict read "the noise
    is coloured ...; R is its white part" where the R to use was the still R."""
    from dataclasses import replace

    from noisevar.diagnostics.verdict import make_verdict

    est = noisevar.estimate(_record(seed))
    d = est.diagnostics
    one = replace(
        d.level_profile, regimes=tuple(replace(r, still=True) for r in d.level_profile.regimes)
    )
    flat = replace(d, level_profile=one)
    assert not flat.level_varies
    v = make_verdict(
        flat, est.variance, est.core_variance, est.outlier_fraction, est.still.variance
    )
    assert v.startswith("the noise level changes along the record"), v
    assert noisevar.format.eng(est.still.variance) in v

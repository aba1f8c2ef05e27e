"""A "still" regime that is the quieter phase of continuous motion (issue 26).

A legged robot climbing stairs (gtsam's ``legged_staircase/imu.csv``, ~101 Hz) walks
throughout: its IMU carries the gait's 12 Hz oscillation everywhere, weaker on the flat than
on the stairs. The quieter phases were read as still regimes, and the verdict quoted "its
still stretches (53%) give 8.654, the R to use". Their noise carries the oscillation: their
level is an upper bound on the sensor's noise, not its level at rest, and the verdict, the
estimate's notes and the still R's own notes say so. A true still stretch (white noise)
keeps "the R to use". Seeded: white noise with an oscillation at 0.12 of the sample rate
throughout, three times stronger in the middle.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv
from noisevar.estimators.regimes import estimate_for

N = 6000


def _walking(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.arange(N)
    amp = np.where((t > 2000) & (t < 4500), 3.0, 1.0)
    return rng.normal(size=N) + amp * np.sin(2 * np.pi * 0.12 * t + rng.uniform(0, 6))


def _still_then_moving(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    z = rng.normal(size=N)
    z[2000:4500] += rng.normal(0, 3, 2500) + 40 * np.sin(np.arange(2500) / 300)
    return z


@pytest.mark.parametrize("seed", range(4))
def test_the_quieter_phase_of_a_gait_is_an_upper_bound(seed: int) -> None:
    est = nv.estimate(_walking(seed))
    v = est.verdict
    assert "the R to use" not in v and "oscillation at 0.12" in v, v
    if est.still is not None:  # kept, said to be an upper bound where users take it
        assert "upper bound on the sensor's noise" in v, v
        assert any("upper bound" in n for n in est.notes)
        assert any("upper bound" in n for n in estimate_for(est, "still").notes)


@pytest.mark.parametrize("seed", range(4))
def test_a_true_still_stretch_keeps_the_r_to_use(seed: int) -> None:
    est = nv.estimate(_still_then_moving(seed))
    assert est.still is not None
    assert "upper bound" not in est.verdict and "oscillation" not in est.verdict
    assert not any("upper bound" in n for n in estimate_for(est, "still").notes)

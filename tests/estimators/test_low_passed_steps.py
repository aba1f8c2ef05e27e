"""Level steps in low-passed noise are jumps, and low-passed noise alone has none (issue 26).

The step detector compared its third difference of window means with what white noise at
the residual's level gives. Noise low-passed by the sensor (lag-one correlation 0.8 and
up) wanders far more over a window: a fifth of a record of it was left out "around level
jumps", the fast-signal rule then dropped the flags, and true steps stayed in R as
outliers (AR(1) 0.9 with 20 steps of 1e4: R 9,794 against 0.060). Each block's own level
of the statistic now raises its threshold (``Above.raised``). On a record under 2,048
samples (a grid of fewer than 8 blocks) one factor read off the whole record raises every
level, and only lone steps are jumps: 23-33 % of AR(1) 0.8-0.98 noise of 500-2,000 samples
was left out, and two steps of 1e4 in 1,000 samples stayed in R (x2.7e5). (Two steps closer
than a step's response, 24 samples, are one run, no lone step: they stay in R, as before.)"""

from __future__ import annotations

import numpy as np
import pytest
from scipy.signal import lfilter

import noisevar as nv
from noisevar.numeric.blocks import runs_of

N = 20_000


def _ar1(a: float, seed: int = 1, n: int = N, k: int = 20) -> tuple[np.ndarray, np.ndarray]:
    rng = np.random.default_rng(seed)
    x = lfilter([1.0], [1.0, -a], rng.normal(size=n)) * np.sqrt(1.0 - a * a)
    edge = min(200, n // 10)
    at = np.sort(rng.choice(np.arange(edge, n - edge), k, replace=False))
    return x, at


def _with_steps(x: np.ndarray, at: np.ndarray, size: float) -> np.ndarray:
    steps = np.zeros(x.size)
    for i in at:
        steps[i:] += size
    return x + steps


@pytest.mark.parametrize("a", [0.8, 0.9, 0.98])
@pytest.mark.parametrize("size", [50.0, 1e4])
def test_steps_in_low_passed_noise_leave_r_as_it_was(a, size):
    x, at = _ar1(a)
    plain = nv.estimate(x)
    e = nv.estimate(_with_steps(x, at, size))
    lo, hi = plain.ci95
    assert lo <= e.variance <= hi, (e.variance, plain.variance)
    runs = runs_of(e.jumps) if e.jumps is not None else []
    assert all(any(a0 <= i <= b0 for a0, b0 in runs) for i in at)  # every step is a jump


@pytest.mark.parametrize("a", [0.8, 0.9, 0.95])
def test_low_passed_noise_alone_has_no_jumps(a):
    x, _ = _ar1(a)
    e = nv.estimate(x)
    left = 0 if e.jumps is None else int(e.jumps.sum())
    assert left < 0.01 * N, left
    assert not any("left out around level jumps" in s for s in e.notes)


def test_white_noise_keeps_every_step_and_the_same_r():
    rng = np.random.default_rng(2)
    x = rng.normal(size=N)
    at = np.sort(rng.choice(np.arange(200, N - 200), 20, replace=False))
    e = nv.estimate(_with_steps(x, at, 12.0))
    runs = runs_of(e.jumps)
    assert all(any(a0 <= i <= b0 for a0, b0 in runs) for i in at)
    assert abs(e.variance - 1.0) < 0.05


@pytest.mark.parametrize("n", [500, 1000, 1800])
@pytest.mark.parametrize("a", [0.8, 0.9, 0.98])
def test_short_low_passed_noise_alone_has_no_jumps(n, a):
    for seed in range(3):
        x, _ = _ar1(a, seed, n)
        e = nv.estimate(x)
        assert e.jumps is None or not e.jumps.any(), (seed, int(e.jumps.sum()))


@pytest.mark.parametrize("a", [0.8, 0.95])
def test_short_low_passed_noise_keeps_its_steps_out_of_r(a):
    for seed in range(3):
        x, _ = _ar1(a, seed, 1000, 2)
        plain = nv.estimate(x)
        e = nv.estimate(_with_steps(x, np.array([300, 650]), 1e4))
        lo, hi = plain.ci95
        assert lo <= e.variance <= hi, (seed, e.variance, plain.variance)


def test_short_white_noise_keeps_its_steps():
    rng = np.random.default_rng(4)
    x = rng.normal(size=1000)
    e = nv.estimate(_with_steps(x, np.array([300, 650]), 12.0))
    runs = runs_of(e.jumps)
    assert all(any(a0 <= i <= b0 for a0, b0 in runs) for i in (300, 650))
    assert abs(e.variance - 1.0) < 0.15


def test_short_random_walk_is_no_cluster_of_jumps():
    """A random walk under a little white noise (300 samples): its own wander, not jumps
    (48-134 samples were left out as jumps before)."""
    for seed in range(4):
        rng = np.random.default_rng(seed)
        walk = np.cumsum(rng.normal(size=300)) + 0.05 * rng.normal(size=300)
        e = nv.estimate(walk)
        assert e.jumps is None or not e.jumps.any(), (seed, int(e.jumps.sum()))


@pytest.mark.parametrize("seed", [16, 29])
def test_short_held_record_in_other_units_scales_exactly(seed):
    """Whole degrees held between changes, with spikes (a ship's temperature topic): in
    degF (x1.8 + 32) R is x3.24 exactly. Held blocks' D3 is 0, or rounding under the
    offset: it must not enter the record's own level (R moved 0.8-1.3 %)."""
    rng = np.random.default_rng(seed)
    t = np.round(20 + np.cumsum(rng.normal(0, 0.08, 900)))
    spikes = rng.choice(900, 3, replace=False)
    t[spikes] += rng.choice([-40, 40], 3)
    a, b = nv.estimate(t).variance, nv.estimate(1.8 * t + 32).variance
    assert b == pytest.approx(3.24 * a, rel=1e-9)

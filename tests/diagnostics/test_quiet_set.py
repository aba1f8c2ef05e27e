"""The quiet set on short records of motion and still stretches (issue 13's IMU target), and
its leave-one-out kurtosis: a tap in a still stretch is motion, heavy tails stay noise."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar import synth
from noisevar.diagnostics import diagnose

N_SHORT = 500


def _motion_then_still(rng: np.random.Generator) -> tuple[np.ndarray, np.ndarray, int]:
    """A burst of motion over the first 40 %, then still; a 4-sample tap in the still part."""
    k = np.arange(N_SHORT)
    noise = rng.standard_normal(N_SHORT)
    burst = 30.0 * rng.uniform(0.5, 2.0) * np.sin(2 * np.pi * k / 23.0)
    motion = np.where(k < 200, burst * np.exp(-(((k - 100) / 60.0) ** 2)), 0.0)
    tap = int(rng.integers(260, 480))
    z = 3.0 * np.sin(k / 500.0) + noise + motion
    z[tap : tap + 4] += rng.normal(0.0, 8.0, 4)
    return z, noise, tap


def test_a_tap_in_a_still_stretch_is_left_out_of_the_quiet_set():
    rng = np.random.default_rng(1301)
    runs, left_out, close = 100, 0, 0
    for _ in range(runs):
        z, noise, tap = _motion_then_still(rng)
        prof = diagnose(z).level_profile
        hit = (prof.start <= tap + 3) & (prof.stop > tap)  # blocks the tap falls in
        left_out += bool(not prof.quiet[hit].any())
        still = np.delete(noise[220:], np.arange(tap - 220, tap - 216))
        close += abs(prof.quiet_variance / np.var(still) - 1.0) <= 0.25
    assert left_out >= 0.85 * runs, left_out
    assert close >= 0.93 * runs, close


@pytest.mark.parametrize(("kind", "params"), [("student_t", {"dof": 5.0}), ("contaminated", {})])
def test_heavy_tails_stay_in_the_quiet_set(kind, params):
    runs, n = 30, 6000
    x = np.arange(n)
    draw = synth.noise(kind, n, rng=1302, runs=runs, **params)
    diags = [diagnose(r + 3.0 * np.sin(x / 500.0)) for r in draw.values]
    ratio = np.array([d.quiet_variance for d in diags]) / draw.values.var(axis=1)
    varies = np.mean([d.level_varies for d in diags])
    assert varies <= 0.1, varies
    assert np.median(ratio) >= 0.85, np.median(ratio)


def _handheld(seed: int, n: int = 2700) -> np.ndarray:
    """White noise (σ = 1) moved three times, knocked 12 times in between (a hand-held IMU).

    Each knock is a ring of 6-14 samples at 10-30 σ: inside one 32-sample block it leaves the
    block's median (so the block sits in a still regime) but not its mean square.
    """
    rng = np.random.default_rng(seed)
    z = rng.standard_normal(n)
    for a in (500, 1400, 2200):
        k = np.arange(int(rng.integers(150, 300)))
        z[a : a + k.size] += rng.uniform(20, 60) * np.sin(2 * np.pi * k / rng.uniform(20, 60))
    for _ in range(12):
        a, k = int(rng.integers(0, n - 40)), np.arange(int(rng.integers(6, 14)))
        ring = np.exp(-k / 4.0) * np.sin(2 * np.pi * k / rng.uniform(3, 8))
        z[a : a + k.size] += rng.uniform(10, 30) * ring
    return z


def test_knocks_in_still_stretches_stay_out_of_the_still_level():
    """YEI hand-held accelerometer (issue 26): knocks' tails must not widen the quiet test.

    The old seed (still blocks within 20x their median) let knocked blocks in, whose
    kurtosis then admitted more of them: still R up to 1.48x (4 of 16 runs above 1.25x).
    """
    from noisevar import estimate

    ratios = [e.still.variance for e in map(estimate, map(_handheld, range(20))) if e.still]
    assert len(ratios) >= 15
    assert max(ratios) < 1.15, ratios
    assert abs(np.mean(ratios) - 1.0) < 0.05, np.mean(ratios)

"""Solar stations' nights as the still R (issue 26; benchmarks/real_audit5.py §3), seeded.

Three kinds of night that had no right still R to use:

(a) a still night whose quiet blocks are cut into pieces under 64 samples (one-count
    spikes of a logger, MIDC's pyranometers), while PELT finds the nights still: the still R
    comes from the still regimes themselves, R's method on them (the spikes are outlying
    samples inside a still regime: in R, as in the whole record's R, and out of its core);
(b) staircase nights on a grid (BSRN's whole W/m²): each night's offset sits elsewhere in
    a step, so a night reads 1e-4 step² and another 0.5: regimes held on the grid are one
    still level, whose R is the rounding error lsb²/12 (§E3), also under a trend;
(c) a night at a logger's floor off any grid, drifting by the last stored digit (MIDC's
    direct normal): no still R of 1e-13, said (docs/algorithms.md §E3 *Held values*).
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv
from noisevar import synth
from noisevar.diagnostics.quantisation import second_difference_step
from noisevar.estimators.regimes import longest_still_stretch, why_no_still


def _sun(n: int, per_day: int = 1440) -> np.ndarray:
    k = np.arange(n) % per_day
    return np.clip(np.sin(np.pi * (k - 400) / 640), 0, None)


def _clouds(rng: np.random.Generator, n: int) -> np.ndarray:
    return 1 + 0.3 * np.convolve(rng.standard_normal(n), np.ones(15) / 15, "same")


SIGMA = 0.05


def spiky_nights(seed: int, n: int = 1440) -> tuple[np.ndarray, np.ndarray]:
    """(a) Night noise 0.05, 30 spikes of 1.0 in the nights, a cloudy day of 800; the
    record and the nights' errors (noise and spikes)."""
    rng = np.random.default_rng(seed)
    sun = _sun(n)
    c = 2.03 + 0.02 * np.sin(np.arange(n) / 90) + 800 * sun**1.5 * _clouds(rng, n)
    err = SIGMA * rng.standard_normal(n)
    night = np.flatnonzero(sun == 0)
    err[rng.choice(night[20:-20], 30, replace=False)] += 1.0
    return c + err, err[sun == 0]


def staircase_nights(seed: int, n_days: int = 10, sigma: float = 0.2) -> np.ndarray:
    """(b) Ten days on a grid of 1, night noise 0.2 step, each night at its own offset."""
    rng = np.random.default_rng(seed)
    n = n_days * 1440
    offset = np.repeat(rng.uniform(-3, 3, n_days + 1), 1440)[:n]
    c = offset + 800 * _sun(n) ** 1.5 * _clouds(rng, n)
    return np.round(c + sigma * rng.standard_normal(n))


def floor_nights(seed: int, n: int = 1440) -> np.ndarray:
    """(c) Nights at -0.4335 drifting by the sixth decimal, a continuous day of 900."""
    rng = np.random.default_rng(seed)
    k = np.arange(n)
    sun = _sun(n)
    floor = np.round(-0.4335 + 3e-6 * np.sin(k / 60) + 4e-7 * rng.standard_normal(n), 6)
    day = 900 * sun**1.5 * _clouds(rng, n) + 0.5 * rng.standard_normal(n)
    return np.where(sun > 0, floor + day, floor)


@pytest.mark.parametrize("seed", [0, 1, 3])
def test_spiky_nights_give_the_still_regimes_r(seed):
    z, err = spiky_nights(seed)
    est = nv.estimate(z)
    assert est.still is not None  # was: still stretches too short (pieces under 64)
    truth = float(np.var(err))  # the spikes in, as R counts them
    assert truth / 1.5 <= est.still.variance <= 1.5 * truth
    assert est.still.ci95[0] <= truth <= est.still.ci95[1]
    assert SIGMA**2 / 1.5 <= est.still.core_variance <= 1.5 * SIGMA**2  # and out
    back = nv.estimate(z[::-1]).still
    assert back is not None and est.still.ci95[0] <= back.variance <= est.still.ci95[1]


@pytest.mark.parametrize("seed", [0, 1, 2, 3])
def test_staircase_nights_on_a_grid_are_one_still_level(seed):
    z = staircase_nights(seed)
    est = nv.estimate(z)
    assert est.diagnostics.lsb == pytest.approx(1.0)
    assert est.still is not None  # was: no still regime (each night its own level)
    truth = 0.2**2 + 1.0 / 12.0  # σ² + lsb²/12 (§E3)
    assert truth / 1.5 <= est.still.variance <= 1.5 * truth


@pytest.mark.parametrize("seed", [0, 1])
def test_staircase_nights_keep_their_still_r_under_a_trend_and_an_offset(seed):
    z = staircase_nights(seed)
    base = nv.estimate(z).still
    s = float(np.std(z))
    for moved in (z + np.linspace(0.0, 1e3 * s, z.size), z + 1e4 * s):
        again = nv.estimate(moved)
        assert again.diagnostics.lsb == pytest.approx(1.0)  # the grid moves with the trend
        assert again.still is not None
        assert base.ci95[0] <= again.still.variance <= base.ci95[1]


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_a_floor_held_to_the_last_digit_has_no_still_r(seed):
    z = floor_nights(seed)
    est = nv.estimate(z)
    assert est.diagnostics.lsb is None
    assert est.still is None  # was: 1.6e-13 to 3e-13, the sixth decimal's rounding
    gap = why_no_still(est)
    assert gap is not None and "last stored digit" in gap
    assert "last stored digit" in est.diagnostics.verdict
    for moved in (z[::-1], z + np.linspace(0.0, 1e3 * np.std(z), z.size)):
        assert nv.estimate(moved).still is None


def test_second_differences_keep_the_grid_under_a_trend_and_an_offset():
    rng = np.random.default_rng(5)
    z = 0.1 * np.round(np.cumsum(rng.normal(0, 0.3, 3000)))
    ramp = np.linspace(0.0, 5e4, z.size)
    for x, step in ((z, 0.1), (z + ramp, 0.1), (z + 1e6, 0.1), (-1e3 * z, 100.0)):
        assert second_difference_step(x) == pytest.approx(step, rel=1e-6)
    assert second_difference_step(z + 1e-3 * rng.standard_normal(z.size)) is None
    assert second_difference_step(3.0 + 0.37 * np.arange(50)) == 0.0  # a line: no step


def test_a_fit_on_the_still_regimes_takes_one_of_them():
    """The fits' still stretch follows the same rule as the still R: a night of the still
    regimes when the quiet blocks are in pieces (was: no still stretch, said)."""
    z, _ = spiky_nights(0)
    est = nv.estimate(z)
    s = longest_still_stretch(z, need=200, est=est)
    night = _sun(z.size) == 0
    assert s.stop - s.start >= 200 and night[s.start : s.stop].all()


def test_a_record_held_on_its_grid_is_called_quantised_not_heavy_tailed():
    """Noise of 0.3 step on a grid (benchmarks/real_noise.py's family): its held regimes are
    one still level now, so its level does not vary; its tails are the rounding's."""
    clean = nv.generate("noise-step", n=6000).clean
    d = synth.noise("gauss", 6000, 3, runs=3, std=5.0)
    z, _ = synth.quantise(clean + d.values, 5.0 / 0.3, d.variance, clean=clean)
    for row in z:
        verdict = nv.estimate(row).diagnostics.verdict
        assert verdict.startswith("white noise under half a step on a grid of step 16.67")
        assert "heavy-tailed" not in verdict

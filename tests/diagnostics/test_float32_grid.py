"""Counts scaled into float32 keep their grid (GOES's X-ray flux, real_audit6)."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.diagnostics.quantisation import second_difference_step


def _counts(seed: int, n: int = 601) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    return np.round(200 + 30 * np.sin(t / 80) + 2.5 * rng.normal(size=n)) * 8


@pytest.mark.parametrize(("seed", "scale"), [(0, 1.234e-9), (1, 3.3e-3), (2, 0.77)])
def test_float32_counts_keep_the_grid_and_the_verdict(seed, scale) -> None:
    c = _counts(seed)
    flux = (c * scale).astype(np.float32).astype(np.float64)
    a, b = noisevar.estimate(c), noisevar.estimate(flux)
    # was: 1.1e-13 (float32's own spacing) for 1.234e-9, or None: "white Gaussian noise"
    assert b.diagnostics.lsb == pytest.approx(8 * scale, rel=1e-5)
    assert b.variance == pytest.approx(a.variance * scale**2, rel=1e-5)
    assert b.verdict.split(" on a grid")[0] == a.verdict.split(" on a grid")[0]
    assert "on a grid of step" in b.verdict


def test_large_counts_in_float64_keep_a_step_of_one() -> None:
    rng = np.random.default_rng(3)
    z = np.round(1e6 + np.cumsum(rng.normal(size=3000)) + rng.normal(size=3000) * 0.4)
    assert second_difference_step(z) == 1.0


def test_float32_noise_off_any_grid_is_not_given_one() -> None:
    rng = np.random.default_rng(4)
    z = (rng.normal(size=4000) * 1e-3 + 0.5).astype(np.float32).astype(np.float64)
    step = second_difference_step(z)
    assert step is None or step < 1e-6  # float32's spacing at most, never a coarse grid


@pytest.mark.parametrize("move", ["scale", "offset", "trend"])
def test_float32_counts_keep_the_grid_when_scaled_or_moved_after(move) -> None:
    """GOES's flux x1e3, + an offset, + a trend (real_audit6's transforms): float64 values
    that carry float32's rounding read 'white Gaussian noise' against 'on a grid'."""
    flux = (_counts(5) * 4.7e-10).astype(np.float32).astype(np.float64)
    s = float(np.std(flux))
    moved = {"scale": 1e3 * flux, "offset": flux + 10 * float(np.max(flux)),
             "trend": flux + np.linspace(0.0, 1e3 * s, flux.size)}[move]  # fmt: skip
    k = 1e3 if move == "scale" else 1.0
    assert noisevar.estimate(moved).diagnostics.lsb == pytest.approx(8 * 4.7e-10 * k, rel=1e-4)


@pytest.mark.parametrize("seed", [5, 6, 7])
def test_float32_counts_keep_the_grid_under_an_offset_far_above_them(seed) -> None:
    """An offset of 1e4 standard deviations (verdict_invariance's) leaves float32's rounding
    as it was, far under float32's rounding at the moved values, which the grid was read
    at: GOES's flux lost its grid there ("white Gaussian noise", was "on a grid")."""
    flux = (_counts(seed) * 4.7e-10).astype(np.float32).astype(np.float64)
    moved = flux + 1e4 * float(np.std(flux))
    a, b = noisevar.estimate(flux), noisevar.estimate(moved)
    assert b.diagnostics.lsb == pytest.approx(a.diagnostics.lsb, rel=1e-6)
    assert b.verdict.split(":")[0] == a.verdict.split(":")[0], (a.verdict, b.verdict)


@pytest.mark.parametrize("move", [0.0, 1.0, -470.0, 9.1e5])
def test_a_float32_decimal_grid_keeps_its_step_under_any_offset(move) -> None:
    """An altitude on a 0.2 m grid written through float32 (Garmin's TCX: 473.7999878),
    moved by an offset after: the step is 0.2 at every offset (audit 11: it was found at
    +0 and +1 but lost at -470 and +9.1e5, so the still level came and went)."""
    rng = np.random.default_rng(7)
    k = 2415 + np.cumsum(rng.integers(-1, 2, size=400))  # ramps leave float32's rounding
    alt = (0.2 * k).astype(np.float32).astype(np.float64)
    step = second_difference_step(alt + move)
    assert step == pytest.approx(0.2, rel=1e-3)

"""A grid found under an offset and a trend (issue 26; real_audit19's AE plate, volts on an
ADC grid of 3.045e-6 written with 10 significant digits, lost its grid at +25.5 V and under
a trend; real_audit16's RTKLIB heights, 0.1 mm, lost theirs at +1.4e4 m)."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.diagnostics.quantisation import second_difference_step

#: An AE recorder's volts per count (real_audit19's plate): not a round number.
VOLTS = 3.044528590326666e-06


def _transient(seed: int, n: int = 20_000) -> np.ndarray:
    """A decaying burst of up to 4000 counts and noise of 0.3 count, in volts written
    with 10 significant digits (a CSV export): each sample's rounding follows its size."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    s = 4000 * VOLTS * np.sin(2 * np.pi * t / 500) * np.exp(-t / 3000)
    counts = np.rint(s / VOLTS + rng.normal(0.0, 0.3, n))
    return np.array([float(f"{v:.10g}") for v in counts * VOLTS])


def _heights(seed: int, n: int = 2400) -> np.ndarray:
    """A wandering height written in 0.1 mm, with ten jumps of metres (RTKLIB's up)."""
    rng = np.random.default_rng(seed)
    s = np.cumsum(rng.normal(0.0, 0.3, n))
    s[rng.integers(0, n, 10)] += rng.normal(0.0, 5.0, 10)
    return np.round(s, 4)


def _moves(z: np.ndarray, step: float) -> dict[str, np.ndarray]:
    """The audits' offset (1e4 standard deviations) and a trend of 0.37 step a sample."""
    return {"offset": z + 1e4 * np.std(z), "trend": z + 0.37 * step * np.arange(z.size)}


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_written_volts_keep_their_grid_under_an_offset(seed) -> None:
    """Was: None at +1e4 std (the 10-digit rounding of values near 0 sat above float64's
    rounding of the moved values, and float32's covered the step)."""
    z = _transient(seed)
    step = second_difference_step(z)
    assert step == pytest.approx(VOLTS, rel=1e-6)
    for moved in _moves(z, VOLTS).values():
        assert second_difference_step(moved) == pytest.approx(step, rel=1e-6)


@pytest.mark.parametrize("seed", [0, 1, 2])
def test_heights_keep_their_grid_under_an_offset(seed) -> None:
    """Was: None at +1e4 std and at +1.37e4 m (the least second difference carried the
    moved values' float rounding, and 1e5 steps read with it fell 3e-3 steps off)."""
    z = _heights(seed)
    step = second_difference_step(z)
    assert step == pytest.approx(1e-4, rel=1e-6)
    for moved in [*_moves(z, 1e-4).values(), z + 1.37e4]:
        assert second_difference_step(moved) == pytest.approx(step, rel=1e-6)


def test_r_its_grid_and_the_finding_do_not_move() -> None:
    """Was (main): under the offset R x0.85 outside its ci95, no grid, and "the noise level
    changes along the record" for "white noise on a grid"."""
    z = _transient(0)
    a = noisevar.estimate(z)
    lo, hi = a.ci95
    for name, moved in _moves(z, VOLTS).items():
        b = noisevar.estimate(moved)
        assert lo <= b.variance <= hi, name
        assert b.diagnostics.lsb == pytest.approx(a.diagnostics.lsb, rel=1e-6), name
        assert b.verdict.split(":")[0] == a.verdict.split(":")[0], name


def test_subnormal_records_read_no_step_without_error() -> None:
    """A record scaled to 1e-310 (subnormal doubles) has no measured rounding (tol 0): the
    least-squares step read divided by it (hypothesis found it in CI's float-range test)."""
    rng = np.random.default_rng(0)
    z = (np.cumsum(rng.normal(0, 0.05, 240)) + rng.normal(0, 1, 240)) * 1e-310
    with np.errstate(divide="raise", over="raise", invalid="raise"):
        second_difference_step(z)

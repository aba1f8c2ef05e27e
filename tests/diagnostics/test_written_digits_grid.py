"""A grid under the rounding of the digits the samples are written with (audit 11: Polar
M400's altitude, a 0.1524 m grid written in mm, read on its grid at +1000 m only)."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.diagnostics.quantisation import second_difference_step, written_resolution


def _half_feet(seed: int, n: int = 3000) -> np.ndarray:
    """A barometric altitude on a half-foot grid, each value held for two samples (as
    Polar's), written in mm (about 100 m)."""
    rng = np.random.default_rng(seed)
    k = 656 + np.cumsum(rng.integers(-1, 2, size=n // 2))
    return np.round(np.repeat(0.1524 * k, 2), 3)


@pytest.mark.parametrize("seed", [0, 1, 2])
@pytest.mark.parametrize("move", [0.0, 1000.0, -900.0, 0.123456, 9.1e5])
def test_a_grid_written_in_mm_is_read_at_every_offset(seed, move) -> None:
    """Was: None at +0, -900 and +9.1e5; 0.1524 at +1000 (float32's rounding, which
    scales with the values, took the mm for it there)."""
    step = second_difference_step(_half_feet(seed) + move)
    assert step == pytest.approx(0.1524, rel=1e-3)


@pytest.mark.parametrize("seed", [3, 4])
def test_r_and_the_verdict_do_not_move_under_an_offset(seed) -> None:
    """Was: R x0.75 under +1000 m (outside its ci95) and "an oscillation at 0.50 of the
    sample rate ... a vibration" at +0: a value flipping between two grid steps."""
    z = _half_feet(seed)
    a, b = noisevar.estimate(z), noisevar.estimate(z + 1000.0)
    assert b.variance == pytest.approx(a.variance, rel=1e-6)
    assert a.verdict.split(":")[0] == b.verdict.split(":")[0]
    assert "vibration" not in a.verdict
    assert a.diagnostics.lsb == pytest.approx(0.1524, rel=1e-3)


def test_the_written_resolution_does_not_see_an_offset_or_a_trend() -> None:
    z = _half_feet(5)
    ramp = np.linspace(0.0, 1e3 * float(np.std(z)), z.size)
    moved = [z, z + 1000.0, z - 900.0, z + ramp]
    assert [written_resolution(x) for x in moved] == [0.001] * 4


def test_subnormal_values_end_the_search_for_written_digits() -> None:
    # a record of subnormal values has a rounding tolerance of 0 and 10**k reached 0: the
    # search for the written resolution never ended (hypothesis's float-range records)
    from noisevar.diagnostics.quantisation import written_resolution

    z = np.array([0.0, 5e-324, 0.0, 1e-323, 0.0, 2e-323] * 30)
    assert written_resolution(z) is None

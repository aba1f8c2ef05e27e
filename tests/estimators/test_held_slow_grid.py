"""A slow signal on a coarse grid with noise far under the step (benchmarks/real_audit19.py:
a USGS pH record on a 0.1 grid, changing in 1.9 % of its samples).

Its R leaves the rounding error out (§E3: too slow to tell from a bias): the verdict said R
"includes the rounding error lsb²/12" at 15x under it. Held values whose residual had no
variation left to diagnose were answered R 1.1e-7 (7,500x under lsb²/12) with no verdict,
where the same record crossing one more step was refused as held.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar as nv

LSB = 0.1


def slow_on_grid(amp: float, period: float, seed: int, n: int = 6000) -> np.ndarray:
    """A sine of ``amp`` around 7.58 over ``period`` samples, noise 0.001, on a 0.1 grid."""
    k = np.arange(n)
    rng = np.random.default_rng(seed)
    return LSB * np.round((7.58 + amp * np.sin(2 * np.pi * k / period)
                           + 0.001 * rng.standard_normal(n)) / LSB)  # fmt: skip


@pytest.mark.parametrize("seed", [0, 1])
def test_r_under_the_rounding_error_says_it_leaves_it_out(seed):
    est = nv.estimate(slow_on_grid(0.07, 1500, seed))
    q = LSB * LSB / 12
    assert est.variance < q
    assert "includes the rounding error" not in est.verdict
    assert "is under the rounding error lsb²/12" in est.verdict
    assert nv.format.eng(est.variance + q) in est.verdict  # R + lsb²/12, the filter's


@pytest.mark.parametrize("seed", [0, 1])
def test_held_values_with_a_degenerate_residual_are_refused_as_held(seed):
    z = slow_on_grid(0.09, 3000, seed)
    for record in (z, np.vstack([z, slow_on_grid(0.09, 3000, seed + 2)])):  # 1-D and 2-D
        with pytest.raises(nv.NoisevarError, match=r"held on a grid of step 0\.1") as exc:
            nv.estimate(record)
        assert "use R = lsb²/12 = 0.0008333" in str(exc.value)
    white = np.random.default_rng(seed).normal(size=(2, 3000))  # not held: answered
    assert all(e.diagnostics is not None for e in nv.estimate(white))

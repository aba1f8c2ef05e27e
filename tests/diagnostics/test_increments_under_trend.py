"""A linear trend adds a constant to every first difference: the increments' test reads none
of it (spoofing's ADS-B positions read a random walk under one, real_audit9)."""

from __future__ import annotations

import numpy as np

import noisevar
from noisevar.diagnostics.sums import _untouched


def _jumps(seed: int, n: int = 20_000) -> np.ndarray:
    """White noise of std 1e-3 on a slow curve, and 27 level jumps of 1."""
    rng = np.random.default_rng(seed)
    t = np.arange(n)
    steps = np.zeros(n)
    steps[np.sort(rng.choice(np.arange(500, n - 500), 27, replace=False))] = 1.0
    return 1e-9 * (t - n / 2) ** 2 + 1e-3 * rng.normal(size=n) + np.cumsum(steps)


def test_a_trend_leaves_the_jumps_out_of_the_increments() -> None:
    for seed in (3, 4):
        z = _jumps(seed)
        ramp = np.linspace(0.0, 1e3 * float(np.std(z)), z.size)
        base, moved = noisevar.estimate(z), noisevar.estimate(z + ramp)
        assert base.diagnostics.identifiable
        # was: "the record behaves like a random walk (its first difference is white)":
        # the ramp's slope (0.4 a sample) set the robust spread the jumps are judged by
        assert moved.diagnostics.identifiable, moved.verdict
        assert moved.verdict.split(":")[0] == base.verdict.split(":")[0]


def test_the_kept_increments_do_not_move_with_a_constant() -> None:
    rng = np.random.default_rng(5)
    dz = rng.normal(size=400)
    dz[[50, 200]] = 30.0
    exclude = np.zeros(dz.size + 1, dtype=bool)
    exclude[[50, 51, 200, 201]] = True
    keep = _untouched(exclude, 0, dz)
    assert not keep[[50, 200]].any()
    for c in (5.0, -40.0, 1e4):
        assert np.array_equal(_untouched(exclude, 0, dz + c), keep)

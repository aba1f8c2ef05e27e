"""The R to use on the still stretches that both block grids find still (issue 26, §E1)."""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.diagnostics import on_both_grids
from noisevar.estimators import estimate_chunked


def _rests(seed: int) -> np.ndarray:
    """White noise (σ = 1) with five rests and four bursts of motion, of random lengths."""
    rng = np.random.default_rng(seed)
    parts = []
    for i in range(9):
        m = int(rng.integers(150, 700))
        noise = rng.normal(0.0, 1.0, m)
        if i % 2:
            noise += rng.uniform(5, 40) * np.sin(np.arange(m) / rng.uniform(2, 6))
        parts.append(noise)
    return np.concatenate(parts)


def test_the_intersection_of_the_two_grids_stretches():
    # the backward stretches are in the reversed record's indices: (0, 30) is (70, 100)
    assert on_both_grids([(0, 40), (60, 100)], [(0, 30), (50, 90)], 100) == [
        (10, 40),
        (70, 100),
    ]
    assert on_both_grids([(0, 50)], [(0, 50)], 100) == []


@pytest.mark.parametrize("seed", range(6))
def test_the_r_to_use_reads_the_same_backwards(seed):
    # rests between bursts: each rest's edge blocks fall differently on the blocks laid
    # from the start and from the end; on one grid alone the reversed record's R to use
    # moved by -15 % to +4 % (20 of 20 seeded records differed), now by under 1e-9
    z = _rests(seed)
    fwd, bwd = noisevar.estimate(z), noisevar.estimate(z[::-1])
    assert fwd.still is not None and bwd.still is not None
    assert bwd.still.variance == pytest.approx(fwd.still.variance, rel=1e-9)
    assert fwd.still.variance == pytest.approx(1.0, rel=0.25)


def test_the_streamed_r_to_use_reads_both_grids_with_the_same_numbers():
    # the chunked engine reads the record backwards in chunks for the second grid
    z = np.concatenate([_rests(s) for s in range(10, 14)])
    one = noisevar.estimate(z)
    many = estimate_chunked(lambda a, b: z[max(a, 0) : b].copy(), z.size, chunk=4096)
    np.testing.assert_allclose(many.still.variance, one.still.variance, rtol=1e-9)
    np.testing.assert_allclose(many.still.ci95, one.still.ci95, rtol=1e-9)

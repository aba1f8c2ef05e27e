"""The trimming's compiled block screens: the NumPy references' flags and levels, bit for bit."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.estimators.auto import _levels
from noisevar.numeric import blocks


def _grid(rng: np.random.Generator) -> _levels.Grids:
    m = int(rng.integers(16, 5000))
    block = int(rng.choice([256, 16, 17, 64, 33])) if m >= 512 else max(min(m // 2, 64), 16)
    after = int(rng.integers(0, 1000)) if rng.random() < 0.7 else 0
    return _levels.Grids.make(m, min(block, m), after)


@pytest.mark.parametrize("seed", range(40))
def test_screened_block_medians_flag_what_the_medians_flag(seed):
    """Medians taken only where a square may exceed them: the flags of every median."""
    rng = np.random.default_rng(seed)
    for kind in range(6):
        g = _grid(rng)
        x = rng.normal(size=g.m)
        if kind == 1:  # quantised: ties at the median
            x = np.round(x * 2) / 2
        if kind == 2:  # spikes
            x[rng.integers(0, g.m, 5)] *= 30
        if kind == 3:  # mostly held: a median of 0
            x = np.where(rng.random(g.m) < 0.6, 0.0, x)
        if kind == 4:  # a change of level
            x[: g.m // 2] *= 10
        sq = x * x
        if kind == 5:
            sq[rng.integers(0, g.m, 3)] = -0.0
        scale = float(rng.choice([25 / 0.4549364231195724, 12.25 / 0.4549364231195724, 1.0]))
        floors = None
        if seed % 2:
            floors = (rng.random(g.nb) * rng.choice([0, 0.1, 1.0]), rng.random(g.nbb) * 0.1)
        fwd, bwd = _levels.medians(sq, g)
        if floors is not None:
            fwd, bwd = np.maximum(fwd, floors[0]), np.maximum(bwd, floors[1])
        ref = _levels.above_own(sq, fwd * scale, bwd * scale, g)
        assert np.array_equal(_levels.above_medians(sq, g, scale, floors), ref)


def test_few_block_medians_are_taken_on_white_noise():
    rng = np.random.default_rng(5)
    sq = rng.normal(size=256 * 1000) ** 2
    need = blocks.medians_needed(sq, 256, 1000, 25 / 0.4549364231195724)
    assert need is not None and need.mean() < 0.02


@pytest.mark.parametrize("seed", range(20))
def test_compiled_rounding_floors_are_numpys(seed):
    rng = np.random.default_rng(100 + seed)
    for _ in range(10):
        g = _grid(rng)
        z = rng.normal(size=g.m) * 10.0 ** rng.uniform(-150, 150)
        if seed % 3 == 0:
            z[rng.integers(0, g.m, 10)] = -0.0
        a = np.abs(z)
        fwd = blocks.block_maxima(a, g.block, g.nb)
        bwd = blocks.block_maxima(g.back(a), g.block, g.nbb)
        assert blocks.abs_block_maxima(z, g.block, g.nb).tobytes() == fwd.tobytes()
        got = blocks.abs_block_maxima(z, g.block, g.nbb, g.q, back=True)
        assert got.tobytes() == bwd.tobytes()

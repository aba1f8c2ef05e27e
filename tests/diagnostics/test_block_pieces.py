"""The diagnostics' block pieces taken many blocks at once equal the loop over blocks."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from noisevar.diagnostics import plan
from noisevar.numeric.blocks import row_medians


@pytest.mark.parametrize(
    ("m", "size", "s0", "length", "holes"),
    [
        (10_000, 256, 0, 10_000, 0),  # a whole record
        (10_000, 256, 1_000, 3_000, 0),  # a chunk: partial blocks at both ends
        (10_000, 255, 37, 9_963, 5),  # odd blocks, some with left-out slots
        (300_000, 70_000, 12_345, 287_655, 3),  # every second slot enters the median
    ],
)
def test_whole_blocks_at_once_equal_the_loop(m, size, s0, length, holes, monkeypatch):
    rng = np.random.default_rng(size + s0)
    e = (
        rng.standard_t(4, length)
        * np.repeat(rng.uniform(0.5, 2.0, length // 100 + 1), 100)[:length]
    )
    e[rng.integers(0, length, 50)] = 0.0
    keep = np.ones(length, dtype=bool)
    for at in rng.integers(0, length - 30, holes):
        keep[at : at + 30] = False
    grid = plan.Grid(m, size)
    fast = plan.block_pieces(grid, s0, e, keep, 0.37)
    monkeypatch.setattr(plan, "_whole_pieces", lambda *a: {})
    slow = plan.block_pieces(grid, s0, e, keep, 0.37)
    assert list(fast) == list(slow)  # the same blocks, in the same order
    for b in slow:
        f, s = dataclasses.asdict(fast[b]), dataclasses.asdict(slow[b])
        for name in ("values",):
            assert [v.tolist() for v in f.pop(name)] == [v.tolist() for v in s.pop(name)]
        assert f == s, b


@pytest.mark.parametrize("cols", [1, 2, 7, 256])
def test_row_medians_equal_numpy(cols):
    v = np.random.default_rng(cols).normal(size=(9, cols)) ** 2
    assert np.array_equal(row_medians(v), np.median(v, axis=1))

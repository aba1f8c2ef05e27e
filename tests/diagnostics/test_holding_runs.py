"""The still stretches on both grids (or either) read off the ranges' ends: the runs of the
per-sample count they replace."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.diagnostics import profile


def _reference(forward, backward, n, least):
    """The count of grids holding each sample, then its runs (the code before)."""
    mine = np.zeros(n + 1, dtype=np.int8)
    for a, b in forward:
        mine[a] += 1
        mine[b] -= 1
    for a, b in backward:
        mine[n - b] += 1
        mine[n - a] -= 1
    mask = np.cumsum(mine[:n]) >= least
    edges = np.flatnonzero(np.diff(np.r_[0, mask.view(np.int8), 0]))
    return [(int(a), int(b)) for a, b in zip(edges[::2], edges[1::2], strict=True)]


def _ranges(rng, n):
    cuts = np.sort(
        rng.choice(
            np.arange(n + 1), size=2 * min(int(rng.integers(0, 6)), (n + 1) // 2), replace=False
        )
    )
    if rng.random() < 0.3 and cuts.size:
        cuts[0], cuts[-1] = 0, n  # touching the record's ends
    return [(int(a), int(b)) for a, b in zip(cuts[::2], cuts[1::2], strict=True)]


@pytest.mark.parametrize("seed", range(30))
def test_runs_from_the_ends_are_the_count_runs(seed):
    rng = np.random.default_rng(seed)
    for _ in range(50):
        n = int(rng.integers(1, 3000))
        fwd, bwd = _ranges(rng, n), _ranges(rng, n)
        both = profile.on_both_grids(fwd, bwd, n)
        either = profile.on_either_grid(fwd, bwd, n)
        assert both == _reference(fwd, bwd, n, 2)
        assert either == _reference(fwd, bwd, n, 1)
        assert profile._holding_runs(fwd, bwd, n, 1) == either

"""The quiet blocks' whiteness-window positions, read run by run: the positions the residual
slots of every position gave."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.diagnostics import _in_blocks, _residual_slots
from noisevar.diagnostics.plan import make_plan


def _reference(plan, runs, ids):
    slots = [np.arange(lo, lo + k) if lo >= 0 else np.full(k, -1) for lo, k in runs]
    white = np.concatenate(slots) if slots else np.zeros(0, dtype=int)
    s = _residual_slots(plan, white)
    return np.isin(np.where(s >= 0, s // plan.profile.size, -1), ids)


@pytest.mark.parametrize("seed", range(25))
def test_quiet_positions_run_by_run_are_the_slots(seed):
    rng = np.random.default_rng(seed)
    n = int(rng.integers(200, 60_000))
    cuts = np.sort(rng.choice(np.arange(1, n), size=int(rng.integers(0, 5)), replace=False))
    bounds = [0, *cuts.tolist(), n]
    segments = tuple((a, b) for a, b in zip(bounds, bounds[1:], strict=False) if b > a)
    plan = make_plan(n, segments, np.zeros(0))
    top = max(plan.profile.count, 1)
    runs, pos = [], 0
    for _ in range(int(rng.integers(1, 30))):
        if rng.random() < 0.2:
            runs.append((-1, int(rng.integers(1, 50))))  # a separator
        else:
            pos += int(rng.integers(0, 3000))
            k = int(rng.integers(1, 4000))
            runs.append((pos, k))
            pos += k
    ids = np.sort(rng.choice(np.arange(top), size=int(rng.integers(0, top + 1)), replace=False))
    assert np.array_equal(_in_blocks(plan, runs, ids), _reference(plan, runs, ids))

"""One first clause for every level that changes, whatever its quiet share (issue 26).

The kind of change (no stretch quiet, none quieter than R, mostly motion, a quiet level to
use, motion leaking through) rests on the quiet set's share and level, which the block
grid's phase moves: SURFRAD's wind less 0-3 samples read 51, 38, 47, 43 % quiet and its
first clause flipped at half; MIDC's CHP1 temperature read a quiet set above R, then none.
The first clause says the level changes; the kind comes after it.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar.diagnostics.verdict import CHANGES


def _still_then_moving(still: float, seed: int, n: int = 2000) -> np.ndarray:
    rng = np.random.default_rng(seed)
    k = np.arange(n)
    move = (k >= int(still * n)).astype(float)
    return rng.normal(0, 0.1, n) + move * (2 * np.sin(k / 3.0) + rng.normal(0, 0.5, n))


@pytest.mark.parametrize("seed", [0, 1])
def test_the_first_clause_does_not_hang_on_the_quiet_share(seed: int) -> None:
    firsts = set()
    for still in (0.3, 0.45, 0.55, 0.7):
        r = noisevar.estimate(_still_then_moving(still, seed))
        assert r.diagnostics.level_varies
        firsts.add(r.diagnostics.verdict.split(":")[0])
    assert firsts == {CHANGES}, firsts


def test_no_quiet_stretch_has_the_same_first_clause() -> None:
    rng = np.random.default_rng(6)  # white noise of a log-normal level, every 50 samples
    x = rng.normal(size=1000) * np.exp(1.5 * rng.normal(size=20).repeat(50))
    d = noisevar.estimate(x).diagnostics
    assert d.level_varies and not d.level_profile.any_quiet
    assert d.verdict.split(":")[0] == CHANGES, d.verdict
    assert "no stretch of it is quiet" in d.verdict

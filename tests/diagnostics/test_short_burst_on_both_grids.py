"""A burst shorter than half a block is a regime of motion on both block grids or on
neither: the level and the R to use do not move when the record is reversed (issue 26
class 4, drop15).

UCR's InternalBleeding16 (``benchmarks/real_audit14.py``) has a 12-sample anomaly in a
smooth record: the smoother's span spreads it over about 20 residuals, which lift the
median of the one 38-sample block that holds it whole (82x, reversed) and of neither
block that shares it (2.8x and 3.1x, forwards). It was one level forwards (R to use R,
0.0479) and two regimes reversed (the quiet level, x0.134). A regime of motion shorter
than ``MOTION_RUN`` blocks is now kept only where the other grid finds it too
(docs/algorithms.md §E1 *Regimes*). Reversal swaps the two grids, so it no longer moves
the level; dropping leading samples moves the record's grid and not the reversed one, so a
burst found whole on the reversed grid is still a regime at some phases only (seeds 2-5
below: 3 of 32 records move with 1-3 dropped, 19 of 32 moved reversed or dropped before).
A short regime of motion is now read on the grid with a block edge at the burst's middle,
which the burst places and no drop moves (``diagnostics/split_grid.py``, drop16).
"""

from __future__ import annotations

import numpy as np

import noisevar
from noisevar.estimators.regimes import why_no_still


def burst_record(seed: int, at: int, n: int = 4000, k: int = 14) -> np.ndarray:
    """A smooth periodic signal (period 90 samples) in white noise of σ 0.1, with ``k``
    samples from ``at`` given noise of σ 3 on top: a short glitch burst."""
    rng = np.random.default_rng(seed)
    phase = 2 * np.pi * np.arange(n) / 90.0
    z = rng.normal(scale=0.1, size=n) + 20.0 * np.sin(phase) + 6.0 * np.sin(2 * phase + 1)
    z[at : at + k] += rng.normal(scale=3.0, size=k)
    return z


def _to_use(z: np.ndarray) -> noisevar.VarianceEstimate | None:
    return use_of(noisevar.estimate(z))


def use_of(est: noisevar.VarianceEstimate) -> noisevar.VarianceEstimate | None:
    return None if why_no_still(est) else (est if est.still is None else est.still)


# on main, 8 of these 16 were one level forwards and two regimes reversed
CASES = [(seed, at) for seed in (0, 1) for at in range(2000, 2032, 4)]


def test_a_short_burst_is_a_regime_on_both_grids_or_neither() -> None:
    moved = {}
    for case in CASES:
        z = burst_record(*case)
        varies = noisevar.estimate(z).diagnostics.level_varies
        if noisevar.estimate(z[::-1]).diagnostics.level_varies != varies:
            moved[case] = varies
    assert not moved, moved


def test_the_r_to_use_of_a_short_burst_stays_inside_its_interval() -> None:
    bad = {}
    for case in CASES:
        z = burst_record(*case)
        base = _to_use(z)
        lo, hi = base.ci95
        use = _to_use(z[::-1])
        if use is None or not lo <= use.variance <= hi:
            bad[case] = None if use is None else use.variance / base.variance
    assert not bad, bad


# on main (both grids), 4 of these 16 moved with 1-3 leading samples dropped: the record's
# grid moves with the drop and the reversed grid does not (drop16)
DROPPED = [(seed, at) for seed in (0, 2) for at in range(2000, 2032, 4)]


def test_a_short_burst_does_not_move_with_dropped_samples() -> None:
    moved = {}
    for case in DROPPED:
        z = burst_record(*case)
        est = noisevar.estimate(z)
        base = use_of(est)
        lo, hi = base.ci95
        for d in (1, 2, 3):
            cut = noisevar.estimate(z[d:])
            use = use_of(cut)
            if cut.diagnostics.level_varies != est.diagnostics.level_varies or use is None:
                moved[case, d] = None if use is None else use.variance / base.variance
            elif not lo <= use.variance <= hi:
                moved[case, d] = use.variance / base.variance
    assert not moved, moved


def test_the_burst_centre_is_placed_by_the_burst_not_the_grid() -> None:
    from noisevar.diagnostics.split_grid import burst_centre

    z = burst_record(2, 2016)
    n, block = z.size, 32
    c = burst_centre(z, 1900, 2150, block)
    assert 2010 <= c <= 2040  # the 14 samples from 2016, spread by the smoother's span
    for d in (1, 2, 3):
        assert burst_centre(z[d:], 1900 - d + 7, 2150 - d - 5, block) == c - d
    assert abs(burst_centre(z[::-1], n - 2150, n - 1900, block) - (n - c)) <= 1

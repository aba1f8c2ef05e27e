"""A still stretch inside the record, about two blocks long, gives the same R to use whatever
the block grids' phase (issue 26 item 2, onegrid11).

Each grid cuts the rest into whole blocks: both find two blocks still, and the stretch
still on both (their intersection) was 64 samples when the grids' phases agreed and 33-63
when dropping a leading sample moved the record's own grid, so the R to use came and went
(sktime's BasicMotions acc_z, gyr_z: 0.0155 -> none with 1-2 samples dropped). Read on
the union of the two grids' still stretches that hold a piece still on both, it is the
same rest on every phase (docs/algorithms.md §E1 *A still stretch inside the record*).
"""

from __future__ import annotations

from dataclasses import replace

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st

import noisevar
from noisevar.diagnostics.profile import LevelProfile, with_back_grid
from noisevar.diagnostics.regimes import Regime
from noisevar.estimators.regimes import variance_for, why_no_still
from noisevar.estimators.still_quiet import quiet_apart
from noisevar.estimators.still_set import (
    ABOVE,
    SAME,
    has_still_apart,
    kept_still,
    still_gap,
    still_note,
)
from tests.estimators.rest_records import rest_in_motion


def _to_use(est):
    """The R to use (``regimes="still"``), None when there is none."""
    return None if why_no_still(est) else (est if est.still is None else est.still)


def _same_r_to_use(z: np.ndarray) -> list[str]:
    """The transforms (reversal, 1-3 leading samples dropped) whose R to use is missing or
    outside the record's R to use's ci95."""
    base = _to_use(noisevar.estimate(z))
    assert base is not None, "the rest gives no R to use"
    lo, hi = base.ci95
    bad = []
    for name, x in (("reversed", z[::-1]), ("drop 1", z[1:]), ("drop 2", z[2:]), ("drop 3", z[3:])):
        use = _to_use(noisevar.estimate(x))
        if use is None or not lo <= use.variance <= hi:
            bad.append(f"{name}: {None if use is None else use.variance / base.variance}")
    return bad


# (seed, n, at, length): on main each lost or gained its R to use under a transform
CASES = [(4, 564, 242, 101), (5, 438, 216, 115), (6, 693, 429, 113), (23, 528, 132, 105),
         (26, 698, 340, 104), (29, 540, 311, 107)]  # fmt: skip


def test_a_rest_two_blocks_long_gives_the_same_r_to_use_on_every_phase() -> None:
    bad = {case: _same_r_to_use(rest_in_motion(*case)) for case in CASES}
    assert not any(bad.values()), bad


def test_the_still_r_is_the_rests_noise() -> None:
    for case in CASES:
        z = rest_in_motion(*case)
        for x in (z, z[1:], z[2:]):
            still = noisevar.estimate(x).still
            assert still is not None and still.ci95[0] <= 0.01 <= still.ci95[1], case


def test_a_grid_that_finds_one_level_adds_no_still_regime() -> None:
    # a 75-sample rest: the reversed grid found the record one regime (still by default,
    # the motion too), and the still regimes' union read the motion: 0.076, 7.6x the noise
    z = rest_in_motion(14, 653, 424, 75)
    for x in (z, z[1:], z[2:], z[3:]):
        still = noisevar.estimate(x).still
        assert still is None or still.ci95[0] <= 0.01 <= still.ci95[1], still.variance


@settings(max_examples=12)
@given(
    seed=st.integers(0, 10_000),
    n=st.integers(400, 700),
    length=st.integers(100, 120),
    where=st.floats(0.0, 1.0),
)
def test_property_the_r_to_use_does_not_move_with_the_grids_phase(
    seed: int, n: int, length: int, where: float
) -> None:
    at = 100 + int(where * (n - length - 200))
    assert not _same_r_to_use(rest_in_motion(seed, n, at, length))


def _moving_still():
    est = noisevar.estimate(rest_in_motion(*CASES[0]))
    assert est.still is not None and est.diagnostics.level_varies
    return est


def test_a_still_r_at_rs_level_makes_r_the_r_to_use() -> None:
    # gtsam's legged robot gyr_x: still R 0.95x R (the R to use), then 1.02x with 2 samples
    # dropped and R inside its interval: the R to use was none; it is R, inside both
    est = _moving_still()
    r = est.variance
    just_over = replace(est.still, variance=1.02 * r, ci95=(0.6 * r, 2.0 * r))
    still, diag = kept_still(est.diagnostics, r, just_over)
    assert still is None and diag.quiet.source == SAME
    assert still_gap(diag, r, None) is None
    assert still_note(diag, r, None).startswith("no separate still R")
    assert variance_for(replace(est, still=None, diagnostics=diag), "still") == r
    # told apart above R by over twice: no still R to use, as before
    high = replace(est.still, variance=3 * r, ci95=(2.5 * r, 4 * r))
    still, diag = kept_still(est.diagnostics, r, high)
    assert still is None and diag.quiet.source == ABOVE
    assert "no still R to use" in still_gap(diag, r, None)


def _profile(quiet: list[bool], regimes: list[tuple[int, int, bool]], n: int) -> LevelProfile:
    k = len(quiet)
    start = np.arange(k) * 32
    stop = np.r_[start[1:], n]
    ones = np.ones(k)
    parts = tuple(Regime(a, b, 1.0, 0.9, 1.1, 100.0, s) for a, b, s in regimes)
    return LevelProfile(
        start, stop, ones, ones, ones, 10 * ones, np.array(quiet), parts, robust=ones
    )


def test_no_quiet_block_on_one_grid_and_one_level_on_the_other_leaves_nothing_apart() -> None:
    # KITTI's GPS east velocity (gtsam): one still level, R the R to use; with 2 samples
    # dropped PELT split the record's grid into two regimes, neither with a quiet block,
    # while the reversed grid still found one level, and the R to use was none
    est = _moving_still()
    n = 320
    own = _profile([False] * 10, [(0, 192, False), (192, n, False)], n)
    back = _profile([True] * 9 + [False], [(0, n, True)], n)
    diag = replace(est.diagnostics, n=n, level_profile=with_back_grid(own, back, n))
    assert diag.level_varies and not has_still_apart(diag, 1.0)
    assert still_gap(diag, 1.0, None) is None
    quiet = quiet_apart(None, {}, diag, 1.0, lambda e: e)  # R is the quiet level
    assert quiet is not None and quiet.source == SAME
    assert still_gap(replace(diag, quiet=quiet), 1.0, None) is None
    # a reversed grid that finds the level varies too: no still R to use, as before
    split = _profile([True] * 5 + [False] * 5, [(0, 160, True), (160, n, False)], n)
    diag = replace(diag, level_profile=with_back_grid(own, split, n))
    assert has_still_apart(diag, 1.0) and still_gap(diag, 1.0, None) is not None

"""A rest whose split PELT makes at its penalty on one block grid's phase and not on the
next: its regimes, and the R to use, do not move when leading samples are dropped or the
record is reversed (issue 26 class 4, drop14).

A rest of 72-95 samples in motion gains 1.4-2x PELT's penalty on the grid that does not
split it (one change worth half the penalty: a hint of a change), so the record read one
level (R to use R) or three regimes (the still R, 9x below) as the grid's phase moved
(``benchmarks/still_phase.py``: 7 of 100 records). Where the record's grid hints a change
it does not make, the reversed grid's regimes are read (docs/algorithms.md §E1 *Regimes*).
"""

from __future__ import annotations

import numpy as np
from hypothesis import example, given, settings
from hypothesis import strategies as st

import noisevar
from noisevar.diagnostics.regimes import hints_a_change
from noisevar.estimators.regimes import why_no_still
from noisevar.stream import estimate_chunked
from tests.estimators.rest_records import rest_in_motion

TRANSFORMS = {
    "reversed": lambda z: z[::-1],
    "drop 1": lambda z: z[1:],
    "drop 2": lambda z: z[2:],
    "drop 3": lambda z: z[3:],
}


def _to_use(z: np.ndarray):
    """The R to use (``regimes="still"``), None when there is none."""
    est = noisevar.estimate(z)
    return None if why_no_still(est) else (est if est.still is None else est.still)


# (seed, n, at, length) of benchmarks/still_phase.py --seed 11: on main each R to use moved
# from the still R (~0.01) to R (~0.09) or back, reversed (7, 19) or with 1-3 dropped (20, 82)
CASES = [(7, 487, 269, 75), (19, 489, 234, 80), (20, 660, 288, 80), (82, 456, 156, 79)]


def test_a_borderline_rest_gives_the_same_r_to_use_on_every_phase() -> None:
    bad = {}
    for case in CASES:
        z = rest_in_motion(*case)
        base = _to_use(z)
        lo, hi = base.ci95
        moved = []
        for name, f in TRANSFORMS.items():
            use = _to_use(f(z))
            if use is None or not lo <= use.variance <= hi:
                moved.append(f"{name}: {None if use is None else use.variance / base.variance}")
        if moved:
            bad[case] = moved
    assert not bad, bad


def test_the_r_to_use_is_the_rests_noise_streamed_too() -> None:
    # the rest's noise is 0.01, the motion's about 0.09: every phase finds the rest, and
    # the streamed path (its reversed grid from the same sums) reads the same still R
    for case in CASES:
        z = rest_in_motion(*case)
        for f in (lambda x: x, *TRANSFORMS.values()):
            x = np.ascontiguousarray(f(z))
            est = noisevar.estimate(x)
            assert est.diagnostics.level_varies, case
            assert est.still is not None and est.still.ci95[0] <= 0.01 <= est.still.ci95[1], case
            many = estimate_chunked(lambda a, b, x=x: x[max(a, 0) : b].copy(), x.size, chunk=512)
            np.testing.assert_allclose(many.still.variance, est.still.variance, rtol=1e-9)


def test_white_noise_hints_no_change() -> None:
    # the hint costs a reversed profile only where a change is worth half PELT's penalty
    # (the screen PELT searches past): one level of white noise hints none in most records
    # and is split no more often than before (tests/diagnostics/test_regimes.py)
    hints = 0
    for seed in range(40):
        z = np.random.default_rng(seed).normal(size=3000)
        est = noisevar.estimate(z)
        prof = est.diagnostics.level_profile
        hints += prof.near_split
        assert not est.diagnostics.level_varies, seed
    assert hints <= 8


def test_hints_a_change_is_the_search_screen() -> None:
    level = np.r_[np.ones(10), np.full(10, 3.0)]
    assert hints_a_change(level, np.full(20, 50.0))
    assert not hints_a_change(np.ones(20), np.full(20, 50.0))
    assert not hints_a_change(np.ones(1), np.ones(1))


@settings(max_examples=25, deadline=None, derandomize=True)
@given(
    seed=st.integers(0, 10_000),
    n=st.integers(400, 700),
    length=st.integers(72, 95),
    where=st.floats(0.0, 1.0),
)
@example(seed=7, n=487, length=75, where=(269 - 100) / (487 - 75 - 200))
def test_whether_the_level_varies_does_not_move_under_reversal(
    seed: int, n: int, length: int, where: float
) -> None:
    # the split is made on both grids or on neither: reversal swaps them (on main 7 of
    # 150 such records read one level one way and three regimes the other)
    at = int(where * (n - length - 200)) + 100
    z = rest_in_motion(seed, n, at, length)
    fwd = noisevar.estimate(z).diagnostics.level_varies
    assert fwd == noisevar.estimate(z[::-1]).diagnostics.level_varies

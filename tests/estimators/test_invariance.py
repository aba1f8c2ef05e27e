"""What must hold on any record: R does not move when nothing changed (issue 26).

Sign, units, an offset and a linear trend change nothing a polynomial residual sees, so R
stays inside its own interval on every motion-burst record (hypothesis draws the records).
Reversal and dropped leading samples move the block grid; their share inside the interval
is measured by ``python benchmarks/invariance.py`` (target 95 %). The jump detector's
decisions (fast signal or jumps) no longer follow the grid: seeded records where they did
are checked here.
"""

from __future__ import annotations

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

import noisevar
from noisevar import synth

N = 8000


def _record(seed: int) -> np.ndarray:
    rng = np.random.default_rng(seed)
    t = np.arange(N)
    z = 3.0 * np.sin(2 * np.pi * t / rng.uniform(2000, 8000)) + rng.normal(0.0, 1.0, N)
    return z + synth.motion_bursts(N, rng)


@settings(max_examples=15)
@given(
    seed=st.integers(0, 2**32 - 1),
    scale=st.floats(1e-9, 1e9),
    offset=st.floats(-1e4, 1e4),
    slope=st.floats(-1.0, 1.0),
)
def test_sign_units_offset_and_trend_leave_r_inside_its_interval(seed, scale, offset, slope):
    z = _record(seed)
    est = noisevar.estimate(z)
    lo, hi = est.ci95
    moved = -scale * z + offset * scale + slope * scale * np.arange(N)
    other = noisevar.estimate(moved)
    assert lo <= other.variance / scale**2 <= hi
    assert other.diagnostics.flags == est.diagnostics.flags


def test_the_same_record_reversed_keeps_its_still_level():
    z = _record(11)
    fwd, bwd = noisevar.estimate(z), noisevar.estimate(z[::-1])
    assert fwd.ci95[0] <= bwd.variance <= fwd.ci95[1]
    if fwd.still is not None and bwd.still is not None:
        assert fwd.still.ci95[0] <= bwd.still.variance <= fwd.still.ci95[1]


@pytest.mark.parametrize("seed", [18, 24, 48, 63])
def test_reversed_motion_burst_records_keep_r_inside_its_interval(seed):
    # seeded records whose reversal moved R out of its ci95 (1.14x, 1.68x, 0.91x, 0.89x):
    # motion flagged as jumps on one block grid and as a fast signal on the other. Of the
    # first 80 seeds, 14 moved out before, one now (seed 4, 1.058x: the span chosen per
    # block, the one decision left on the grid from the start; the rest 0.995-1.02x)
    z = _record(seed)
    fwd, bwd = noisevar.estimate(z), noisevar.estimate(z[::-1])
    assert fwd.ci95[0] <= bwd.variance <= fwd.ci95[1]


@pytest.mark.parametrize("seed", [1, 3, 12, 37])
def test_reversal_leaves_the_jumps_and_a_fixed_span_r_unchanged(seed):
    # by construction: the levels are read on two grids (from the start and from the end),
    # the step detector tests each boundary on both sides, and the fast-signal rule uses a
    # centred window; with one span (no choice per block) R is the same sum
    from noisevar.estimators.auto import jump_mask

    z = _record(seed)
    fwd, bwd = jump_mask(z), jump_mask(z[::-1])
    assert (fwd is None) == (bwd is None)
    if fwd is not None:
        np.testing.assert_array_equal(bwd[::-1], fwd)
    a = noisevar.estimate(z, "auto", span=21).variance
    assert noisevar.estimate(z[::-1], "auto", span=21).variance == pytest.approx(a, rel=1e-9)


def test_fast_signal_flags_are_dropped_by_a_window_centred_on_them():
    # a block grid anchored at the record's start decided "fast signal" or "jumps" per block:
    # reversed, the same motion fell on other blocks and R moved (hand-held YEI gyroscope Y
    # 2.3x, issue 26); the window centred on each flag moves with the record
    from noisevar.estimators.auto._trim import _believed

    rng = np.random.default_rng(3)
    for n in (2715, 4096, 1000):
        found = np.zeros(n, dtype=bool)
        found[rng.integers(0, n, 40)] = True
        a = int(rng.integers(0, n - 450))
        found[a : a + 400 : 2] = True  # a fast signal: every other sample for 400
        kept = _believed(found, 256)
        back = _believed(found[::-1], 256)
        assert (kept is None) == (back is None)
        if kept is not None:
            np.testing.assert_array_equal(back[::-1], kept)
            assert not kept[a : a + 400].any()  # the fast stretch is not jumps


def _shaken(seed: int, n: int = 4000) -> np.ndarray:
    """White noise (σ = 1) with one shake: a smooth swing and heavy-tailed knocks in it."""
    rng = np.random.default_rng(seed)
    z = rng.normal(size=n)
    a, m = int(rng.integers(500, n - 800)), int(rng.integers(150, 400))
    t = np.arange(m)
    swing = rng.uniform(30, 300) * np.sin(np.pi * t / m) ** 2
    z[a : a + m] += swing + rng.uniform(5, 50) * rng.standard_t(3, size=m)
    return z


def test_dropping_a_leading_sample_leaves_the_first_pass_levels_to_the_blocks_content():
    # the first pass took its block medians of every fourth square: which fourth moved with
    # the samples dropped, and where a shake fills part of a block its median sits in the
    # shake, so the shake was left out of the local level or not and R moved (x0.19 here
    # with one sample dropped; the Pololu MinIMU's acc_y x0.053 with three, issue 26)
    from noisevar.estimators.auto._levels import Grids, medians

    z = _shaken(7)
    est, again = noisevar.estimate(z), noisevar.estimate(z[1:])
    assert est.ci95[0] <= again.variance <= est.ci95[1]
    sq = np.random.default_rng(0).chisquare(1, 1000)
    fwd, bwd = medians(sq, Grids.make(sq.size, 256))
    np.testing.assert_array_equal(fwd, np.median(sq[:768].reshape(3, 256), axis=1))
    np.testing.assert_array_equal(bwd, np.median(sq[::-1][:768].reshape(3, 256), axis=1))


def test_a_steep_trend_leaves_taps_that_ring_in_the_noise():
    # the step detector's confirmation takes window medians, which ignore a tap: but on a
    # trend steeper than the noise a window's order is its time order, its median the mean
    # of its two middle samples, and a tap moved it like a mean: taps became jumps and were
    # cut (R x0.17 here at 5 σ per sample; the Pololu MinIMU's acc_x x0.14, issue 26).
    # Medians now taken off the windows' local line: an added trend changes nothing
    from noisevar.numeric import steps

    rng = np.random.default_rng(0)
    n = 3000
    z = rng.normal(size=n)
    for k in range(150, n - 150, 200):  # taps that ring: 4 samples of alternating ±15 σ
        z[k : k + 4] += 15.0 * np.array([1, -1, 1, -1]) * rng.uniform(0.7, 1.3, 4)
    est = noisevar.estimate(z)
    for slope in (5.0, 50.0):
        ramp = slope * np.arange(n)
        assert est.ci95[0] <= noisevar.estimate(z + ramp).variance <= est.ci95[1]
        found = steps.step_mask(z + ramp, lambda x: x > 1.0)
        np.testing.assert_array_equal(found, steps.step_mask(z, lambda x: x > 1.0))

"""The bottom layer's block arithmetic and step detector against their naive forms."""

from __future__ import annotations

import numpy as np
import pytest


@pytest.mark.parametrize("n, block", [(1000, 256), (1030, 256), (5000, 64), (70, 16), (20, 16)])
def test_kept_block_sums_equals_zeroing_a_copy(n, block):
    from noisevar.numeric.blocks import block_sums, kept_block_sums

    rng = np.random.default_rng(n + block)
    nb = max(1, n // block)
    for k in (0, 1, 5, 200):
        x = rng.standard_normal(n) ** 2
        x[rng.integers(0, n, 3)] = 1e15  # a huge outlier must not swamp its block's sum
        idx = np.union1d(rng.integers(0, n, k), np.flatnonzero(x > 1e10)).astype(int)
        ref = x.copy()
        ref[idx] = 0.0
        before = x.copy()
        got = kept_block_sums(x, idx, block, nb)
        np.testing.assert_allclose(got, block_sums(ref, block, nb), rtol=1e-12, atol=0)
        np.testing.assert_array_equal(x, before)


def test_block_medians_equal_numpy_median():
    from noisevar.numeric.blocks import block_medians

    rng = np.random.default_rng(3)
    for block in (256, 18, 17):
        x = rng.standard_normal(50 * block + 7)
        ref = np.median(x[: 50 * block].reshape(50, block)[:, ::4], axis=1)
        np.testing.assert_array_equal(block_medians(x, block, 50, 4), ref)


def test_step_mask_finds_a_jump_and_ignores_a_parabola():
    from noisevar.numeric.steps import step_mask

    rng = np.random.default_rng(4)
    k = np.arange(4000.0)
    z = 1e-4 * (k - 2000.0) ** 2 + rng.standard_normal(k.size)
    z[2500:] += 8.0

    def above(x):
        return x > 1.0  # unit noise variance, scale 1

    hit = step_mask(z, above)
    assert hit[2490:2510].any()
    assert not hit[:2400].any() and not hit[2600:].any()


def test_step_mask_flags_the_same_samples_on_the_reversed_record():
    # D3[k] is centred between samples k - 1 and k: flagging both makes the detector
    # symmetric in time (before, the reversed record's flags sat one sample off; issue 26)
    from noisevar.numeric.steps import step_mask

    rng = np.random.default_rng(7)
    z = rng.standard_normal(3000)
    z[700:] += 9.0
    z[1801:2300] -= 7.0
    z[2600:2640] += 12.0 * np.sin(np.arange(40.0))

    def above(x):
        return x > 1.0

    hit = step_mask(z, above)
    assert hit[690:710].any() and hit[1790:1810].any()
    np.testing.assert_array_equal(step_mask(z[::-1], above)[::-1], hit)


def test_lone_steps_one_run_per_jump_whatever_its_size():
    # a step is one event: a 40-sigma jump flags its whole response (up to 4w samples),
    # yet it is one lone step, as a small one is; a run longer than one response, runs
    # closer than 2w, or a side that bends (a fast signal) are not lone; the same reversed
    from noisevar.numeric.steps import STEP_WINDOW, lone_steps

    w = STEP_WINDOW
    rng = np.random.default_rng(5)
    z = 0.01 * np.arange(700) + rng.standard_normal(700)  # a ramp: straight sides

    def above(x):
        return x > 1.0  # the local noise variance is 1

    found = np.zeros(700, dtype=bool)
    found[100 : 100 + 4 * w] = True  # one big jump's whole response
    found[200:202] = True  # a small jump
    found[300 : 300 + 4 * w + 1] = True  # longer than one step's response
    found[400:404] = found[408:412] = True  # two runs 4 apart: one run (gaps <= w merge)
    found[500:504] = found[515:519] = True  # two runs 11 apart (< 2w): not quiet sides
    found[600:604] = True  # a run whose left side bends
    z[600 - 2 * w : 600] += 20.0 * np.sin(np.arange(2 * w) / 2.0)
    lone = lone_steps(z, found, above)
    assert lone[100 : 100 + 4 * w].all() and lone[200:202].all()
    assert lone[400:412].sum() == 8
    assert not lone[300 : 300 + 4 * w + 1].any() and not lone[500:520].any()
    assert not lone[600:604].any()
    np.testing.assert_array_equal(lone_steps(z[::-1], found[::-1], above)[::-1], lone)


@pytest.mark.parametrize("n, block", [(5000, 256), (5100, 256), (300, 16), (200, 100), (150, 100)])
def test_chosen_above_sums_compiled_equal_the_numpy_path(n, block):
    """One pass over each block's chosen row: the same sums (added in sample order) and counts."""
    from noisevar.estimators.auto._levels import half_levels
    from noisevar.estimators.auto._trim import _above_sums
    from noisevar.numeric.blocks import chosen_above_sums

    rng = np.random.default_rng(n + block)
    nb = max(1, n // block)
    sq = rng.standard_t(3, (4, n)) ** 2 * rng.uniform(0.1, 10.0, (4, 1))
    choice = rng.integers(0, 4, nb)
    local = rng.uniform(1.0, 6.0, nb)
    if nb > 1:
        local[rng.integers(0, nb)] = np.inf  # an all-trimmed block
    got = chosen_above_sums(sq, choice, local, half_levels(local), block)
    ref = _above_sums(sq, choice, local, block)
    assert got is not None and ref[1].sum() > 0
    assert np.array_equal(got[0], ref[0]) and np.array_equal(got[1], ref[1])


def test_lone_steps_share_one_residual_maker_per_side_length():
    """The line's residual maker is made once per length and cannot be changed by a caller."""
    from noisevar.numeric.steps import _line_residuals

    r = _line_residuals(11)
    assert r is _line_residuals(11) and not r.flags.writeable
    t = np.arange(11.0)
    np.testing.assert_allclose(r @ (2.0 - 3.0 * t), 0.0, atol=1e-12)  # a line: no residual
    np.testing.assert_allclose(r @ r, r, atol=1e-12)  # a projection

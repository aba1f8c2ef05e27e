"""The whiteness windows' and increments' masks without glitches, against the per-sample rule."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar import diagnostics as D
from noisevar.diagnostics.plan import make_plan, probe_of
from noisevar.diagnostics.segments import Segmentation
from noisevar.diagnostics.sums import DiagSums, diag_part
from noisevar.diagnostics.whiteness import WHITE_LAGS


def _reference(sums: DiagSums, keep_w, used, g):
    """Each position's sample, then: a glitch within h of a residual's, at an increment's ends."""
    plan = sums.plan
    slots = D._residual_slots(plan, sums.white.joined_slots())
    near = np.zeros(slots.size, dtype=bool)
    on = slots >= 0
    k = D._sample_of(plan, slots[on])
    near[on] = np.array([np.any(np.abs(g - x) <= plan.h) for x in k], dtype=bool)
    inc = sums.incr.joined_slots()
    touch = np.zeros(inc.size, dtype=bool)
    d0 = np.cumsum([0] + [b - a - 1 + WHITE_LAGS for a, b in plan.segments])
    for (a, b), s0 in zip(plan.segments, d0, strict=False):
        mine = (inc >= s0) & (inc < s0 + b - a - 1)
        k = inc[mine] - s0 + a
        touch[mine] = np.isin(k, g) | np.isin(k + 1, g)
    return keep_w & ~near, used & ~touch


@pytest.mark.parametrize(
    "n, segments",
    [
        (20_000, ((0, 20_000),)),
        (600_000, ((0, 600_000),)),  # windows spread over the record
        (9_000, ((0, 3_000), (3_000, 3_030), (3_030, 9_000))),  # one too short to diagnose
        (700_000, ((0, 250_000), (250_000, 700_000))),
    ],
)
def test_masks_without_glitches_equal_the_per_sample_rule(n, segments):
    rng = np.random.default_rng(n)
    z = rng.standard_normal(n)
    seg = Segmentation(segments, ())
    plan = make_plan(n, segments, probe_of(z.__getitem__, n))
    sums = DiagSums(plan)
    for i, (a, b) in enumerate(segments):
        sums.add(diag_part(z[a:b], a, (a, b), i, plan))
    e_w, keep_w = sums.white.joined()
    dz, used = sums.incr.joined()
    # glitches at the edges of segments and windows, next to each other, and anywhere
    g = np.unique(np.r_[0, n - 1, [a for a, _ in segments], [b - 1 for _, b in segments],
                        rng.integers(0, n, 40), 500, 501, 503])  # fmt: skip
    ref = _reference(sums, keep_w.copy(), used.copy(), g)
    got = D._without_glitches(sums, keep_w, used, lambda: z, seg, g)
    assert np.array_equal(got[0], ref[0]) and np.array_equal(got[1], ref[1])
    assert (~got[0] & keep_w).any()  # some residuals were left out

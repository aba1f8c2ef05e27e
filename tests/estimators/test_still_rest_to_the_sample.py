"""A rest of 64-95 samples inside motion keeps its R to use whatever the block grids' phase
(issue 26 item 2, drop13).

Each grid cuts such a rest into one or two whole blocks as its phase falls; the stretches
still on both grids, their union and the still regimes could all be under the 64 samples
R's method needs, so the R to use came and went with 1-3 leading samples dropped. Its ends
read to the sample (the residual windows at the quiet level,
``still_extent.to_the_sample``) are the rest's own, on every phase (docs/algorithms.md §E1
*A still stretch inside the record*).
"""

from __future__ import annotations

import noisevar
from noisevar.estimators.still_extent import to_the_sample
from tests.estimators.rest_records import rest_in_motion
from tests.estimators.test_still_inside_phase import _same_r_to_use

# (seed, n, at, length): on main each had no R to use, or lost it or moved it outside its
# ci95 under reversal or 1-3 dropped samples (benchmarks/still_phase.py's 72-95 family)
CASES = [(5, 438, 240, 90), (7, 510, 220, 75), (37, 576, 193, 72), (38, 679, 223, 79),
         (27, 409, 126, 76)]  # fmt: skip


def test_a_short_rest_gives_the_same_r_to_use_on_every_phase() -> None:
    bad = {case: _same_r_to_use(rest_in_motion(*case)) for case in CASES}
    assert not any(bad.values()), bad


def test_the_rests_still_r_is_its_noise_on_every_phase() -> None:
    for case in CASES:
        z = rest_in_motion(*case)
        for x in (z, z[::-1], z[1:], z[2:], z[3:]):
            still = noisevar.estimate(x).still
            assert still is not None and still.ci95[0] <= 0.01 <= still.ci95[1], case


def test_the_rests_ends_are_read_off_its_samples() -> None:
    # the same rest, found from any piece of it: the ends do not depend on the seed
    seed, n, at, length = CASES[1]
    z = rest_in_motion(seed, n, at, length)
    prof = noisevar.estimate(z).diagnostics.level_profile
    back, read = prof.back_grid.profile, lambda a, b: z[a:b]
    pieces = [[(at + k, at + k + 20)] for k in range(0, 50, 7)]
    found = {tuple(to_the_sample(p, prof, back, read, n)) for p in pieces}
    assert len(found) == 1, found
    ((a, b),) = found.pop()
    assert abs(a - at) <= 3 and abs(b - (at + length)) <= 3, (a, b)

"""The fast-signal rule does not flip when one short run changes between lone step and not.

``gpx_untimed`` (issue 26, ``benchmarks/real_audit3.py``): R moved x6.6 when the first
fix was dropped. Whether a short run of the step detector's flags is a lone step turns on
its gap to the next run (2w), which one sample's shift of the flags moves; the rule counted
every flag but the lone steps', so two runs near the start stopped being lone, one other
became lone, the count crossed the fraction, and the stretch's flags (jumps on the whole
record) were dropped as a fast signal. Synthetic flags of the same build: long runs and
short ones, with the two lone sets the whole record and the record less its first fix had.
Now a run one jump explains (``lone_steps(..., alone=False)``) counts once, lone or not.
"""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.estimators.auto._trim import _believed


def _flags(density: float) -> tuple[np.ndarray, ...]:
    rng = np.random.default_rng(26)
    n = 871
    found = np.zeros(n, dtype=bool)
    for a, b in ((14, 56), (69, 101), (347, 369), (377, 392), (509, 565), (738, 770)):
        found[a:b] = rng.random(b - a) < density
        found[a] = found[b - 1] = True
    short = (113, 192, 199, 227, 297, 313, 414, 640, 656, 711, 833)
    for a in short:
        found[a : a + 4] = True  # short runs with straight sides: one jump's response each

    def lone(starts: tuple[int, ...]) -> np.ndarray:
        out = np.zeros(n, dtype=bool)
        for a in starts:
            out[a : a + 4] = True
        return out

    # every short run is step-shaped; the whole record's lone steps, and those of the record
    # less its first sample
    whole, shifted = lone((192, 199, 227, 297, 313, 414, 640)), lone((113, 192, 199, 227, 414, 833))
    return found, lone(short), whole, shifted


@pytest.mark.parametrize("density", [0.66, 0.7, 0.74, 0.8])
def test_which_short_runs_are_lone_does_not_flip_the_fast_signal_rule(density):
    found, shaped, whole, shifted = _flags(density)
    a, b = _believed(found, 256, whole, shaped), _believed(found, 256, shifted, shaped)
    assert a is not None and b is not None  # before: 177-200 jumps kept against 4-70
    np.testing.assert_array_equal(a, b)

"""A still set that R's own residual reads above the whole record is no quiet level
(real_audit4: a ship's temperature, still R 107.1 against R 42.2, which dropping 2 or 3
samples removed)."""

from __future__ import annotations

from dataclasses import replace

import noisevar
from noisevar.estimators.still_quiet import above_record
from noisevar.estimators.still_set import ABOVE, still_gap, still_note
from tests.estimators.test_still_from_regimes_everywhere import moving_record


def _moving():
    e = noisevar.estimate(moving_record())
    assert e.still is not None
    return e


def test_a_still_r_under_r_stays() -> None:
    e = _moving()
    assert above_record(e.diagnostics, e.still, e) is None


def test_a_still_r_above_r_is_refused_with_its_reason_everywhere() -> None:
    e = _moving()
    high = replace(e.still, variance=10 * e.ci95[1], ci95=(5 * e.ci95[1], 20 * e.ci95[1]))
    q = above_record(e.diagnostics, high, e)
    assert q is not None and q.source == ABOVE and q.variance is None
    assert "no quieter level than R" in q.reason
    d = replace(e.diagnostics, quiet=q)
    gap = still_gap(d, e.variance, None)
    assert gap is not None and q.reason in gap and "no still R to use" in gap
    assert still_note(d, e.variance, None) == (
        "no still R: the still stretches read above the whole record"
    )

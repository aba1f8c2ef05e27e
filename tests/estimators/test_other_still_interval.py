"""Another still level's interval from its own stretch's tails (audit 11: GENEActiv z's
"13.69x (ci95 1.50-25035646563412.54x)", widened by the whole record's kurtosis)."""

from __future__ import annotations

import numpy as np

import noisevar


def _postures(seed: int) -> np.ndarray:
    """Still (σ 0.01), then walking with heavy-tailed jolts (the record's kurtosis over
    1000), with another still posture (σ 0.014, one jolt) at samples 3000-3800."""
    rng = np.random.default_rng(seed)
    n, t = 8400, np.arange(8400)
    z = 0.01 * rng.normal(size=n)
    walk = t >= 1200
    jolts = 1 + 0.5 * rng.standard_t(2, size=int(walk.sum()))
    z[walk] += 0.3 * np.sin(2 * np.pi * t[walk] / 50) * jolts
    z[3000:3800] = 0.014 * rng.normal(size=800)
    z[3400] += 0.5
    return z


def test_another_still_level_is_bounded_by_its_own_tails() -> None:
    est = noisevar.estimate(_postures(0))
    assert est.diagnostics.kurtosis > 1000
    (level,) = est.diagnostics.other_still
    # was: 5.59x (ci95 1.18-2470.62x): the stretch read at the record's tails
    assert level.lo < level.ratio < level.hi < 10 * level.ratio

"""The still set is one answer: verdict, ``est.still``, ``variance_for`` and ``regimes="still"``.

benchmarks/real_audit.py (issue 26), reproduction B: on 10 real channels the verdict quoted
a still level while ``est.still`` was None (its still stretches shorter than the still path
needs), and ``variance_for(est, "still")``, the R to use, silently gave the whole record's
R, up to 886x the quoted level. A seeded record reproduces it: white noise (variance 9e-4)
still for its first k samples, then motion.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from noisevar import synth
from noisevar.diagnostics.profile import still_if_quiet
from noisevar.diagnostics.regimes import Regime
from noisevar.estimators.regimes import (
    STILL_MIN,
    estimate_for,
    longest_still_stretch,
    still_gap,
    variance_for,
)


@pytest.mark.parametrize("seed", [0, 1])
def test_short_still_start_gives_no_whole_record_r_as_still(seed: int) -> None:
    est = noisevar.estimate(synth.still_start(64, rng=seed))
    assert est.diagnostics.level_varies and est.still is None  # the case reproduced
    with pytest.raises(noisevar.NoisevarError, match="too short|shorter than"):
        variance_for(est, "still")
    with pytest.raises(noisevar.NoisevarError, match=f"the {STILL_MIN} samples"):
        estimate_for(est, "still")
    assert variance_for(est, "all") == est.variance


def test_short_still_start_verdict_says_indicative() -> None:
    est = noisevar.estimate(synth.still_start(64, rng=0))
    gap = still_gap(est.diagnostics, est.variance, est.still)
    assert gap is not None
    assert "indicative only" in est.diagnostics.verdict
    # said once: the gap's reason covers the whiteness test the short stretches cannot take
    assert est.diagnostics.verdict.count("record the sensor still for longer") == 1
    assert gap.removeprefix("regimes='still': ") in est.diagnostics.verdict


def test_long_still_start_gives_its_still_r() -> None:
    est = noisevar.estimate(synth.still_start(128, rng=0))
    assert est.still is not None
    use = variance_for(est, "still")
    assert use == est.still.variance and 0.3 < use / 9e-4 < 3.0
    assert "indicative" not in est.diagnostics.verdict


def test_fits_follow_the_same_rule() -> None:
    z = synth.still_start(64, rng=0)
    est = noisevar.estimate(z)
    with pytest.raises(noisevar.NoisevarError) as exc:
        longest_still_stretch(z)
    assert str(exc.value) == still_gap(est.diagnostics, est.variance, est.still)


def test_one_still_regime_uses_the_whole_record() -> None:
    est = noisevar.estimate(0.1 * np.random.default_rng(3).normal(size=2000))
    assert not est.diagnostics.level_varies
    assert variance_for(est, "still") == est.variance
    assert longest_still_stretch(0.1 * np.random.default_rng(3).normal(size=2000)).one_regime


def test_still_regime_without_quiet_block_is_not_still() -> None:
    start, stop = np.array([0, 50, 100]), np.array([50, 100, 150])
    regimes = (
        Regime(0, 50, 1.0, 0.5, 2.0, 10.0, True),
        Regime(50, 150, 9.0, 5.0, 20.0, 10.0, False),
    )
    out = still_if_quiet(regimes, start, stop, np.zeros(3, dtype=bool))
    assert not any(r.still for r in out)
    kept = still_if_quiet(regimes, start, stop, np.array([True, False, False]))
    assert kept == regimes


def test_regimes_and_quiet_set_agree_on_level_changing_noise() -> None:
    for seed in range(4):  # tests/diagnostics/test_audit_verdicts.py's record
        rng = np.random.default_rng(seed)
        z = rng.normal(size=1000) * np.exp(1.5 * rng.normal(size=20).repeat(50))
        d = noisevar.estimate(z).diagnostics
        if any(r.still for r in d.regimes):
            assert d.level_profile.quiet.any()

"""A short record that drives, then parks (a GNSS position of a few hundred fixes).

The drive is all level jumps to the jump detector: every residual of the level profile
there is left out around them, so the profile saw the parked half alone, one still level,
while R held the drive: "white Gaussian noise: R = ... is a good Kalman R" at 3.9-22x the
parked noise. Runs of blocks too thin to measure are now motion of no measured level
(``LevelProfile.unmeasured``), and the parked half's R is the one quoted beside R.
"""

from __future__ import annotations

import numpy as np
import pytest

import noisevar
from tests.diagnostics.park_records import SIGMA
from tests.diagnostics.park_records import drive_then_park as _drive_then_park

CASES = [(3, 300, 5.0, True), (3, 400, 2.0, True), (0, 400, 2.0, False)]


@pytest.mark.parametrize(("seed", "n", "step", "smooth"), CASES)
def test_the_drive_is_motion_and_the_parked_noise_is_quoted(
    seed: int, n: int, step: float, smooth: bool
) -> None:
    z = _drive_then_park(seed, n, step, smooth)
    for rec in (z, z[::-1]):
        est = noisevar.estimate(rec)
        v = est.diagnostics.verdict
        assert not v.startswith("white"), v
        assert v.startswith("the noise level changes along the record"), v
        assert "move too fast to measure" in v  # where, said
        assert est.still is not None
        lo, hi = est.still.ci95
        assert lo <= SIGMA**2 <= hi, (est.still.variance, est.still.ci95)
        assert est.ci95[0] > hi  # R holds the drive: the still R is apart from it
        share = est.diagnostics.level_profile.quiet_share
        assert 0.3 < share < 0.7  # the parked half, over the record (not over its blocks)
        assert est.diagnostics.level_profile.unmeasured


def test_a_record_with_no_thin_run_has_none() -> None:
    rng = np.random.default_rng(1)
    est = noisevar.estimate(rng.normal(size=2000))
    assert est.diagnostics.level_profile.unmeasured == ()
    assert est.diagnostics.verdict.startswith("white")


def test_the_level_profile_shades_the_drive() -> None:
    """The Noise panel shows where the record moved too fast to measure, in its times."""
    import json

    from noisevar.diagnostics.panel import noise_panel_data
    from noisevar.figures.noise import level_profile_plot

    z = _drive_then_park(3, 300, 5.0, True)
    est = noisevar.estimate(z)
    t = 100.0 + 0.5 * np.arange(z.size)
    panel = noise_panel_data(z, est.diagnostics, t)
    (a, b), = est.diagnostics.level_profile.unmeasured
    assert panel.unmeasured_x.tolist() == [[t[a], t[b - 1]]]
    json.dumps(panel.to_dict(), allow_nan=False)
    shapes = level_profile_plot(panel).layout.shapes
    assert [(s.x0, s.x1) for s in shapes] == [(t[a], t[b - 1])]


def test_a_long_staircase_is_not_called_a_short_record() -> None:
    """Close steps leave few residuals clear of jumps: before, "only 20000 samples"."""
    rng = np.random.default_rng(0)
    n = 20000
    z = rng.normal(size=n) + 20.0 * np.floor(np.arange(n) / 60)
    v = noisevar.estimate(z).diagnostics.verdict
    assert v.startswith(f"{n} samples, but only ")
    assert "residuals clear of the level jumps" in v and "only 20000 samples" not in v


def test_under_twice_the_parked_noise_the_drive_is_still_apart() -> None:
    """2 samples dropped: R 1.92x the parked noise, under the 2x of a left-out run's rule;
    before, "white Gaussian noise: R = 0.004798 ... is a good Kalman R"."""
    est = noisevar.estimate(_drive_then_park(6, 300, 2.0, True)[2:])
    assert est.diagnostics.verdict.startswith("the noise level changes along the record")
    assert est.still is not None
    lo, hi = est.still.ci95
    assert lo <= SIGMA**2 <= hi < est.variance


def test_lone_glitches_outside_the_drive_hold_r_not_the_drive() -> None:
    """UCR InternalBleeding16 (real_audit14): runs of level jumps too fast to measure and
    two outlying samples holding R at 7.5x its core. The glitches are R's excess, said as
    outlying samples; the R to use stays R (it became the still level for a moment)."""
    from dataclasses import replace

    from noisevar.diagnostics import Glitch
    from noisevar.estimators.still_set import has_still_apart

    est = noisevar.estimate(_drive_then_park(3, 300, 5.0, True))
    d = est.diagnostics
    (a, b), = d.level_profile.unmeasured
    assert has_still_apart(d, est.variance)
    inside = replace(d, glitches=(Glitch(a + 5, 40.0),))  # part of the drive
    assert has_still_apart(inside, est.variance)
    outside = replace(d, glitches=(Glitch(b + 50, 40.0),))
    assert not has_still_apart(outside, est.variance)


def test_every_surface_says_the_level_changes() -> None:
    """The verdict says the level changes; the flags (badges, the row's
    ``flag_level_varies``), the severity (the dashboard's warning), the answer and the
    Kalman fit's record check say it too. They read one level, with a check mark, where
    the still R was apart from one regime (``NoiseDiagnostics.level_changes``)."""
    from noisevar.estimators.answer import record_answer
    from noisevar.noise_model.kalman_record import record_check

    est = noisevar.estimate(_drive_then_park(3, 300, 5.0, True))
    assert est.diagnostics.level_varies is False  # one regime: the drive is left out
    assert est.diagnostics.verdict.startswith("the noise level changes along the record")
    assert est.diagnostics.flags["level_varies"] is True
    assert est.to_row()["flag_level_varies"] is True
    ans = record_answer(est)
    assert ans.level_varies and ans.severity == "warning"
    check = record_check(est.variance, est)
    assert any(b.startswith("one noise level") for b in check.broken), check.broken

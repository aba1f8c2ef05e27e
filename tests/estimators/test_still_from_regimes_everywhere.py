"""A still R measured on the still regimes (no quiet block on the record's own grid) is
the one every page and fit uses, and the verdict quotes it (real_audit4: a ROS 2 bag's gyro,
still R 5.96e-7 from the reversed grid's still regimes; the verdict said "no stretch of it
is quiet" and ``inertial_noise(regimes="still")`` found no still stretch)."""

from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

import noisevar
from noisevar.diagnostics.regimes import QuietLevel
from noisevar.diagnostics.verdict import make_verdict
from noisevar.estimators.regimes import longest_still_stretch


def moving_record() -> np.ndarray:
    """White noise (σ 1) with three bursts of 20x the noise: a still R apart from R."""
    rng = np.random.default_rng(8)
    z = rng.normal(0, 1.0, 20000)
    for c in (3000, 9000, 15000):
        z[c : c + 2000] += rng.normal(0, 20.0, 2000)
    return z


@pytest.fixture(scope="module")
def moving():
    z = moving_record()
    e = noisevar.estimate(z)
    assert e.still is not None and e.diagnostics.level_varies and e.still.stretches
    return z, e


def _no_quiet_block(e):
    """``e`` as if its own grid's quiet blocks and still regimes were none (the bag's case)."""
    d = e.diagnostics
    prof = d.level_profile
    prof = replace(
        prof,
        quiet=np.zeros_like(prof.quiet),  # so no still stretch on this grid either
        regimes=tuple(replace(r, still=False) for r in prof.regimes),
    )
    share = sum(b - a for a, b in e.still.stretches) / d.n
    quiet = QuietLevel(e.still.variance, *e.still.ci95, share, "still")
    return replace(d, level_profile=prof, quiet=quiet)


def test_the_verdict_quotes_the_still_r_it_has(moving) -> None:
    z, e = moving
    d = _no_quiet_block(e)
    v = make_verdict(d, e.variance, e.core_variance, e.outlier_fraction, e.still.variance)
    assert "no stretch of it is quiet" not in v, v
    assert f"({d.quiet.share:.0%})" in v and "(0%)" not in v, v


def test_the_fits_take_the_still_rs_stretches(moving) -> None:
    z, e = moving
    e2 = replace(e, diagnostics=_no_quiet_block(e))
    e2.still = e.still
    s = longest_still_stretch(z, 0, "the fit", e2)
    assert any(a <= s.start and s.stop <= b for a, b in e.still.stretches), (s, e.still.stretches)

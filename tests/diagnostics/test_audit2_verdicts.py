"""Failure classes of the second real-record audit (benchmarks/real_audit2.py), seeded."""

import numpy as np
import scipy.signal as ss

import noisevar


def test_coloured_verdict_never_names_only_white_slopes():
    """PX4 gyro/accel class: whiteness fails, the power-law slopes read white at every
    factor; the verdict said "coloured: white at 1-16 samples". Now it names the lag-1
    correlation that makes it coloured."""
    rng = np.random.default_rng(0)
    z = ss.lfilter([1.0], [1.0, -0.2], rng.normal(size=1300))  # AR(1), phi 0.2
    d = noisevar.estimate(z).diagnostics
    assert not d.flags["white"]
    assert d.verdict.startswith("the noise is coloured")
    assert "coloured: white at" not in d.verdict
    assert "coloured: lag-1 autocorrelation +" in d.verdict


def test_a_constant_stretch_is_no_still_level():
    """heartpy's PPG class: the sensor lost contact and wrote 0 for 836 samples. The
    quiet stretches "gave 0", and under a linear trend that stretch became the R to use
    (7.7e-25). A flat stretch is a dropout, not the sensor's still noise."""
    n = 15000
    rng = np.random.default_rng(0)
    z = 50.0 * np.sin(np.arange(n) / 40.0) + rng.normal(size=n)
    z[2100:2940] = 0.0
    trend = np.linspace(0.0, 1e3 * np.std(z), n)
    for y in (z, z + trend, z[1:], z[3:]):
        est = noisevar.estimate(y)
        assert est.still is not None
        assert 0.9 < est.still.variance < 1.1
        assert not any(g.still and g.variance < 1e-6 for g in est.diagnostics.regimes)

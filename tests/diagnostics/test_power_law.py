"""The power-law identification equals allantools' (Riley and Greenhall 2004), vectorised."""

import allantools
import numpy as np
import pytest

from noisevar.diagnostics.power_law import AVERAGING_FACTORS
from noisevar.errors import NoisevarError
from noisevar.numeric.noise_id import lag1_acf, noise_id


def _records() -> list[np.ndarray]:
    rng = np.random.default_rng(20261126)
    out = []
    for k in range(24):
        w = rng.normal(size=4096)
        kind = k % 4
        if kind == 1:  # random walk
            w = np.cumsum(w)
        elif kind == 2:  # flicker (1/f) by spectral shaping
            f = np.fft.rfftfreq(w.size)
            f[0] = f[1]
            w = np.fft.irfft(np.fft.rfft(w) / np.sqrt(f), n=w.size)
        elif kind == 3:  # differenced white (blue)
            w = np.diff(rng.normal(size=4097))
        out.append(w + rng.normal(0, 0.3 * k / 24, size=w.size))
    return out


@pytest.mark.parametrize("af", AVERAGING_FACTORS)
def test_noise_id_equals_allantools(af):
    for x in _records():
        ours = noise_id(x, af)
        theirs = int(allantools.autocorr_noise_id(x, af, data_type="phase")[0])
        assert ours == theirs


def test_lag1_acf_equals_allantools_to_rounding():
    for x in _records()[:6]:
        assert lag1_acf(x) == pytest.approx(allantools.ci.lag1_acf(x), rel=1e-10, abs=1e-12)


def test_constant_or_short_stretches_are_refused():
    with pytest.raises(NoisevarError):
        lag1_acf(np.ones(100))
    with pytest.raises(NoisevarError):
        noise_id(np.arange(40.0), 4)


@pytest.mark.parametrize("dmax", [1, 3])
def test_noise_id_with_the_allan_deviations_differencing_equals_allantools(dmax):
    # the Allan deviation's edf asks with dmax = 2 (ADEV) or 3 (HDEV)
    for x in _records()[:8]:
        for af in (1, 8):
            theirs = allantools.autocorr_noise_id(x, af, data_type="phase", dmin=0, dmax=dmax)[0]
            assert noise_id(x, af, dmax=dmax) == int(theirs)


def test_the_quadratic_removed_is_polyfits_to_rounding():
    from noisevar.numeric.noise_id import _less_quadratic

    rng = np.random.default_rng(8)
    for n in (30, 1001, 2**15):
        t = np.arange(n)
        x = rng.normal(size=n).cumsum() + 1e-3 * (t - n / 3) ** 2 + 40.0
        want = x - np.polyval(np.polyfit(t, x, 2), t)
        np.testing.assert_allclose(_less_quadratic(x), want, rtol=0, atol=1e-9 * np.abs(want).max())

"""The compiled kernels of noisevar.numeric.fir against their NumPy references."""

from __future__ import annotations

import numpy as np
import pytest

from noisevar.diagnostics import whiteness
from noisevar.numeric import _fir_numba, fir


@pytest.mark.parametrize("n", [21, 22, 40, 1023, 1025, 70_001])
def test_lagged_products_equal_the_dot_products(n):
    x = np.random.default_rng(n).normal(3.0, 2.0, n)
    out = np.empty(21)
    _fir_numba.lagged_products(x, 20, out)
    ref = np.array([np.dot(x[k:], x[: n - k]) for k in range(21)])
    np.testing.assert_allclose(out, ref, rtol=1e-12, atol=1e-12 * ref[0])


def test_sample_acf_is_the_same_with_and_without_the_kernel(monkeypatch):
    rng = np.random.default_rng(5)
    e = np.convolve(rng.normal(size=20_000), [1.0, 0.6, 0.2], mode="same")
    keep = rng.random(e.size) > 0.05
    compiled = whiteness.sample_acf(e, 20, keep)
    monkeypatch.setattr(fir, "USE_COMPILED", False)
    reference = whiteness.sample_acf(e, 20, keep)
    np.testing.assert_allclose(compiled, reference, rtol=1e-10, atol=1e-12)
    # MA(2) with taps 1, 0.6, 0.2: ρ1 = (0.6 + 0.12) / (1 + 0.36 + 0.04)
    assert compiled[0] == pytest.approx(0.72 / 1.4, abs=0.03)

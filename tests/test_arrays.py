"""The shared array helpers give the same numbers as NumPy."""

from __future__ import annotations

import numpy as np
from hypothesis import given, settings
from hypothesis import strategies as st
from hypothesis.extra.numpy import arrays

from noisevar._arrays import median_inplace
from noisevar.filters.selection import robust_noise_scale

finite = st.floats(-1e6, 1e6, allow_nan=False, allow_infinity=False)


@settings(max_examples=200)
@given(arrays(np.float64, st.integers(1, 60), elements=finite))
def test_median_inplace_equals_numpy_median(v):
    expected = np.median(v)
    assert median_inplace(v.copy()) == expected


@settings(max_examples=100)
@given(arrays(np.float64, st.integers(3, 80), elements=finite))
def test_robust_noise_scale_is_the_mad_of_second_differences(z):
    d2 = np.diff(z, n=2)
    expected = np.median(np.abs(d2 - np.median(d2))) / 0.6744897501960817 / np.sqrt(6.0)
    assert robust_noise_scale(z) == expected

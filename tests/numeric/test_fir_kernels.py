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


@pytest.mark.parametrize("span", [3, 5, 9, 11, 13, 21, 41, 81])
def test_symmetric_fir_adds_its_taps_in_order(span):
    # the kernel takes four taps per pass over its tile: each output must still be
    # d_1 ((z_{t-1} - z_t) + (z_{t+1} - z_t)) + ... added from k = 1 up, bit for bit
    rng = np.random.default_rng(span)
    z = rng.normal(size=3_000) * 10.0 ** rng.uniform(-3, 3, 3_000)
    d = fir.residual_sequence(span, 3)
    h = span // 2
    mid = z[h : z.size - h]
    ref = np.zeros(mid.size)
    for k in range(1, h + 1):
        ref = ref + d[h + k] * (
            (z[h - k : z.size - h - k] - mid) + (z[h + k : z.size - h + k] - mid)
        )
    out = np.empty(z.size - 2 * h)
    _fir_numba.symmetric_fir(z, d[h:].copy(), out, False)
    assert np.array_equal(out, ref)
    _fir_numba.symmetric_fir_squares(z, d[h:].copy(), out)
    assert np.array_equal(out, ref * ref)
    assert np.array_equal(fir.centred_fir(z, d), ref)  # the compiled path
    np.testing.assert_allclose(out, np.convolve(z, d, mode="valid") ** 2, rtol=1e-9, atol=1e-9)


def test_the_residual_filter_is_exactly_blind_to_an_offset_and_a_held_value(monkeypatch):
    """Differences to the centre sample: a held stretch gives exactly 0 at any level, and
    an integer offset changes no bit (issue 26: ties at 0 moved R under an offset)."""
    rng = np.random.default_rng(8)
    z = np.repeat(rng.integers(20, 26, 300), rng.integers(1, 90, 300)).astype(float)
    d = fir.residual_sequence(11, 3)
    for compiled in (True, False):
        monkeypatch.setattr(fir, "USE_COMPILED", compiled)
        e = fir.centred_fir(z, d)
        held = np.ptp(np.lib.stride_tricks.sliding_window_view(z, 11), axis=1) == 0
        assert held.sum() > 1000 and np.all(e[held] == 0.0)
        assert np.array_equal(fir.centred_fir(z + 32.0, d), e)
        assert np.all(fir.centred_fir(1.8 * z, d)[held] == 0.0)


@pytest.mark.parametrize("n", [1, 7, 24, 25, 26, 27, 1001])
def test_lagged_products_add_one_sample_at_a_time(n):
    """Four samples per pass over the lags: each lag's sum is still added in sample order."""
    rng = np.random.default_rng(n)
    x = rng.normal(size=n) * 10.0 ** rng.uniform(-50, 50)
    lags = 20
    out = np.empty(lags + 1)
    _fir_numba.lagged_products(x, lags, out)
    want = np.zeros(lags + 1)
    for k in range(min(lags + 1, n)):  # a running sum from 0, as the kernel's
        want[k] = np.cumsum(np.r_[0.0, x[: n - k] * x[k:]])[-1]
    assert out.tobytes() == want.tobytes()


@pytest.mark.parametrize("square", [False, True])
@pytest.mark.parametrize("kind", ["white", "held", "held+trend", "huge"])
def test_rounded_fir_screens_as_it_writes(kind, square, monkeypatch):
    """One pass (the kernel counts rounded_off's candidates): the same numbers as the two."""
    rng = np.random.default_rng(len(kind))
    z = rng.standard_normal(5000)
    if kind.startswith("held"):  # a quantised record: residuals at 0 and at rounding
        z = np.repeat(rng.integers(20, 26, 100), rng.integers(1, 90, 100)).astype(float)
        z = z + (1e-3 * np.arange(z.size) if kind == "held+trend" else 0.0)
    elif kind == "huge":
        z = z * 1e150  # squares near the float limit
    d = fir.residual_sequence(21, 3)
    ref = fir.rounded_off(fir.centred_fir(z, d, square=square), z, d, squared=square)
    for peak in (None, max(float(z.max()), -float(z.min()))):
        assert np.array_equal(fir.rounded_fir(z, d, square=square, peak=peak), ref)
    monkeypatch.setattr(fir, "USE_COMPILED", False)
    assert np.array_equal(fir.rounded_fir(z, d, square=square), ref)
    if kind == "held+trend":  # the screen found candidates, and some were zeroed
        assert np.count_nonzero(ref == 0) > np.count_nonzero(fir.centred_fir(z, d) == 0)


@pytest.mark.parametrize(
    "spans", [(11, 21, 41, 81), (81, 11, 41), (5,), (21, 13), (5, 9, 13, 17, 21)]
)
@pytest.mark.parametrize("kind", ["white", "held+trend"])
def test_rounded_fir_squares_equal_one_filter_at_a_time(spans, kind):
    """Every span's squares at once (each pair of taps formed once): the same numbers."""
    rng = np.random.default_rng(len(spans))
    z = rng.standard_normal(3000) * 7.0 + 1e3
    if kind == "held+trend":
        z = np.repeat(rng.integers(20, 26, 60), rng.integers(1, 90, 60)).astype(float)
        z = z + 1e-3 * np.arange(z.size)
    ds = [fir.residual_sequence(s, 3) / np.linalg.norm(fir.residual_sequence(s, 3)) for s in spans]
    ref = np.full((len(ds), z.size), -1.0)
    for d, row in zip(ds, ref, strict=True):
        h = d.size // 2
        fir.rounded_fir(z, d, row[h : z.size - h], square=True)
    got = np.full_like(ref, -1.0)
    assert fir.rounded_fir_squares(z, ds, got) is got
    assert np.array_equal(got, ref)

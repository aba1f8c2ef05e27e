"""Residual filters: the local-polynomial residual sequence and the centred filters that apply it.

A centred local polynomial (Savitzky-Golay) fit leaves the residual ``e = d * z`` with
``d`` the sequence of :func:`residual_sequence` (docs/algorithms.md §F5.1): ``auto``
estimates the noise from it and the diagnostics look through it. :func:`centred_fir` and
:func:`lagged_products` run the compiled kernels of :mod:`noisevar.numeric._fir_numba`
while :data:`USE_COMPILED` is true (and numba is installed), else their NumPy
references (the same numbers, to rounding; tested).
"""

from __future__ import annotations

from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

try:  # the compiled kernels (numba); np.convolve and einsum below are the reference
    from noisevar.numeric import _fir_numba
except ImportError:  # pragma: no cover - numba not installed
    _fir_numba = None  # type: ignore[assignment]

#: The one compiled/NumPy switch of the residual filters: the compiled kernels while this
#: is true (and numba is installed); false selects ``np.convolve`` and ``einsum``.
USE_COMPILED: bool = _fir_numba is not None


@lru_cache(maxsize=64)
def residual_sequence(span: int, order: int) -> NDArray:
    """Difference sequence ``δ - w`` of a centred local-polynomial (Savitzky-Golay) fit.

    Parameters
    ----------
    span : int
        Odd number of samples of each local fit.
    order : int
        Polynomial degree; the residual is blind to polynomials up to it.

    Returns
    -------
    ndarray, shape (span,)
        Read-only, exactly symmetric.
    """
    h = span // 2
    # w = row h of the hat matrix P = Q Q' of a polynomial fit over the centred window
    # (the Savitzky-Golay smoothing coefficients, as scipy.signal.savgol_coeffs)
    q, _ = np.linalg.qr(np.vander((np.arange(span, dtype=float) - h) / max(h, 1), order + 1))
    w = q @ q[h]
    d = -0.5 * (w + w[::-1])  # exactly symmetric (the fit is to about 1e-15)
    d[h] += 1.0
    d.setflags(write=False)
    return d


def centred_fir(
    x: NDArray, d: NDArray, out: NDArray | None = None, square: bool = False
) -> NDArray:
    """``e[t] = Σ_k d_k x[t + k]`` (squared if ``square``) at every centred sample.

    Parameters
    ----------
    x : ndarray, shape (n,)
    d : ndarray, shape (2h + 1,)
        A symmetric sequence (the compiled kernel reads its second half).
    out : ndarray, shape (n - 2h,), optional
        Written in place and returned.
    square : bool
        Write ``e²``.

    Returns
    -------
    ndarray, shape (n - 2h,)
    """
    if USE_COMPILED and _fir_numba is not None:
        out = np.empty(x.size - d.size + 1) if out is None else out
        half = d[d.size // 2 :].copy()
        if square:
            _fir_numba.symmetric_fir_squares(np.ascontiguousarray(x), half, out)
        else:
            _fir_numba.symmetric_fir(np.ascontiguousarray(x), half, out, False)
        return out
    e = np.convolve(x, d[::-1], mode="valid")
    if square:
        return np.multiply(e, e, out=e if out is None else out)
    if out is None:
        return e
    out[:] = e
    return out


def lagged_products(x: NDArray, lags: int) -> NDArray:
    """``Σ_i x_i x_{i+k}`` for ``k = 0..lags`` (compiled: one pass over ``x``).

    Parameters
    ----------
    x : ndarray, shape (n,)
    lags : int

    Returns
    -------
    ndarray, shape (lags + 1,)
    """
    if USE_COMPILED and _fir_numba is not None and x.size > lags:
        out = np.empty(lags + 1)
        _fir_numba.lagged_products(np.ascontiguousarray(x, dtype=float), lags, out)
        return out
    n = x.size
    # einsum: no BLAS threads (which thrash on a busy machine for these sizes)
    return np.array([float(np.einsum("i,i->", x[k:], x[: n - k])) for k in range(lags + 1)])

"""Residual filters: the local-polynomial residual sequence and the centred filters that apply it.

A centred local polynomial (Savitzky-Golay) fit leaves the residual ``e = d * z`` with
``d`` the sequence of :func:`residual_sequence` (docs/algorithms.md §F5.1): ``auto``
estimates the noise from it and the diagnostics look through it. :func:`centred_fir` and
:func:`lagged_products` run the compiled kernels of :mod:`noisevar.numeric._fir_numba`
while :data:`USE_COMPILED` is true (and numba is installed), else their NumPy
references (the same numbers, to rounding; tested).
"""

from __future__ import annotations

from collections.abc import Sequence
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import maximum_filter1d

try:  # the compiled kernels (numba); np.convolve and einsum below are the reference
    from noisevar.numeric import _fir_numba
except ImportError:  # pragma: no cover - numba not installed
    _fir_numba = None  # type: ignore[assignment]

#: The one compiled/NumPy switch of the residual filters: the compiled kernels while this
#: is true (and numba is installed); false selects ``np.convolve`` and ``einsum``.
USE_COMPILED: bool = _fir_numba is not None
#: The rounding of a record's floats, in units in the last place of its magnitude: a
#: residual (or a noise level's standard deviation) no larger than ``ROUNDING_ULPS`` ulps
#: of the largest sample it reads is float rounding, not noise. The residual of a held or
#: straight stretch is 0 in exact arithmetic and such rounding in floats, which an offset,
#: a scale or a trend moves (issue 26: a quantised temperature plus a trend gave a still
#: level of 1e-29; x1.8 moved R by 1.4 %).
ROUNDING_ULPS = 4.0


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
        A symmetric sequence that sums to zero (a residual sequence, blind to a constant;
        the compiled kernel reads its second half).
    out : ndarray, shape (n - 2h,), optional
        Written in place and returned.
    square : bool
        Write ``e²``.

    Returns
    -------
    ndarray, shape (n - 2h,)

    Notes
    -----
    Computed as ``Σ_k d_k ((x[t - k] - x[t]) + (x[t + k] - x[t]))`` over ``k >= 1``, taps
    added in order: an offset cancels exactly, and a held (constant) stretch gives exactly
    0 whatever its value, so that ties at 0 (a quantised record's held values) stay ties
    under an offset or a scale (issue 26).
    """
    if USE_COMPILED and _fir_numba is not None:
        out = np.empty(x.size - d.size + 1) if out is None else out
        half = d[d.size // 2 :].copy()
        if square:
            _fir_numba.symmetric_fir_squares(np.ascontiguousarray(x), half, out)
        else:
            _fir_numba.symmetric_fir(np.ascontiguousarray(x), half, out, False)
        return out
    h, n = d.size // 2, x.size
    mid = x[h : n - h]
    e = np.zeros(mid.size)
    for k in range(1, h + 1):
        e += d[h + k] * ((x[h - k : n - h - k] - mid) + (x[h + k : n - h + k] - mid))
    if square:
        return np.multiply(e, e, out=e if out is None else out)
    if out is None:
        return e
    out[:] = e
    return out


def rounded_fir(
    x: NDArray,
    d: NDArray,
    out: NDArray | None = None,
    square: bool = False,
    peak: float | None = None,
) -> NDArray:
    """``rounded_off(centred_fir(x, d, out, square), x, d, square)``, screened as it is written.

    Parameters
    ----------
    x, d, out, square : see :func:`centred_fir`.
    peak : float, optional
        ``max |x|``, when the caller has it.

    Returns
    -------
    ndarray, shape (n - 2h,)

    Notes
    -----
    :func:`rounded_off`'s first screen (outputs at or below the rounding of the largest
    ``|x|``) is counted by the compiled kernel as it writes them: on most records none,
    and no pass of its own; else :func:`rounded_off` as it is.
    """
    if not (USE_COMPILED and _fir_numba is not None) or x.size < d.size:
        return rounded_off(centred_fir(x, d, out, square), x, d, square)
    top = _rounding_unit(d) * (_peak(x) if peak is None else peak)
    out = np.empty(x.size - d.size + 1) if out is None else out
    half = d[d.size // 2 :].copy()
    limit = top * top if square else top
    if _fir_numba.symmetric_fir(np.ascontiguousarray(x), half, out, square, limit):
        rounded_off(out, x, d, square)
    return out


def rounded_fir_squares(
    x: NDArray, ds: Sequence[NDArray], out: NDArray, peak: float | None = None
) -> NDArray:
    """:func:`rounded_fir` of ``x`` squared for several sequences at once.

    Parameters
    ----------
    x : ndarray, shape (n,)
    ds : sequence of ndarray
        Symmetric sequences (see :func:`centred_fir`), ``2 h_s + 1`` taps each.
    out : ndarray, shape (len(ds), n)
        Row ``s`` takes sequence ``s``'s squared outputs at samples ``h_s .. n - h_s``
        (its other samples are not written); returned.
    peak : float, optional
        ``max |x|``, when the caller has it.

    Notes
    -----
    Compiled: one pass over the samples that every sequence reaches, each pair of taps'
    differences formed once for all the sequences
    (:func:`~noisevar.numeric._fir_numba.symmetric_firs_squares`; each sequence's taps
    added in its own order), and the single kernel at the shorter sequences' other
    samples: the same numbers as one :func:`rounded_fir` per sequence.
    """
    hs = [d.size // 2 for d in ds]
    n, top = x.size, max(hs)
    order = sorted(range(len(ds)), key=lambda s: -hs[s])  # the kernel's: longest first
    if not (USE_COMPILED and _fir_numba is not None) or n < 2 * top + 2 or len(ds) > 4:
        for d, h, row in zip(ds, hs, out, strict=True):
            rounded_fir(x, d, row[h : n - h], square=True, peak=peak)
        return out
    x = np.ascontiguousarray(x, dtype=float)
    peak = _peak(x) if peak is None else peak
    limits = np.empty(len(ds))
    halves = np.zeros((4, top + 1))  # the kernel's four rows
    for s, (d, h) in enumerate(zip(ds, hs, strict=True)):
        bound = _rounding_unit(d) * peak
        limits[s] = bound * bound
        halves[s, : h + 1] = d[h:]
    low = np.zeros(len(ds), dtype=np.int64)
    lows = np.zeros(len(ds), dtype=np.int64)
    _fir_numba.symmetric_firs_squares(
        x, halves[order + [s for s in range(4) if s >= len(ds)]], np.array(hs)[order], top,
        n - top, out, np.array(order), limits[order], lows,
    )  # fmt: skip
    low[order] = lows
    for s, h in enumerate(hs):
        if h < top:  # the samples the longest sequence does not reach, at both ends
            half = halves[s, : h + 1].copy()
            low[s] += _fir_numba.symmetric_fir(x[: top + h], half, out[s, h:top], True, limits[s])
            tail = out[s, n - top : n - h]
            low[s] += _fir_numba.symmetric_fir(x[n - top - h :], half, tail, True, limits[s])
        if low[s]:
            rounded_off(out[s, h : n - h], x, ds[s], True)
    return out


def _rounding_unit(d: NDArray) -> float:
    """:func:`rounded_off`'s bound per unit of ``max |x|``."""
    return ROUNDING_ULPS * np.finfo(float).eps * float(np.sqrt(np.dot(d, d)))


def _peak(x: NDArray) -> float:
    """``max |x|`` (from the largest and the least value: no ``|x|`` array)."""
    return max(float(np.max(x)), -float(np.min(x)))


def rounded_off(e: NDArray, x: NDArray, d: NDArray, squared: bool = False) -> NDArray:
    """``e = centred_fir(x, d)`` with the outputs at float rounding set to 0 (in place).

    Parameters
    ----------
    e : ndarray, shape (n - 2h,)
        The filter's outputs.
    x : ndarray, shape (n,)
        Its input.
    d : ndarray, shape (2h + 1,)
    squared : bool
        ``e`` holds the squared outputs.

    Returns
    -------
    ndarray
        ``e``, 0 where ``|e|`` is at most :data:`ROUNDING_ULPS` ulps of the largest
        ``|x|`` under the output's window, times ``|d|``.
    """
    h = d.size // 2
    if not e.size:
        return e
    unit = _rounding_unit(d)
    # candidates against the largest |x| of all (no window's is larger): on most records
    # none, and this one comparison is all it costs
    top = unit * _peak(x)
    idx = np.flatnonzero(e <= top * top if squared else np.abs(e) <= top)
    if not idx.size:
        return e
    if idx.size > e.size // 16:  # many (held values): every window's largest |x| at once
        local = maximum_filter1d(np.abs(x), d.size)[h : x.size - h][idx]
    else:
        local = np.abs(x[idx[:, None] + np.arange(d.size)]).max(axis=1)
    top = unit * local
    v = e[idx]
    e[idx[v <= top * top if squared else np.abs(v) <= top]] = 0.0
    return e


def centred_rows(rows: NDArray, x: NDArray, at: NDArray) -> NDArray:
    """``rows @ x`` for rows that each sum to zero, read from differences to ``x[at]``.

    Parameters
    ----------
    rows : ndarray, shape (m, k)
        Residual rows (of ``I - P`` for a fit that holds constants: each sums to zero).
    x : ndarray, shape (k,) or (r, k)
        Samples (one window per row of ``x`` when 2-D).
    at : ndarray of int, shape (m,)
        Each row's own sample in the window.

    Returns
    -------
    ndarray, shape (m,) or (r, m)

    Notes
    -----
    ``Σ_i r_i (x_i - x_at)``: as :func:`centred_fir`, an offset cancels exactly and a held
    stretch gives exactly 0.
    """
    x = np.asarray(x, dtype=float)
    ref = x[..., at]  # (m,) or (r, m)
    return np.einsum("mk,...mk->...m", rows, x[..., None, :] - ref[..., :, None])


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

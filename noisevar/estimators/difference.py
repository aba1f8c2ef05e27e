"""Difference estimators: Rice, second difference, Hall-Kay-Titterington, MAD peers.

One sequence ``d`` is one estimator (docs/algorithms.md §F1): the variance is
``mean((d * z)²) / sum(d²)`` over the valid part of the convolution, with
``n / sum_k ρ_k²`` effective degrees of freedom. The MAD peers are §F2. All of them
take many channels at once (``z`` of shape ``(k, n)``).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.estimators.results import VarianceEstimate, chi2_interval
from noisevar.estimators.spec import MethodSpec

MAD_TO_SIGMA = 1.0 / 0.6744897501960817
#: Asymptotic efficiency of the MAD scale estimator at the Gaussian (relative to the SD).
MAD_EFFICIENCY = 0.3675


def sequence_efficiency(d: ArrayLike) -> float:
    """``sum_k ρ_k²`` of a difference sequence: variance inflation over the Cramér-Rao floor.

    Parameters
    ----------
    d : array_like
        The sequence.

    Returns
    -------
    float
        1 for a delta (independent squares); 1.5 for Rice's ``[1, -1]``.
    """
    d = np.asarray(d, dtype=float)
    # ρ = (d ⋆ d) / sum(d²)
    ac = np.correlate(d, d, mode="full") / np.sum(d**2)
    return float(np.sum(ac**2))


def _zero_sum_unit(d: list[float]) -> NDArray:
    """Project a published (4-decimal) sequence onto sum 0, sum of squares 1.

    The printed order-3 values sum to 1e-4, which would leak an offset ``c`` into the
    estimate as ``(1e-4 c)²``.
    """
    a = np.asarray(d, dtype=float)
    a = a - a.mean()
    return a / np.sqrt(np.sum(a**2))


#: Hall-Kay-Titterington (1990) optimal difference sequences, orders 1-3.
HKT_SEQUENCES = {
    1: _zero_sum_unit([0.7071, -0.7071]),
    2: _zero_sum_unit([0.8090, -0.5000, -0.3090]),
    3: _zero_sum_unit([0.1942, 0.2809, 0.3832, -0.8582]),
}


def _estimates(
    method: str,
    variance: NDArray,
    dof: float,
    n_used: int,
    n_total: int,
    params: dict,
    notes: list[list[str]],
) -> list[VarianceEstimate]:
    """One result per channel (each with its own copy of ``params``)."""
    return [
        VarianceEstimate(
            method, float(v), chi2_interval(float(v), dof), n_used, n_total, dof, dict(params), nt
        )
        for v, nt in zip(variance, notes, strict=True)
    ]


def difference_variance(z: NDArray, d: ArrayLike) -> tuple[NDArray, int]:
    """``mean((d * z)²) / sum(d²)`` along the last axis, and the number of terms.

    Parameters
    ----------
    z : ndarray, shape (..., n)
        Samples.
    d : array_like, shape (L,)
        Difference sequence (``sum(d) = 0``).

    Returns
    -------
    variance : ndarray, shape (...)
    n_terms : int
        ``n - L + 1``.
    """
    d = np.asarray(d, dtype=float)
    # e_k = sum_j d_j z_{k+j}: an FIR with taps d reversed, valid part only. np.convolve per
    # channel: for these few taps it is about 4x faster than lfilter(axis=-1), and channels are few
    rows = np.reshape(z, (-1, z.shape[-1]))
    e = [np.convolve(r, d[::-1], mode="valid") for r in rows]
    e = (e[0] if len(e) == 1 else np.stack(e)).reshape(*z.shape[:-1], -1)
    # var = mean(e²) / sum(d²)
    return np.mean(e**2, axis=-1) / np.sum(d**2), e.shape[-1]


def _sequence_method(name: str, d: ArrayLike, description: str) -> MethodSpec:
    """The :class:`MethodSpec` of the difference estimator with sequence ``d``."""
    seq = np.asarray(d, dtype=float)
    eff = sequence_efficiency(seq)

    def func(z: NDArray, notes: list[list[str]]) -> list[VarianceEstimate]:
        var, m = difference_variance(z, seq)
        return _estimates(name, var, m / eff, m, z.shape[-1], {}, notes)

    return MethodSpec(name, description, "peer", func, (), vectorised=True, residual=lambda p: seq)


def _mad_diff(z: NDArray, notes: list[list[str]]) -> list[VarianceEstimate]:
    dz = np.diff(z, axis=-1)
    med = np.median(dz, axis=-1, keepdims=True)
    # σ = 1.4826 MAD(Δz) / sqrt(2)
    var = (np.median(np.abs(dz - med), axis=-1) * MAD_TO_SIGMA) ** 2 / 2.0
    if np.any(var == 0):
        raise NoisevarError(
            "mad-diff: at least half of the first differences are equal (quantised or "
            "repeated samples), so their median absolute deviation is 0 and says nothing "
            "about the noise; use rice or hkt3 instead"
        )
    dof = dz.shape[-1] * MAD_EFFICIENCY / 1.5
    return _estimates("mad-diff", var, dof, dz.shape[-1], z.shape[-1], {}, notes)


def _wavelet_mad(
    z: NDArray, notes: list[list[str]], wavelet: str = "db4"
) -> list[VarianceEstimate]:
    import pywt

    try:
        wav = pywt.Wavelet(wavelet)
    except ValueError:
        raise NoisevarError(f"unknown wavelet {wavelet!r}: try 'db4' or 'sym8'") from None
    _, detail = pywt.dwt(z, wav, mode="periodization", axis=-1)
    # σ = 1.4826 median|w| over the finest details
    sigma = np.median(np.abs(detail), axis=-1) * MAD_TO_SIGMA
    dof = detail.shape[-1] * MAD_EFFICIENCY
    n = z.shape[-1]
    return _estimates("wavelet-mad", sigma**2, dof, n, n, {"wavelet": wavelet}, notes)


METHODS: tuple[MethodSpec, ...] = (
    _sequence_method("rice", [1.0, -1.0], "Rice first difference mean(Δz²)/2"),
    _sequence_method("diff2", [1.0, -2.0, 1.0], "second difference mean((Δ²z)²)/6"),
    *(
        _sequence_method(
            f"hkt{k}", HKT_SEQUENCES[k], f"Hall-Kay-Titterington optimal difference, order {k}"
        )
        for k in (1, 2, 3)
    ),
    MethodSpec(
        "mad-diff",
        "median absolute deviation of first differences",
        "peer",
        _mad_diff,
        vectorised=True,
        assumes=("white", "identifiable", "gaussian"),
        moment=False,
    ),
    MethodSpec(
        "wavelet-mad",
        "Donoho-Johnstone MAD of finest wavelet details",
        "peer",
        _wavelet_mad,
        ("wavelet",),
        vectorised=True,
        assumes=("white", "identifiable", "gaussian"),
        moment=False,
    ),
)

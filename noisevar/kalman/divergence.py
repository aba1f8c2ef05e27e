"""Divergence and consistency: :class:`DivergenceCheck`, NIS / NEES, :func:`nis_band`.

A run is flagged, never hidden (docs/algorithms.md §G4).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy import stats


@dataclass(frozen=True)
class DivergenceCheck:
    """How a run is judged to have diverged (reported, never hidden).

    A run is flagged when

    * its state or covariance becomes NaN/infinite, or the innovation
      covariance is singular;
    * a diagonal element of ``P`` exceeds ``covariance_limit`` (default:
      ``1e6`` times the largest diagonal element of ``P0`` and of ``R``) —
      an exploding covariance;
    * the mean NIS over a window of ``window`` steps exceeds
      ``nis_factor · m``: the innovations are far larger than the filter
      believes (chi-square mean is ``m``);
    * with truth, the mean NEES over a window exceeds ``nis_factor · n``.

    Parameters
    ----------
    covariance_limit : float, optional
        Absolute limit on any diagonal element of ``P``.
    nis_factor : float
        How far above its chi-square mean a windowed NIS / NEES may go.
    window : int
        Window length for the NIS / NEES test.
    check_every : int
        How often (in steps) :func:`run_filter` checks finiteness and size
        of ``P`` while running.
    """

    covariance_limit: float | None = None
    nis_factor: float = 10.0
    window: int = 100
    check_every: int = 50


#: Matrix entries per chunk in :func:`quadratic_form_inverse` (~2 MB of float64).
_QF_CHUNK = 1 << 18


def quadratic_form_inverse(A: NDArray, v: NDArray) -> NDArray:
    """``vᵀ A⁻¹ v`` for stacks of symmetric positive-definite ``A`` (NIS, NEES).

    A Cholesky factorisation and forward substitution written element-wise
    over the stack (no LAPACK call per member). Non-finite or non-positive-definite
    members give NaN.

    Parameters
    ----------
    A : ndarray, shape (..., k, k)
        Symmetric positive-definite matrices.
    v : ndarray, shape (..., k)
        Vectors.

    Returns
    -------
    ndarray, shape (...)
    """
    lead = A.shape[:-2]
    if len(lead) >= 1 and lead[0] > 1 and A.size > _QF_CHUNK:
        # chunks along the first axis that fit in cache: the entries are
        # gathered with a stride of k*k, so cold memory would cost k*k passes
        step = max(1, _QF_CHUNK // A[0].size)
        return np.concatenate(
            [
                _quadratic_form_inverse(A[i : i + step], v[i : i + step])
                for i in range(0, lead[0], step)
            ]
        )
    return _quadratic_form_inverse(A, v)


def _quadratic_form_inverse(A: NDArray, v: NDArray) -> NDArray:
    k = A.shape[-1]
    # each matrix entry as its own contiguous array: element-wise arithmetic
    # without reductions over tiny axes
    a = {(i, j): np.ascontiguousarray(A[..., i, j]) for i in range(k) for j in range(i + 1)}
    L: dict[tuple[int, int], NDArray] = {}
    with np.errstate(invalid="ignore", divide="ignore"):
        for j in range(k):
            d = a[j, j].copy()
            for p in range(j):
                d -= L[j, p] * L[j, p]
            L[j, j] = np.sqrt(np.where(d > 0, d, np.nan))
            for i in range(j + 1, k):
                e = a[i, j].copy()
                for p in range(j):
                    e -= L[i, p] * L[j, p]
                L[i, j] = e / L[j, j]
        total = np.zeros(A.shape[:-2])
        y: list[NDArray] = []
        for i in range(k):
            e = np.array(v[..., i], dtype=float)
            for p in range(i):
                e -= L[i, p] * y[p]
            y.append(e / L[i, i])
            total += y[i] * y[i]
    return total


def check_block(
    x_rec: NDArray,
    P: NDArray,
    failed: NDArray,
    start: int,
    stop: int,
    cov_limit: float,
    div_step: NDArray,
    reasons: list[str],
) -> NDArray:
    """Flag runs that went non-finite or whose covariance exploded in steps [start, stop).

    Parameters
    ----------
    x_rec : ndarray, shape (N, B, n)
        Recorded states.
    P : ndarray, shape (B, n, n)
        Covariance after step ``stop - 1``.
    failed : ndarray of bool, shape (B,)
        Runs the filter reported failed (non positive definite in the Huber update).
    start, stop : int
        The block of steps.
    cov_limit : float
        Limit on any diagonal element of ``P``.
    div_step, reasons : ndarray, list of str
        Updated in place for newly flagged runs.

    Returns
    -------
    ndarray of bool, shape (B,)
        The runs flagged by this call.
    """
    block = x_rec[start:stop]  # (k, B, n)
    nonfinite = ~np.all(np.isfinite(block), axis=2)  # (k, B)
    pdiag = np.diagonal(P, axis1=1, axis2=2)
    bad_now = ~np.all(np.isfinite(pdiag), axis=1) | failed
    big = np.any(np.abs(pdiag) > cov_limit, axis=1)
    newly = (nonfinite.any(axis=0) | bad_now | big) & (div_step < 0)
    for b in np.flatnonzero(newly):
        if nonfinite[:, b].any():
            div_step[b] = start + int(np.argmax(nonfinite[:, b]))
            reasons[b] = f"state became NaN/infinite at step {div_step[b]}"
        elif bad_now[b]:
            div_step[b] = stop - 1
            reasons[b] = f"covariance became NaN/infinite or S singular by step {div_step[b]}"
        else:
            div_step[b] = stop - 1
            reasons[b] = (
                f"covariance exploded: max diag(P) = {np.max(pdiag[b]):.3g} > "
                f"{cov_limit:.3g} by step {div_step[b]}"
            )
    return newly


def check_consistency(
    stat: NDArray,
    dof: int,
    div: DivergenceCheck,
    div_step: NDArray,
    reasons: list[str],
    label: str,
    what: str,
) -> None:
    """Flag runs whose windowed mean NIS/NEES is far above its chi-square mean."""
    B, N = stat.shape
    w = max(1, min(int(div.window), N))
    finite = np.where(np.isfinite(stat), stat, 0.0)
    c = np.cumsum(np.concatenate([np.zeros((B, 1)), finite], axis=1), axis=1)
    mean_w = (c[:, w:] - c[:, :-w]) / w  # window ending at step j + w - 1
    limit = div.nis_factor * dof
    hi = stats.chi2.ppf(0.999, w * dof) / w
    for b in range(B):
        if div_step[b] >= 0:
            continue
        over = np.flatnonzero(mean_w[b] > limit)
        if over.size:
            j = int(over[0]) + w - 1
            div_step[b] = j
            reasons[b] = (
                f"{label} diverged: {what} far larger than the filter's covariance says "
                f"(mean {label} over {w} steps = {mean_w[b, over[0]]:.3g} at step {j}; "
                f"chi-square mean {dof}, 99.9 % bound {hi:.3g})"
            )


def nis_band(dof: int, window: int = 1, coverage: float = 0.95) -> tuple[float, float]:
    """Two-sided chi-square band for a mean of ``window`` NIS (or NEES) values.

    Parameters
    ----------
    dof : int
        Degrees of freedom of one value (``m`` for NIS, ``n`` for NEES).
    window : int
        Number of values averaged.
    coverage : float
        Probability inside the band.

    Returns
    -------
    (low, high) : tuple of float
    """
    a = (1.0 - coverage) / 2.0
    return (
        float(stats.chi2.ppf(a, dof * window) / window),
        float(stats.chi2.ppf(1.0 - a, dof * window) / window),
    )

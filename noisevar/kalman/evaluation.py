"""Metrics over batched filter runs, shared by the experiments and the benchmark.

Every function takes a batched :class:`~noisevar.kalman.result.FilterResult`
(leading Monte Carlo axis) and returns plain floats / dicts, with ``None``
where a number does not exist (a run that blew up), so the output is valid
JSON.
"""

from __future__ import annotations

import math
from collections import Counter
from collections.abc import Callable, Iterable
from concurrent.futures import ProcessPoolExecutor
from typing import Any

import numpy as np
from numpy.typing import NDArray

from noisevar.kalman.result import FilterResult


def finite_or_none(value: float) -> float | None:
    """``float(value)``, or ``None`` when it is NaN/infinite (JSON has no NaN).

    Parameters
    ----------
    value : float

    Returns
    -------
    float or None
    """
    value = float(value)
    return value if math.isfinite(value) else None


def pooled_rmse(
    result: FilterResult, states: tuple[int, ...], skip: int = 0, err: NDArray | None = None
) -> float | None:
    """RMSE pooled over runs and steps: ``sqrt(mean_{runs, k} Σ_{i in states} e_i²)``.

    Runs that blew up (NaN after their divergence step) are left out; ``None``
    when no run is left.

    Parameters
    ----------
    result : FilterResult
        A batched run with truth.
    states : tuple of int
        State components summed (``(0, 1)``: horizontal position).
    skip : int
        Leading steps left out.
    err : ndarray, optional
        ``result.state_error()`` when the caller already has it (it is the
        costly part for a large batch).

    Returns
    -------
    float or None
    """
    if err is None:
        err = result.state_error()
    err = err[..., skip:, :][..., list(states)]
    sq = np.sum(err**2, axis=-1)
    ok = np.all(np.isfinite(sq), axis=-1)
    if not ok.any():
        return None
    return finite_or_none(np.sqrt(np.mean(sq[ok])))


def r_diagonal(result: FilterResult) -> NDArray:
    """Diagonal of the ``R`` used at every step, shape ``(B, N, m)``."""
    return np.diagonal(result.R, axis1=-2, axis2=-1)


def r_tracking_error(result: FilterResult, R_true: NDArray, start: int) -> tuple[float, float]:
    """Mean ``|R̂_jj / R_jj - 1|`` and mean ``R̂_jj / R_jj - 1`` from step ``start`` on.

    Averaged over runs, steps ``k >= start`` and channels ``j``.

    Parameters
    ----------
    result : FilterResult
        Batched run.
    R_true : ndarray, shape (N, m, m)
        True covariance per step (aligned with the result's steps).
    start : int
        First step counted (after the change has settled).

    Returns
    -------
    (mean_abs_error, mean_bias) : tuple of float
    """
    est = r_diagonal(result)[:, start:]
    true = np.diagonal(R_true, axis1=-2, axis2=-1)[None, start:]
    ratio = est / true - 1.0
    return float(np.mean(np.abs(ratio))), float(np.mean(ratio))


def divergence_summary(result: FilterResult) -> dict[str, Any]:
    """How many runs diverged, and why (reasons grouped by kind).

    Parameters
    ----------
    result : FilterResult
        Batched run.

    Returns
    -------
    dict
        ``{"runs": k, "of": B, "reasons": {kind: count}, "example": first reason}``.
    """
    div = np.atleast_1d(result.diverged)
    reasons = result.divergence_reason
    reasons = [reasons] if isinstance(reasons, str) else list(reasons)
    kinds = Counter(r.split(":")[0] for r, d in zip(reasons, div, strict=True) if d)
    example = next((r for r, d in zip(reasons, div, strict=True) if d), "")
    return {
        "runs": int(div.sum()),
        "of": int(div.size),
        "reasons": dict(kinds),
        "example": example,
    }


def map_jobs(func: Callable[[Any], Any], items: Iterable[Any], jobs: int = 1) -> list[Any]:
    """``[func(item) for item in items]``, in ``jobs`` worker processes when ``jobs > 1``.

    Each filter of an experiment is one task (its runs are already batched
    inside the task), so two processes on a two-core machine roughly halve
    the wall time. Results are identical whatever ``jobs`` is: every task
    regenerates its seeded scenario.

    Parameters
    ----------
    func : callable
        A module-level function (it is pickled to the workers).
    items : iterable
        Task arguments.
    jobs : int
        Worker processes (1: run here, in order).

    Returns
    -------
    list
        Results in the order of ``items``.
    """
    items = list(items)
    if jobs <= 1 or len(items) <= 1:
        return [func(item) for item in items]
    with ProcessPoolExecutor(max_workers=min(jobs, len(items))) as pool:
        return list(pool.map(func, items))


def fmt(value: Any, width: int = 11) -> str:
    """A number for a text table (``-`` for None, 4 significant digits)."""
    if value is None:
        return "-".rjust(width)
    if isinstance(value, str):
        return value.rjust(width)
    v = float(value)
    if v != 0 and (abs(v) >= 1e5 or abs(v) < 1e-3):
        return f"{v:.4e}".rjust(width)
    return f"{v:.4g}".rjust(width)


def filter_summary(
    result: FilterResult, groups: dict[str, tuple[int, ...]] | None
) -> dict[str, Any]:
    """One row of a filter table: RMSE per state group (with truth), mean NIS, divergence.

    Uses :mod:`noisevar.kalman.evaluation`; NIS is chi-square with ``m``
    degrees of freedom when the filter is consistent, so its mean should be
    close to the number of measured channels.

    Parameters
    ----------
    result : FilterResult
    groups : dict of str to tuple of int, optional
        Label to state indices, for an RMSE per group (needs the truth).

    Returns
    -------
    dict
    """
    row: dict[str, Any] = {"filter": result.strategy}
    batched = result if result.batched else None
    if groups and result.truth is not None and batched is not None:
        for label, states in groups.items():
            row[f"RMSE {label}"] = pooled_rmse(batched, states)
    nis = np.asarray(result.nis, dtype=float)
    row["mean NIS"] = float(np.nanmean(nis)) if np.isfinite(nis).any() else float("nan")
    row["channels m"] = int(result.innovation.shape[-1])
    div = divergence_summary(batched) if batched is not None else None
    if div is not None:
        row["diverged"] = f"{div['runs']}/{div['of']}: {div['example']}" if div["runs"] else "no"
    else:
        row["diverged"] = str(result.divergence_reason or "no")
    return row

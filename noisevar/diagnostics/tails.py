"""Tails of the noise seen through a residual filter (docs/algorithms.md §E1)."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

#: A tail index below this means the fourth moment may not exist (Student-t 3 dof: 3).
TAIL_INDEX_MIN = 4.0
#: Noise kurtosis above which the noise counts as heavy-tailed (Gaussian: 3, Laplace: 6).
HEAVY_KURTOSIS = 4.0


def heavy_tails(kurtosis: float) -> bool:
    """Whether noise of this kurtosis is beyond a Gaussian interval's assumption."""
    return bool(kurtosis > HEAVY_KURTOSIS)


def unreliable_tail(alpha: float | None) -> bool:
    """Whether a tail index ``alpha`` (:func:`tail_index`) leaves no finite fourth moment:
    no variance interval can then be trusted."""
    return alpha is not None and alpha < TAIL_INDEX_MIN


def noise_kurtosis(e: NDArray, d: NDArray) -> float:
    """Kurtosis of iid noise ``v`` from its residual ``e = d * v`` (3 for Gaussian noise).

    Parameters
    ----------
    e : ndarray
        Residual samples (zero mean).
    d : ndarray
        The residual filter.

    Returns
    -------
    float

    Notes
    -----
    For ``e = d * v`` with ``Σ d² = 1``, ``κ_e - 3 = (κ_v - 3) Σ d⁴``: the filter
    averages the tails away, and this undoes it.
    """
    peak = float(np.max(np.abs(e))) if e.size else 0.0
    if not peak > 0.0 or not np.isfinite(peak):
        return 3.0
    x = e / peak  # the kurtosis is scale-free: keep the fourth powers in range
    return kurtosis_from_moments(float(np.mean(x * x)), float(np.mean((x * x) ** 2)), d)


def kurtosis_from_moments(m2: float, m4: float, d: NDArray) -> float:
    """:func:`noise_kurtosis` from the residual's second and fourth moments (any common scale)."""
    if not (m2 * m2 > 0 and np.isfinite(m2) and np.isfinite(m4)):  # m2² may underflow to 0
        return 3.0
    u = d / np.sqrt(np.dot(d, d))
    # m2² can underflow (a residual at float rounding but for a few samples): in two steps
    ratio = m4 / m2**2 if m2 * m2 > 0.0 else (m4 / m2) / m2
    # κ_v = 3 + (κ_e - 3) / Σ d⁴
    return float(max(3.0 + (ratio - 3.0) / np.sum(u**4), 1.0))


def tail_index(e: NDArray) -> float | None:
    """Hill's estimate of the tail index of ``|e|`` from its largest ``sqrt(n)`` values.

    Returns None for fewer than 400 samples. A Gaussian gives about 6 at the sizes
    used here; Student-t with ``ν`` dof gives about ``ν``.
    """
    n = e.size
    if n < 400:
        return None
    k = int(np.sqrt(n))
    top = np.partition(np.abs(e), n - k - 1)[n - k - 1 :]
    floor = top.min()
    logs = np.log(top[top > floor] / floor) if floor > 0 else np.array([])
    if logs.size == 0 or np.mean(logs) <= 0:
        return None
    # α = 1 / mean(log(x_(i) / x_(k+1)))
    return float(1.0 / np.mean(logs))

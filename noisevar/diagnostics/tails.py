"""Tails of the noise seen through a residual filter (docs/algorithms.md §E1)."""

from __future__ import annotations

from statistics import NormalDist  # no scipy on the estimate's path

import numpy as np
from numpy.typing import NDArray

#: A tail index below this means the fourth moment may not exist (Student-t 3 dof: 3).
TAIL_INDEX_MIN = 4.0
#: Noise kurtosis above which the noise counts as heavy-tailed (Gaussian: 3, Laplace: 6).
HEAVY_KURTOSIS = 4.0
#: Kurtosis below which iid samples count as light-tailed: a sample variance's variance,
#: ``σ⁴ (κ - 1) / n``, as far below the Gaussian's (κ = 3) as :data:`HEAVY_KURTOSIS` puts
#: it above (1.5x): ``1 + 2 / 1.5 = 2.33`` (uniform or quantised noise 1.8, a sine 1.5,
#: a square wave 1).
LIGHT_KURTOSIS = 1.0 + 4.0 / (HEAVY_KURTOSIS - 1.0)
#: The noise kurtosis read off a residual (:func:`noise_kurtosis`) under
#: ``3 - LIGHT_SE / sqrt(n)`` is measurably lighter-tailed than Gaussian (uniform: 1.8).
#: Measured: Gaussian noise reads 2.32-3.4 at n = 300 and 2.92 at least at n = 10,000
#: (40 seeds), uniform noise 2.03 at most at n = 300.
LIGHT_SE = 16.0
#: Two-sided level of the test that a sample's kurtosis is a Gaussian's at its size.
KURTOSIS_ALPHA = 0.01
#: Fewest samples :func:`tails_shape` tests light tails on (as ``scipy.stats.kurtosistest``,
#: whose normal approximation needs 20).
KURTOSIS_MIN_N = 20


def heavy_tails(kurtosis: float) -> bool:
    """Whether noise of this kurtosis is beyond a Gaussian interval's assumption."""
    return bool(kurtosis > HEAVY_KURTOSIS)


def tails_shape(n: int, kurtosis: float) -> str:
    """The tails of ``n`` iid samples of this kurtosis: ``"heavy"``, ``"light"`` or
    ``"gaussian"``.

    Parameters
    ----------
    n : int
        Samples (e.g. a Kalman filter's standardised innovations).
    kurtosis : float
        Their kurtosis ``b2 = m4 / m2²`` (3 for Gaussian samples).

    Returns
    -------
    str

    Notes
    -----
    Heavy: :func:`heavy_tails`. Light: below :data:`LIGHT_KURTOSIS` and below a Gaussian
    sample's ``b2`` at ``n`` by more than the two-sided :data:`KURTOSIS_ALPHA` normal
    bound, on its exact mean ``3 (n-1)/(n+1)`` and variance
    ``24 n (n-2)(n-3) / ((n+1)² (n+3)(n+5))`` (the first step of Anscombe and Glynn's
    test; ``b2``'s lower tail is shorter than the normal's, so the bound is on the safe
    side; ``scipy.stats.kurtosistest``'s cube-root step gives a positive statistic to a
    sine's 1.5 at 2,000 samples). A Gaussian's sample kurtosis falls below 2.33 in short
    records (its sd is about ``sqrt(24 / n)``). Fewer than :data:`KURTOSIS_MIN_N`
    samples: never light.
    """
    if heavy_tails(kurtosis):
        return "heavy"
    if kurtosis >= LIGHT_KURTOSIS or n < KURTOSIS_MIN_N:
        return "gaussian"
    mean = 3.0 * (n - 1) / (n + 1)
    var = 24.0 * n * (n - 2) * (n - 3) / ((n + 1) ** 2 * (n + 3) * (n + 5))
    bound = NormalDist().inv_cdf(1.0 - KURTOSIS_ALPHA / 2.0)
    return "light" if (kurtosis - mean) / np.sqrt(var) < -bound else "gaussian"


def light_noise(n: int, kurtosis: float) -> bool:
    """Whether noise of this kurtosis, read off a residual of ``n`` samples
    (:func:`noise_kurtosis`), is measurably lighter-tailed than Gaussian (the verdict's
    rule: its spread is the deconvolved kurtosis's, wider than iid samples' of
    :func:`tails_shape`)."""
    return bool(kurtosis < 3.0 - LIGHT_SE / np.sqrt(max(n, 1)))


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

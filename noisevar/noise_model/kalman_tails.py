"""The Kalman fit's Gaussian assumption checked on its innovations (docs/algorithms.md §E6).

The maximum-likelihood fit assumes Gaussian noise; its interval is the Gaussian Fisher
information's. A few glitches that hold most of ``r`` break that assumption: the interval
is then widened for the innovations' kurtosis (the quasi-likelihood correction the
estimate's interval makes, §E1) and a note says so.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from noisevar.estimators.interval import heavy_tails, tail_index, unreliable_tail


def innovation_kurtosis(nu: NDArray) -> float:
    """Kurtosis of the standardised innovations ``nu`` (3 for Gaussian noise)."""
    peak = float(np.max(np.abs(nu))) if nu.size else 0.0
    if not peak > 0.0 or not np.isfinite(peak):
        return 3.0
    x = (nu / peak) ** 2  # scale-free: keep the fourth powers in range
    m2 = float(np.mean(x))
    return float(np.mean(x * x) / m2**2) if m2 > 0 else 3.0


def tails_widening(nu: NDArray) -> tuple[float, str | None, float]:
    """The factor on the fit's log-parameter covariance, the note (None: Gaussian enough) and
    the innovations' kurtosis.

    Parameters
    ----------
    nu : ndarray
        Standardised innovations of the fitted filter.

    Returns
    -------
    factor : float
        ``max(1, (κ - 1) / 2)``: a variance's sampling variance is ``(κ - 1) σ⁴ / n``,
        ``2 σ⁴ / n`` for Gaussian noise; 1 unless the innovations are heavy-tailed.
    note : str or None
    kurtosis : float

    Notes
    -----
    With ``m`` glitches that hold most of ``r``, ``κ ≈ n / m``, so the widened interval is the
    glitch count's Poisson one: ``r`` is as uncertain as the number of glitches in the record.
    Heavy: :func:`~noisevar.estimators.interval.heavy_tails`, the estimate's rule.
    """
    kurt = innovation_kurtosis(nu)
    if not heavy_tails(kurt):
        return 1.0, None, kurt
    factor = (kurt - 1.0) / 2.0
    alpha = tail_index(nu)
    unreliable = (
        f"; their tail index {alpha:.1f} is too low for a finite fourth moment (or a few "
        "glitches of one size): even the widened interval is unreliable"
        if unreliable_tail(alpha)
        else ""
    )
    return (
        factor,
        (
            f"the innovations are heavy-tailed (kurtosis {kurt:.3g}; Gaussian noise gives 3): the "
            "fit's Gaussian assumption is broken, and r counts the outlying samples (glitches, "
            "bursts) as noise, which may hold most of it; the intervals are widened "
            f"x{np.sqrt(factor):.2g} for the kurtosis{unreliable}. Check the estimate's core "
            "variance, and gate the outliers or use a robust filter"
        ),
        kurt,
    )

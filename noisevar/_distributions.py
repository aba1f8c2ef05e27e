"""The few normal and χ² functions the estimate path needs, from :mod:`scipy.special`.

``scipy.stats`` costs about 100 MB and 1.8 s to import; these are the formulas
``scipy.stats`` itself evaluates (``chi2.ppf`` is ``2 gammaincinv(ν/2, q)``,
``chi2.sf`` is ``chdtrc``, ``norm.cdf`` is ``ndtr``), so they give the same floats
(tests/test_imports.py compares them with ``scipy.stats``).
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike
from scipy import special

_SQRT_2PI = np.sqrt(2 * np.pi)


def chi2_ppf(q: ArrayLike, df: ArrayLike) -> np.ndarray | float:
    """Quantile ``q`` of χ²(``df``), as ``scipy.stats.chi2.ppf`` (NaN where undefined)."""
    q = np.asarray(q, dtype=float)
    df = np.asarray(df, dtype=float)
    ok = (df > 0) & (q >= 0) & (q <= 1)
    with np.errstate(invalid="ignore"):
        # χ²_q(ν) = 2 P⁻¹(ν/2, q), P the regularised lower incomplete gamma function
        out = np.where(ok, 2 * special.gammaincinv(df / 2, q), np.nan)
    return out[()] if out.ndim == 0 else out


def chi2_sf(x: float, df: float) -> float:
    """``P(X > x)`` for ``X ~ χ²(df)``, as ``scipy.stats.chi2.sf`` (NaN where undefined)."""
    if not df > 0 or math.isnan(x):
        return float("nan")
    if x <= 0:
        return 1.0
    return float(special.chdtrc(df, x))


def chi2_pdf(x: float, df: float) -> float:
    """Density of χ²(``df``) at ``x > 0``, as ``scipy.stats.chi2.pdf``."""
    # f(x) = x^(ν/2-1) e^(-x/2) / (2^(ν/2) Γ(ν/2)), in logs
    log_f = special.xlogy(df / 2.0 - 1, x) - x / 2.0 - special.gammaln(df / 2.0)
    return float(np.exp(log_f - (np.log(2) * df) / 2.0))


def norm_cdf(x: float) -> float:
    """Standard normal distribution function, as ``scipy.stats.norm.cdf``."""
    return float(special.ndtr(x))


def norm_pdf(x: float) -> float:
    """Standard normal density, as ``scipy.stats.norm.pdf``."""
    # φ(x) = exp(-x²/2) / sqrt(2π)
    return float(np.exp(-(x**2) / 2.0) / _SQRT_2PI)

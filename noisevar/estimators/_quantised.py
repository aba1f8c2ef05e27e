"""Quantised records at low noise: the rounding error ``auto``'s residual misses (§E3).

On a grid of step ``Δ`` with noise ``σ`` below about ``Δ/2``, the mean rounding error
``b(c)`` follows the clean signal ``c``; where the signal moves slowly against ``Δ``
the residual filter removes it with the signal. :func:`quantisation_correction` models
what the residual sees from the record's local speed and solves for ``σ``
(docs/algorithms.md §E3).
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, replace
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy import optimize

from noisevar.estimators.auto import residual_sequence
from noisevar.estimators.results import VarianceEstimate

#: Corrected only below this noise standard deviation, in steps: above it the part of
#: the rounding error the residual can miss is under 1e-4 of the error variance.
QUANT_MAX_SIGMA = 0.45
#: Harmonics of the mean rounding error ``b`` in the model.
HARMONICS = 64
#: Samples of the straight-line fit that gives the signal's local speed.
SLOPE_SPAN = 321
#: At most this many positions enter the model (in :data:`PIECES` evenly spread runs).
MAX_POSITIONS = 1 << 16
#: The model takes the signal's offsets within a step as uniform: only when the signal
#: travels at least this many steps over the record.
MIN_TRAVEL = 10.0
PIECES = 32
#: Frequencies (cycles per sample, 0 to 0.5) of the tabulated residual-filter gain.
_FREQ = np.linspace(0.0, 0.5, 2049)


@dataclass(frozen=True)
class QuantCorrection:
    """What the correction found.

    Attributes
    ----------
    sigma : float
        The noise standard deviation before rounding, in grid steps.
    factor : float
        The error variance over what the residual saw (1 when not applied).
    travel : float
        Steps the signal travels over the record.
    """

    sigma: float
    factor: float
    travel: float

    @property
    def applied(self) -> bool:
        """The signal travels enough steps for the model (:data:`MIN_TRAVEL`)."""
        return self.travel >= MIN_TRAVEL


@lru_cache(maxsize=16)
def _gain(span: int, order: int) -> NDArray:
    """``|H(f)|² / Σh²`` of the residual sequence at :data:`_FREQ`."""
    h = residual_sequence(span, order)
    j = np.arange(span) - span // 2
    return np.abs(np.exp(-2j * np.pi * np.outer(_FREQ, j)) @ h) ** 2 / np.sum(h * h)


def _pieces(n: int) -> list[tuple[int, int]]:
    """The positions ``[a, b)`` the model averages over (each ``SLOPE_SPAN // 2`` from an end)."""
    r = SLOPE_SPAN // 2
    inner = n - 2 * r
    if inner <= MAX_POSITIONS:
        return [(r, n - r)]
    size = MAX_POSITIONS // PIECES
    step = (inner - size) // (PIECES - 1)
    return [(r + i * step, r + i * step + size) for i in range(PIECES)]


def harmonic_gains(
    read: Callable[[int, int], NDArray], n: int, lsb: float, span: int, order: int
) -> tuple[NDArray, float] | None:
    """``A_m``: the residual's mean gain at ``m`` times the signal's local speed, m = 1..M.

    Parameters
    ----------
    read : callable
        ``read(a, b)`` returns samples ``a .. b`` of the record.
    n : int
        Samples in the record.
    lsb : float
        The grid step.
    span, order : int
        The residual sequence (:func:`noisevar.estimators.auto.residual_sequence`).

    Returns
    -------
    gains : ndarray, shape (HARMONICS,)
    speed : float
        The mean local speed, in steps per sample.
    None when the record is too short.
    """
    if n < 2 * SLOPE_SPAN:
        return None
    r = SLOPE_SPAN // 2
    t = np.arange(SLOPE_SPAN, dtype=float) - r
    slope = t / np.sum(t * t)  # v = Σ t x / Σ t²: the least-squares slope
    m = np.arange(1, HARMONICS + 1)
    gain = _gain(span, order)
    total, count, speed = np.zeros(HARMONICS), 0, 0.0
    for a, b in _pieces(n):
        x = read(a - r, b + r) / lsb
        v = np.abs(np.convolve(x, slope[::-1], mode="valid"))
        f = np.outer(v, m) % 1.0  # harmonic m of b(c) at frequency m v (aliased)
        total += np.interp(np.minimum(f, 1.0 - f), _FREQ, gain).sum(axis=0)
        count += v.size
        speed += float(v.sum())
    return total / count, speed / count


def _missed(s: float, gains: NDArray) -> float:
    """Σ_m β_m² (1 - A_m) / 2 in steps², with σ = ``s`` steps."""
    m = np.arange(1, HARMONICS + 1)
    # β_m = Δ/(π m) exp(-2π² m² σ²/Δ²): the harmonics of b(c) = E[Q(c + n)] - c
    beta = np.exp(-2.0 * np.pi**2 * m**2 * s**2) / (np.pi * m)
    return float(np.sum(beta**2 * (1.0 - gains)) / 2.0)


def solve_sigma(seen: float, gains: NDArray) -> float:
    """``σ`` (in steps) such that ``σ² + 1/12 - missed(σ) = seen`` (``seen`` in steps²)."""

    # f(σ) = σ² + 1/12 - Σ β_m²(1 - A_m)/2 - seen: increasing in σ
    def f(s: float) -> float:
        return s * s + 1.0 / 12.0 - _missed(s, gains) - seen

    if f(0.0) >= 0.0:
        return 0.0
    hi = np.sqrt(max(seen, 1.0 / 12.0)) + 1.0
    return float(optimize.brentq(f, 0.0, hi, xtol=1e-12, rtol=1e-12))


def quantisation_correction(
    read: Callable[[int, int], NDArray],
    n: int,
    lsb: float,
    seen: float,
    span: int,
    order: int,
) -> QuantCorrection | None:
    """The correction for a quantised record whose residual saw ``seen`` (§E3).

    Parameters
    ----------
    read : callable
        ``read(a, b)`` returns samples ``a .. b``.
    n : int
        Samples in the record.
    lsb : float
        The grid step found in the record.
    seen : float
        The variance the residual measured.
    span, order : int
        The residual sequence used.

    Returns
    -------
    QuantCorrection or None
        None when the noise is above :data:`QUANT_MAX_SIGMA` steps (nothing to correct)
        or the record is too short.

    Notes
    -----
    With the offsets of the signal within a step taken as uniform, the error variance
    is ``σ² + Δ²/12`` and the residual sees it less ``Σ β_m² (1 - A_m) / 2``.
    """
    x = seen / lsb**2
    if not (np.isfinite(x) and 0.0 <= x < QUANT_MAX_SIGMA**2 + 1.0 / 12.0):
        return None
    got = harmonic_gains(read, n, lsb, span, order)
    if got is None:
        return None
    gains, speed = got
    s = solve_sigma(x, gains)
    # the error variance: σ² + Δ²/12 (offsets uniform within a step)
    truth = s * s + 1.0 / 12.0
    travel = speed * n
    factor = truth / x if x > 0 and travel >= MIN_TRAVEL else 1.0
    return QuantCorrection(sigma=s, factor=factor, travel=travel)


def apply_correction(result: VarianceEstimate, corr: QuantCorrection) -> VarianceEstimate:
    """``result`` with the variance, its interval and the core scaled, and a note.

    The note speaks in grid steps (the record may have been scaled by a power of two).
    """
    if not corr.applied:
        note = (
            f"the noise is small against the grid step (about {corr.sigma:.2f} of a step) and "
            f"the signal crosses only {corr.travel:.1f} steps: part of the rounding error is a "
            "bias that follows the signal, not in the variance (docs/algorithms.md §E3)"
        )
        return replace(result, notes=[*result.notes, note])
    k = corr.factor
    core = None if result.core_variance is None else result.core_variance * k
    note = (
        f"the noise is small against the grid step (about {corr.sigma:.2f} of a step): the "
        "rounding error partly follows the signal and the residual misses that part, so the "
        f"variance was multiplied by {k:.4f} (docs/algorithms.md §E3)"
    )
    lo, hi = result.ci95
    return replace(
        result,
        variance=result.variance * k,
        ci95=(lo * k, hi * k),
        core_variance=core,
        notes=[*result.notes, note],
    )

"""Which power-law noise dominates at each averaging factor (lag-1 autocorrelation).

Names for a measured quantity (allantools' phase data): α = 2 white, 1 flicker, 0 random
walk, -1 flicker walk, -2 random run (docs/algorithms.md §E4).

The identification is Riley and Greenhall's (2004), as ``allantools.autocorr_noise_id``
computes it for phase data; allantools' lag-1 autocorrelation is a Python loop (0.2 s
per 2^17 samples), so :func:`lag1_acf` and :func:`noise_id` are the same equations
vectorised (equal to allantools' to rounding: tests/diagnostics/test_power_law.py).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError

#: Averaging factors probed.
AVERAGING_FACTORS = (1, 4, 16, 64)
#: At most this many samples are used (the identification is costly on long records).
POWER_LAW_MAX = 2**17
#: At least this many averaged samples per factor.
POWER_LAW_MIN = 64

NAMES = {2: "white", 1: "flicker", 0: "random walk", -1: "flicker walk", -2: "random run"}


def power_law_types(z: NDArray) -> tuple[tuple[int, int], ...]:
    """``(averaging factor, α)`` of the dominant power-law noise at each factor.

    Parameters
    ----------
    z : ndarray
        Uniformly sampled record (the first :data:`POWER_LAW_MAX` samples are used).

    Returns
    -------
    tuple of (int, int)
        Empty when the record is too short.
    """
    x = np.asarray(z[:POWER_LAW_MAX], dtype=float)
    x = (x - x.mean()) / (np.std(x) or 1.0)  # the statistics are scale-free
    out = []
    for af in AVERAGING_FACTORS:
        if x.size // af < POWER_LAW_MIN:
            break
        out.append((af, max(-2, min(2, noise_id(x, af)))))
    return tuple(out)


def lag1_acf(x: NDArray) -> float:
    """Lag-1 autocorrelation, Riley and Greenhall (2004) eq. (2).

    Raises
    ------
    NoisevarError
        When ``x`` is constant (no autocorrelation is defined).
    """
    e = x - x.mean()
    # sums of products without BLAS: its threads, woken for one product on a busy
    # machine, cost more than the product (and their split changes its last bits)
    b = float(np.einsum("i,i->", e, e))
    if not b > 0.0:
        raise NoisevarError("power-law identification failed: a constant stretch.")
    return float(np.einsum("i,i->", e[:-1], e[1:])) / b


def noise_id(x: NDArray, af: int, dmax: int = 2) -> int:
    """The dominant power-law exponent α of phase data ``x`` at averaging factor ``af``.

    Notes
    -----
    Riley and Greenhall (2004): decimate by ``af``, remove a quadratic, then difference
    ``d`` times until ``ρ = r1 / (1 + r1) < 0.25`` (or ``d = dmax``), ``r1`` the lag-1
    autocorrelation; ``α = 2 - round(2ρ) - 2d`` (``allantools.autocorr_noise_id``'s
    ``alpha_int`` for phase data).
    """
    x = np.asarray(x[::af], dtype=float)
    if x.size < 30:
        raise NoisevarError(f"power-law identification failed: {x.size} samples (needs 30).")
    t = np.arange(x.size)
    x = x - np.polyval(np.polyfit(t, x, 2), t)
    d = 0
    while True:
        r1 = lag1_acf(x)
        if not r1 > -1.0:
            raise NoisevarError("power-law identification failed: an alternating stretch.")
        rho = r1 / (1.0 + r1)
        if rho < 0.25 or d >= dmax:
            return int(-1.0 * np.round(2 * rho) - 2.0 * d) + 2
        x = np.diff(x)
        d += 1


def describe(types: tuple[tuple[int, int], ...]) -> str:
    """Plain words: ``"white at 1 sample, flicker at 4-16 samples"``."""
    parts: list[tuple[int, int, int]] = []  # (alpha, first af, last af)
    for af, alpha in types:
        if parts and parts[-1][0] == alpha:
            parts[-1] = (alpha, parts[-1][1], af)
        else:
            parts.append((alpha, af, af))
    words = []
    for alpha, a, b in parts:
        span = f"{a} sample{'s' if a > 1 else ''}" if a == b else f"{a}-{b} samples"
        words.append(f"{NAMES[alpha]} at {span}")
    return ", ".join(words)

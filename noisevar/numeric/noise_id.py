"""Riley and Greenhall's (2004) lag-1 autocorrelation noise identification, vectorised.

The same equations as ``allantools.autocorr_noise_id`` for phase data; allantools'
lag-1 autocorrelation is a Python loop (0.2 s per 2^17 samples). The two agree on every
test record (tests/diagnostics/test_power_law.py). Used by the diagnostics (which
coloured noise) and by the Allan deviation's Greenhall edf (which noise at each tau).
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError


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


def _less_quadratic(x: NDArray) -> NDArray:
    """``x`` less its least-squares quadratic in the sample index (as ``np.polyfit``'s).

    Projected on polynomials orthogonal over the samples (a constant, the centred index,
    its square less its mean): three sums, where ``np.polyfit``'s least-squares solver
    spends 40x longer on a long record; the same fit, to rounding.
    """
    u = np.linspace(-1.0, 1.0, x.size)  # the index, centred and scaled
    u2 = u * u
    u2 -= u2.mean()
    u2 -= u * (np.einsum("i,i->", u2, u) / np.einsum("i,i->", u, u))  # exactly orthogonal
    out = x - x.mean()
    for p in (u, u2):
        out -= p * (np.einsum("i,i->", out, p) / np.einsum("i,i->", p, p))
    return out


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
    x = _less_quadratic(x)
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

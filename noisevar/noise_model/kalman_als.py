"""Autocovariance least squares (:func:`noisevar.noise_model.kalman_fit.fit_kalman`'s
``method="als"``): a fixed-gain predictor's innovations, their autocovariances per unit q
and r, and the iterated fit (docs/algorithms.md §E6 *ALS*)."""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.optimize
import scipy.signal
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.noise_model._steady import steady_state


def als_columns(F: NDArray, hv: NDArray, Q1: NDArray, Kp: NDArray, lags: int) -> NDArray:
    """Innovation autocovariances per unit q and per unit r of the filter with predictor gain Kp."""
    Abar = F - np.outer(Kp, hv)
    # P = Abar P Abar' + q Q1 + r Kp Kp'  (stationary prediction error)
    Pq = scipy.linalg.solve_discrete_lyapunov(Abar, Q1)
    Pr = scipy.linalg.solve_discrete_lyapunov(Abar, np.outer(Kp, Kp))
    cols = np.empty((lags, 2))
    row = hv.copy()  # h' Abar^j
    prev = None
    for j in range(lags):  # lags <= ~50 small matrix products
        # C_0 = h'P h + r;  C_j = h'Abar^j P h - h'Abar^(j-1) Kp r
        cols[j, 0] = row @ Pq @ hv
        cols[j, 1] = row @ Pr @ hv + (1.0 if j == 0 else -(prev @ Kp))
        prev, row = row, row @ Abar
    return cols


def innovations_lti(zc: NDArray, F: NDArray, hv: NDArray, Kp: NDArray) -> NDArray:
    """Innovations of the fixed-gain predictor, one lfilter pass from a zero state."""
    Abar = F - np.outer(Kp, hv)
    b, a = scipy.signal.ss2tf(Abar, Kp[:, None], -hv[None, :], np.array([[1.0]]))
    return scipy.signal.lfilter(b[0], a, zc)


def als_fit(
    zc: NDArray, fhq: tuple[NDArray, NDArray, NDArray], tk: float, lags: int, h_floor: float
) -> tuple[float, float, list[str]]:
    """Iterated ALS: fit (q, r), rebuild the gain from the fit, fit again (at most 12 times).

    ``fhq`` is the model's ``(F, h, Q / q)``, ``tk`` its ``T^k`` (``h = q T^k / r``),
    ``h_floor`` the smallest ``h`` a retry with a slower gain goes to.
    """
    F, hv, Q1 = fhq
    notes: list[str] = []
    h_ratio, q, r = 1.0, 0.0, 0.0
    for _ in range(12):
        _, K, _ = steady_state(F, hv, Q1 * (h_ratio / tk), 1.0)
        Kp = F @ K
        rho = max(abs(np.linalg.eigvals(F - np.outer(Kp, hv))))
        burn = int(min(zc.size // 4, 20 + 40 / max(1.0 - rho, 1e-3)))
        e = innovations_lti(zc, F, hv, Kp)[burn:]
        m = e.size
        # C_j = mean(e_{k+j} e_k)
        c = np.array([np.dot(e[j:], e[: m - j]) / (m - j) for j in range(lags)])
        A = als_columns(F, hv, Q1, Kp, lags)
        scale = np.linalg.norm(A, axis=0)
        scale[scale == 0] = 1.0
        sol, _ = scipy.optimize.nnls(A / scale, c)
        q, r = sol / scale
        if q <= 0 and h_ratio > h_floor:
            h_ratio *= 1e-2  # q hidden by a gain too fast for it: try a slower filter
            continue
        if r <= 0 or q <= 0:
            break
        new = q * tk / r
        done = abs(np.log(new / h_ratio)) < 1e-3
        h_ratio = new
        if done:
            break
    if q <= 0:
        notes.append("ALS found no process noise (q = 0): the record is a polynomial plus noise")
    if r <= 0:
        raise NoisevarError(
            "ALS found no measurement noise (r = 0): the record is too smooth for this model; "
            "use method='mle' or a lower-order model"
        )
    return float(q), float(r), notes

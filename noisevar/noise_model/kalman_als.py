"""Autocovariance least squares' pieces: a fixed-gain predictor's innovations and their
autocovariances per unit q and r (:func:`noisevar.noise_model.kalman_fit.fit_kalman`)."""

from __future__ import annotations

import numpy as np
import scipy.linalg
import scipy.signal
from numpy.typing import NDArray


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

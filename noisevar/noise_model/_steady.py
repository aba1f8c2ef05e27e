"""The Kalman filter of a linear scalar-measurement model, run fast on one record.

Three stages (docs/algorithms.md §E6): an exact diffuse start in information form
(the first ``d`` samples fix the state), a compiled time-varying pass while the gain
still moves, and one LTI pass (``scipy.signal.lfilter``) once it has reached the
steady-state gain of ``solve_discrete_are``.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
import scipy.linalg
import scipy.signal
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.numeric.jit import jit

#: Relative change of the gain below which the time-varying pass hands over to the LTI pass.
GAIN_TOL = 1e-15
#: Longest time-varying pass (samples); beyond it the steady-state gain is used.
MAX_TRANSIENT = 20000


@dataclass(frozen=True)
class FilterPass:
    """One pass of the filter over ``z[start:]``: innovations, their variances, estimates."""

    innovations: NDArray
    s: NDArray
    states: NDArray
    start: int


def steady_state(F: NDArray, h: NDArray, Q: NDArray, r: float) -> tuple[NDArray, NDArray, float]:
    """Predicted covariance ``P``, filter gain ``K`` and innovation variance ``S`` at steady state.

    Raises
    ------
    NoisevarError
        If the Riccati equation has no stabilising solution.
    """
    try:
        # P = F P F' - F P h (h'P h + r)^-1 h'P F' + Q
        P = scipy.linalg.solve_discrete_are(F.T, h[:, None], Q, np.array([[r]]))
    except (np.linalg.LinAlgError, ValueError) as exc:
        msg = f"the Riccati equation has no solution for these q and r ({exc})"
        raise NoisevarError(msg) from None
    P = 0.5 * (P + P.T)
    s = float(h @ P @ h) + r
    return P, P @ h / s, s


def diffuse_start(z: NDArray, F: NDArray, h: NDArray, Q: NDArray, r: float) -> tuple:
    """Exact diffuse start: the posterior ``(x, P)`` after the first ``d = n`` samples.

    Information form, so that an infinite prior is exact: ``Y = P^-1`` starts at 0.
    """
    n = F.shape[0]
    Finv = np.linalg.inv(F)
    Y = np.zeros((n, n))
    y = np.zeros(n)
    eye = np.eye(n)
    for k in range(n):  # d = n steps, not a pass over the record
        M = Finv.T @ Y @ Finv
        G = np.linalg.inv(eye + M @ Q)
        # Y- = (I + M Q)^-1 M,  y- = (I + M Q)^-1 F^-T y
        Y, y = G @ M, G @ (Finv.T @ y)
        # Y = Y- + h h'/r,  y = y- + h z/r
        Y = Y + np.outer(h, h) / r
        y = y + h * z[k] / r
    P = np.linalg.inv(Y)
    P = 0.5 * (P + P.T)
    return P @ y, P, n


@jit
def _transient(z, F, h, Q, r, x, P, tol, max_steps):  # pragma: no cover - compiled
    # long: one Kalman step written out with explicit loops (no temporaries: n <= 3)
    n = x.size
    N = min(z.size, max_steps)
    e = np.empty(N)
    s = np.empty(N)
    X = np.empty((N, n))
    x = x.copy()
    P = P.copy()
    xn = np.empty(n)
    FP = np.empty((n, n))
    Pn = np.empty((n, n))
    A = np.empty((n, n))
    IKH = np.empty((n, n))
    Ph = np.empty(n)
    K = np.empty(n)
    prev = np.zeros(n)
    steady = 0
    used = N
    for k in range(N):
        # x- = F x,  P- = F P F' + Q
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += F[i, j] * x[j]
            xn[i] = acc
        for i in range(n):
            for j in range(n):
                acc = 0.0
                for m in range(n):
                    acc += F[i, m] * P[m, j]
                FP[i, j] = acc
        for i in range(n):
            for j in range(n):
                acc = Q[i, j]
                for m in range(n):
                    acc += FP[i, m] * F[j, m]
                Pn[i, j] = acc
        # S = h'P-h + r,  K = P-h / S,  d = z - h'x-
        S = r
        d = z[k]
        for i in range(n):
            acc = 0.0
            for j in range(n):
                acc += Pn[i, j] * h[j]
            Ph[i] = acc
            S += h[i] * acc
            d -= h[i] * xn[i]
        dk = 0.0
        kmax = 0.0
        for i in range(n):
            K[i] = Ph[i] / S
            x[i] = xn[i] + K[i] * d
            dk = max(dk, abs(K[i] - prev[i]))
            kmax = max(kmax, abs(K[i]))
            prev[i] = K[i]
            for j in range(n):
                IKH[i, j] = (1.0 if i == j else 0.0) - K[i] * h[j]
        # P = (I - K h') P- (I - K h')' + r K K'   (Joseph)
        for i in range(n):
            for j in range(n):
                acc = 0.0
                for m in range(n):
                    acc += IKH[i, m] * Pn[m, j]
                A[i, j] = acc
        for i in range(n):
            for j in range(n):
                acc = r * K[i] * K[j]
                for m in range(n):
                    acc += A[i, m] * IKH[j, m]
                P[i, j] = acc
        e[k] = d
        s[k] = S
        for i in range(n):
            X[k, i] = x[i]
        steady = steady + 1 if dk <= tol * kmax else 0
        if steady > n + 2:
            used = k + 1
            break
    return e[:used], s[:used], X[:used], used, prev


def _lti_tail(z, past_z, past_out, F, h, K, states=True):
    """Innovations (and estimates) of the steady-state filter, continued from the past."""
    n = F.shape[0]
    A = (np.eye(n) - np.outer(K, h)) @ F
    # s_{k+1} = A s_k + K z_k (s_k = x(k-1|k-1));  x(k|k) = A s_k + K z_k,  e_k = z_k - h'F s_k
    C = np.vstack([A, -(h @ F)[None, :]])
    D = np.concatenate([K, [1.0]])[:, None]
    num, den = scipy.signal.ss2tf(A, K[:, None], C, D)
    out = np.zeros((z.size, n + 1))
    for i in range(0 if states else n, n + 1):  # one LTI pass per output (n + 1 <= 4)
        zi = scipy.signal.lfiltic(num[i], den, past_out[::-1, i], past_z[::-1])
        out[:, i], _ = scipy.signal.lfilter(num[i], den, z, zi=zi)
    return out[:, n], out[:, :n]


def filter_pass(
    z: NDArray,
    F: NDArray,
    h: NDArray,
    Q: NDArray,
    r: float,
    x0: NDArray | None = None,
    P0: NDArray | None = None,
    states: bool = True,
) -> FilterPass:
    """Run the filter on ``z`` (from the diffuse start, or from ``x0, P0`` at sample -1).

    Returns
    -------
    FilterPass
        Innovations ``e_k``, their variances ``S_k`` and estimates ``x(k|k)`` for
        ``k >= start`` (``start = d`` with the diffuse start, else 0); with
        ``states=False`` the estimates after the time-varying part are zeros.
    """
    z = np.ascontiguousarray(z, dtype=float)
    if x0 is None:
        x0, P0, start = diffuse_start(z, F, h, Q, r)
    else:
        start = 0
    rest = z[start:]
    e, s, X, used, K = _transient(
        rest, F, h, Q, float(r), np.array(x0, float), np.array(P0, float), GAIN_TOL, MAX_TRANSIENT
    )
    if used < rest.size:
        n = F.shape[0]
        if used == MAX_TRANSIENT:  # not converged yet: the steady state of the Riccati equation
            _, K, s_ss = steady_state(F, h, Q, r)
        else:
            s_ss = s[-1]
        past = np.column_stack([X[-n:], e[-n:]])
        e2, X2 = _lti_tail(rest[used:], rest[used - n : used], past, F, h, K, states)
        e = np.concatenate([e, e2])
        s = np.concatenate([s, np.full(e2.size, s_ss)])
        X = np.vstack([X, X2])
    return FilterPass(e, s, X, start)

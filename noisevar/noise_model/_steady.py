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
from noisevar.kalman import kernels
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
        # P = F P F' - F P h (h'P h + r)^-1 h'P F' + Q; scipy's balancing casts a NaN scale
        # to int on matrices beyond the float range (a step of 1e19 s): no stray warning,
        # the non-finite P is refused below
        with np.errstate(invalid="ignore", over="ignore"):
            P = scipy.linalg.solve_discrete_are(F.T, h[:, None], Q, np.array([[r]]))
    except (np.linalg.LinAlgError, ValueError) as exc:
        msg = f"the Riccati equation has no solution for these q and r ({exc})"
        raise NoisevarError(msg) from None
    if not np.all(np.isfinite(P)):
        raise NoisevarError("the Riccati equation has no finite solution for these q and r")
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


def _transient(
    z: NDArray,
    F: NDArray,
    h: NDArray,
    Q: NDArray,
    r: float,
    x: NDArray,
    P: NDArray,
    tol: float,
    max_steps: int,
) -> tuple[NDArray, NDArray, NDArray, int, NDArray]:
    """The time-varying filter from ``x, P`` until its gain settles, at most ``max_steps`` samples.

    Each step is the compiled step of :mod:`noisevar.kalman.kernels` (one run,
    ``H = h'``, ``R = r``, Joseph form), inlined into the loop. The gain has settled
    when its largest change stays within ``tol`` times its largest entry for ``n + 3``
    steps.

    Returns
    -------
    e, s, X, used, K
        Innovations, their variances, estimates ``x(k|k)`` (``used`` rows each),
        the number of samples used and the last gain.
    """
    n = F.shape[0]
    return _transient_loop(
        np.ascontiguousarray(z, dtype=float),
        np.ascontiguousarray(F, dtype=float)[None],
        np.array(h, dtype=float).reshape(1, 1, n),
        np.ascontiguousarray(Q, dtype=float)[None],
        np.full((1, 1, 1), float(r)),
        np.array(x, dtype=float).reshape(1, n),
        np.array(P, dtype=float).reshape(1, n, n),
        float(tol),
        int(max_steps),
        np.empty(0, dtype=np.int64),
        np.empty(kernels.work_shape(n, 1)),
        (None,) * n,
        (None,),
    )


@jit
def _transient_loop(z, F, H, Q, R, x, P, tol, max_steps, none, work, nt, mt):  # pragma: no cover
    """:func:`_transient` on the kernels' operands (``x``, ``P`` updated in place)."""
    n = len(nt)
    N = min(z.size, max_steps)
    e = np.empty(N)
    s = np.empty(N)
    X = np.empty((N, n))
    x_pred = np.empty((1, n))
    P_pred = np.empty((1, n, n))
    zk = np.empty((1, 1))
    z_pred = np.empty((1, 1))
    d = np.empty((1, 1))
    res = np.empty((1, 1))
    PHt = np.empty((1, n, 1))
    HPHt = np.empty((1, 1, 1))
    S = np.empty((1, 1, 1))
    SK = np.empty((1, 1 + n, 1))  # S^-1 and K
    T = np.empty((n, n))
    prev = np.zeros(n)
    steady = 0
    used = N
    for k in range(N):
        # x- = F x,  P- = F P F' + Q
        kernels.predict_linear_inline(F, x, P, Q, x_pred, P_pred, T, nt)
        # d = z - h'x-  (kind 2: a linear H, no selection, no angles)
        zk[0, 0] = z[k]
        kernels.measure_inline(zk, x_pred, P_pred, H, 2, none, none, z_pred, d, PHt, HPHt, nt, mt)
        # S = h'P-h + r,  K = P-h / S,  x = x- + K d,  P (Joseph)
        kernels.gain_update_inline(
            x_pred, P_pred, R, d, H, 2, none, none, zk, True, S, SK, x, P, res, work, nt, mt
        )
        e[k] = d[0, 0]
        s[k] = S[0, 0, 0]
        dk = 0.0
        kmax = 0.0
        for i in range(n):
            K = SK[0, 1 + i, 0]
            X[k, i] = x[0, i]
            dk = max(dk, abs(K - prev[i]))
            kmax = max(kmax, abs(K))
            prev[i] = K
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

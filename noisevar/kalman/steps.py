"""The Kalman filter step as pure functions on batched arrays (numpy reference).

Every array carries a leading batch axis ``B`` (Monte Carlo runs in lock-step).
The equations are those of docs/algorithms.md §G1-§G5; the compiled kernels of
:mod:`noisevar.kalman.kernels` compute the same terms in the same order. The
``*_into`` functions at the end are these functions with the kernels' signatures:
the numpy backend :func:`noisevar.kalman.kernels.backend` picks without numba.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
from numpy.typing import NDArray

_TWO_PI = 2.0 * np.pi


def matvec(a: NDArray, v: NDArray) -> NDArray:
    """Stacked matrix times stacked vector, ``(..., r, c) @ (..., c) -> (..., r)``."""
    return np.matmul(a, v[..., None])[..., 0]


def inv(a: NDArray) -> NDArray:
    """Inverses of a stack of matrices; a singular or non-finite member gives NaN."""
    try:
        return np.linalg.inv(a)
    except np.linalg.LinAlgError:
        out = np.full(np.shape(a), np.nan)
        for i in np.ndindex(np.shape(a)[:-2]):
            try:
                out[i] = np.linalg.inv(a[i])
            except np.linalg.LinAlgError:
                pass
        return out


def wrap_columns(a: NDArray, cols: Sequence[int]) -> NDArray:
    """Wrap columns ``cols`` of ``a`` (shape (B, m)) to ``[-π, π)`` in place (§G3)."""
    if len(cols):
        cols = list(cols)
        # a = (a + π) mod 2π - π
        a[:, cols] = np.mod(a[:, cols] + np.pi, _TWO_PI) - np.pi
    return a


def predict(
    x: NDArray, P: NDArray, F: NDArray, Q: NDArray, x_pred: NDArray | None = None
) -> tuple[NDArray, NDArray]:
    """Time update (docs/algorithms.md §G1).

    Parameters
    ----------
    x, P : ndarray, shapes (B, n), (B, n, n)
        Estimate ``x(k-1|k-1)`` and its covariance.
    F : ndarray, shape (n, n) or (B, n, n)
        Transition matrix (the Jacobian for an EKF).
    Q : ndarray, shape (n, n) or (B, n, n)
        Process-noise covariance.
    x_pred : ndarray, shape (B, n), optional
        ``f(x)`` of a nonlinear model (default ``F x``).

    Returns
    -------
    x_pred, P_pred : ndarray
    """
    if x_pred is None:
        # x = Fx
        x_pred = matvec(F, x)
    # P = FPF' + Q
    P_pred = F @ P @ np.swapaxes(F, -1, -2) + Q
    return x_pred, P_pred


def innovation(z: NDArray, z_pred: NDArray, angles: Sequence[int] = ()) -> NDArray:
    """Innovation ``d = z - h(x(k|k-1))``, angle components wrapped (§G2, §G3)."""
    # y = z - Hx
    return wrap_columns(z - z_pred, angles)


def gain(P_pred: NDArray, H: NDArray, R: NDArray) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Innovation covariance and Kalman gain (docs/algorithms.md §G2).

    Returns
    -------
    PHt, S, S_inv, K : ndarray
        ``P Hᵀ``, ``S``, ``S⁻¹`` (NaN for a singular member) and ``K``.
    """
    # PH'
    PHt = P_pred @ np.swapaxes(H, -1, -2)
    # S = HPH' + R
    S = H @ PHt + R
    S_inv = inv(S)
    # K = PH'S^-1
    K = PHt @ S_inv
    return PHt, S, S_inv, K


def update(
    x_pred: NDArray,
    P_pred: NDArray,
    d: NDArray,
    K: NDArray,
    H: NDArray,
    R: NDArray,
    joseph: bool = True,
) -> tuple[NDArray, NDArray]:
    """Measurement update with gain ``K`` (docs/algorithms.md §G2).

    ``joseph=False`` gives the short form ``P = (I - KH) P``, used only by the
    intermediate iterations of an iterative strategy.

    Returns
    -------
    x, P : ndarray
        ``x(k|k)`` and ``P(k|k)`` (exactly symmetric in the Joseph form).
    """
    # x = x + Ky
    x = x_pred + matvec(K, d)
    # A = I - KH
    A = np.eye(x.shape[-1]) - K @ H
    if not joseph:
        # P = (I - KH)P
        return x, A @ P_pred
    # P = (I - KH)P(I - KH)' + KRK'
    P = A @ P_pred @ np.swapaxes(A, -1, -2) + K @ R @ np.swapaxes(K, -1, -2)
    # P = (P + P') / 2
    return x, (P + np.swapaxes(P, -1, -2)) * 0.5


def cholesky(a: NDArray) -> tuple[NDArray, NDArray]:
    """Batched Cholesky factors and a mask of members that are not positive definite (NaN)."""
    bad = np.zeros(a.shape[0], dtype=bool)
    try:
        return np.linalg.cholesky(a), bad
    except np.linalg.LinAlgError:
        a = np.array(a)
        finite = np.all(np.isfinite(a), axis=(1, 2))
        bad = ~finite
        bad[finite] = np.linalg.eigvalsh(a[finite])[:, 0] <= 0
        a[bad] = np.eye(a.shape[-1])
        L = np.linalg.cholesky(a)
        L[bad] = np.nan
        return L, bad


def huber_update(
    x_pred: NDArray,
    P_pred: NDArray,
    d: NDArray,
    H: NDArray,
    R: NDArray,
    kappa: float,
    iterations: int,
    tol: float,
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Huber M-estimation update by IRLS (docs/algorithms.md §G5).

    Returns
    -------
    x, P : ndarray
        Robust ``x(k|k)``, ``P(k|k)``.
    psi : ndarray, shape (B, n + m)
        Final Huber weights.
    failed : ndarray of bool, shape (B,)
        Runs whose ``P(k|k-1)`` or ``R`` is not positive definite.
    """
    B, n = x_pred.shape
    m = d.shape[1]
    H = np.broadcast_to(H, (B, m, n))
    R = np.broadcast_to(R, (B, m, m))
    Lp, bad_p = cholesky(P_pred)
    Lr, bad_r = cholesky(R)
    Lp_inv, Lr_inv = inv(Lp), inv(Lr)
    # y = M x + τ, whitened by blockdiag(P, R)^(-1/2)
    M = np.concatenate([Lp_inv, Lr_inv @ H], axis=1)
    # z_lin = z - h(x_pred) + H x_pred
    z_lin = d + matvec(H, x_pred)
    y = np.concatenate([matvec(Lp_inv, x_pred), matvec(Lr_inv, z_lin)], axis=1)
    x = x_pred
    psi = np.ones((B, n + m))
    for _ in range(int(iterations)):
        if np.isfinite(kappa):
            # ψ_i = min(1, κ / |τ_i|)
            tau = np.abs(y - matvec(M, x))
            psi = np.minimum(1.0, kappa / np.maximum(tau, 1e-300))
        MtW = M.mT * psi[:, None, :]
        # P = (M'ΨM)^-1,  x = P M'Ψ y
        P = inv(MtW @ M)
        x_new = (P @ (MtW @ y[:, :, None]))[:, :, 0]
        step = np.max(np.abs(x_new - x) / np.sqrt(np.diagonal(P, axis1=1, axis2=2)))
        x = x_new
        if not np.isfinite(kappa) or step < tol:
            break
    return x, 0.5 * (P + P.mT), psi, bad_p | bad_r


# ------------------------------------------------------------------ kernel signatures
def _config(cfg: NDArray) -> tuple[int, list[int]]:
    na = int(cfg[1])
    return int(cfg[0]), [int(a) for a in cfg[2 : 2 + na]]


def predict_linear_into(F, x, P, Q, x_out, P_out, nt) -> None:
    """:func:`predict` into ``x_out``, ``P_out`` (see ``kernels.predict_linear``)."""
    x_out[...], P_out[...] = predict(x, P, F, Q)


def predict_cov_into(F, P, Q, P_out, nt) -> None:
    """``P_out = F P Fᵀ + Q`` (see ``kernels.predict_cov``)."""
    # P = FPF' + Q
    P_out[...] = F @ P @ np.swapaxes(F, -1, -2) + Q


def measure_into(z, x_pred, P_pred, H, cfg, z_pred, d, PHt, HPHt, nt, mt) -> None:
    """Predicted measurement, innovation, ``P Hᵀ``, ``H P Hᵀ`` (see ``kernels.measure``)."""
    kind, angles = _config(cfg)
    if kind in (1, 2):
        z_pred[...] = matvec(H, x_pred)
    PHt[...] = P_pred @ np.swapaxes(H, -1, -2)
    HPHt[...] = H @ PHt
    d[...] = innovation(z, z_pred, angles)


def innovation_into(z, x_pred, cfg, d) -> None:
    """``d = z - x_pred``, angles wrapped (identity ``H``)."""
    d[...] = innovation(z, x_pred, _config(cfg)[1])


def gain_update_into(x_pred, P_pred, R, d, H, cfg, z, final, S, SK, x, P, r, work, nt, mt) -> None:
    """:func:`gain` and :func:`update` into the buffers of ``kernels.gain_update``."""
    kind, angles = _config(cfg)
    m = d.shape[1]
    _, S[...], SK[:, :m], SK[:, m:] = gain(P_pred, H, R)
    x[...], P[...] = update(x_pred, P_pred, d, SK[:, m:], H, R, joseph=bool(final))
    if kind != 3:
        r[...] = innovation(z, matvec(H, x), angles)

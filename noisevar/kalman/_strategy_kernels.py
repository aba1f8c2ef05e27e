"""Compiled (numba) kernels of the adaptive strategies: moving windows, Sage-Husa, VB.

Each kernel updates a whole batch in place; :func:`noisevar.kalman.kernels.backend` hands
them (or their plain-Python bodies) to the strategies.
"""

from __future__ import annotations

import numpy as np

from noisevar.numeric.jit import jit


@jit
def _push(buf, total, count, pos, v):  # pragma: no cover - compiled
    """One push of ``MovingMean`` on flattened rows (see strategies.MovingMean)."""
    size = buf.shape[0]
    w = total.shape[0]
    if count >= size:
        for j in range(w):
            total[j] -= buf[pos, j]
    for j in range(w):
        buf[pos, j] = v[j]
        total[j] += v[j]
    if pos + 1 == size:  # exact re-sum once per wrap-around, in numpy's order
        for j in range(w):
            total[j] = buf[0, j]
        for i in range(1, size):
            for j in range(w):
                total[j] += buf[i, j]


@jit
def _diag_into(est, out):  # pragma: no cover - compiled
    """``out = est[:, :, None] * eye`` (a NaN variance fills its row, as in numpy)."""
    B, m = est.shape
    for b in range(B):
        for i in range(m):
            for j in range(m):
                out[b, i, j] = est[b, i] * (1.0 if i == j else 0.0)


@jit
def _floor_clip(est, floor, guard):  # pragma: no cover - compiled
    """Clip variances below ``floor`` (per channel), counting the runs that needed it."""
    B, m = est.shape
    for b in range(B):
        low = False
        for i in range(m):
            if est[b, i] < floor[i]:
                low = True
                est[b, i] = floor[i]
        if low:
            guard[b] += 1


@jit
def window_diag(buf, total, count, pos, u, hph, sign, adapt, floor, guard, R_out):
    """RAE / IAE (diagonal): push ``u²``; if ``adapt``, ``R_out = diag(mean + sign·hph)``, clipped.

    ``count`` and ``pos`` are the moving mean's before the push. Returns
    whether ``R_out`` was written.
    """
    B, m = u.shape
    v = np.empty(B * m)
    for b in range(B):
        for i in range(m):
            v[b * m + i] = u[b, i] * u[b, i]
    _push(buf.reshape((buf.shape[0], B * m)), total.reshape(B * m), count, pos, v)
    if not adapt:
        return False
    c = min(count + 1, buf.shape[0])
    est = np.empty((B, m))
    for b in range(B):
        for i in range(m):
            mean = total[b, i] / c
            if sign > 0:
                est[b, i] = mean + hph[b, i]
            else:
                est[b, i] = mean - hph[b, i]
    _floor_clip(est, floor, guard)
    _diag_into(est, R_out)
    return True


@jit
def outer_q(buf, total, count, pos, d, adapt, K, Q_out):  # pragma: no cover - compiled
    """RAE-Q: push ``d dᵀ``; when ``adapt``, ``Q_out = sym((K C) Kᵀ)`` with ``C`` the mean."""
    B, m = d.shape
    n = K.shape[1]
    v = np.empty(B * m * m)
    for b in range(B):
        for i in range(m):
            for j in range(m):
                v[(b * m + i) * m + j] = d[b, i] * d[b, j]
    _push(buf.reshape((buf.shape[0], B * m * m)), total.reshape(B * m * m), count, pos, v)
    if not adapt:
        return False
    c = min(count + 1, buf.shape[0])
    C = np.empty((m, m))
    KC = np.empty((n, m))
    Qb = np.empty((n, n))
    for b in range(B):
        for i in range(m):
            for j in range(m):
                C[i, j] = total[b, i, j] / c
        for i in range(n):
            for j in range(m):
                s = 0.0
                for k in range(m):
                    s += K[b, i, k] * C[k, j]
                KC[i, j] = s
        for i in range(n):
            for j in range(n):
                s = 0.0
                for k in range(m):
                    s += KC[i, k] * K[b, j, k]
                Qb[i, j] = s
        for i in range(n):
            for j in range(n):
                Q_out[b, i, j] = 0.5 * (Qb[i, j] + Qb[j, i])
    return True


@jit
def sage_husa_diag(est_prev, d, hph, dk, floor, guard, est_out, R_out):  # pragma: no cover
    """Sage-Husa (diagonal) step: the estimate with its fallback, then the clipped ``R``."""
    B, m = d.shape
    one = 1.0 - dk
    est = np.empty((B, m))
    for b in range(B):
        low = False
        for i in range(m):
            outer = d[b, i] * d[b, i]
            e = one * est_prev[b, i] + dk * (outer - hph[b, i])
            if e < floor[i]:
                low = True
                e = one * est_prev[b, i] + dk * outer
            est_out[b, i] = e
            est[b, i] = e
        if low:
            guard[b] += 1
    _floor_clip(est, floor, guard)
    _diag_into(est, R_out)


@jit
def vb_predict(alpha, beta, rho, beta_pred, R_out):  # pragma: no cover - compiled
    """VB time update in place: ``α = ρα + 1/2``, ``β⁻ = ρβ``, ``β = β⁻``; ``R_out = diag(β/α)``."""
    B, m = alpha.shape
    for b in range(B):
        for i in range(m):
            alpha[b, i] = rho * alpha[b, i] + 0.5
            bp = rho * beta[b, i]
            beta_pred[b, i] = bp
            beta[b, i] = bp
            for j in range(m):
                R_out[b, i, j] = bp / alpha[b, i] * (1.0 if i == j else 0.0)


@jit
def vb_beta(beta_pred, r, HPH, alpha, beta, R_out, want_R):  # pragma: no cover - compiled
    """VB ``β = β⁻ + r²/2 + diag(H P Hᵀ)/2``; ``R_out = diag(β/α)`` when ``want_R``.

    ``HPH`` is ``H P Hᵀ`` (shape (B, m, m); ``P`` itself for an identity ``H``).
    """
    B, m = r.shape
    for b in range(B):
        for i in range(m):
            v = beta_pred[b, i] + 0.5 * r[b, i] * r[b, i] + 0.5 * HPH[b, i, i]
            beta[b, i] = v
            if want_R:
                for j in range(m):
                    R_out[b, i, j] = v / alpha[b, i] * (1.0 if i == j else 0.0)

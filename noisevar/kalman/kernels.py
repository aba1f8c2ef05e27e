"""Compiled (numba) kernels of the filter step and of the strategies, and the backend switch.

Each kernel does one step of a whole batch (loops over the batch axis ``B``).
The dimensions reach the kernels as the lengths of ``nt = (None,) * n`` and
``mt = (None,) * m``, compile-time constants, so small loops are unrolled.
The arithmetic follows :mod:`noisevar.kalman.steps` term by term: this module
is the step's compiled twin. Other compiled code (the steady-state pass of
:mod:`noisevar.noise_model`) calls the step through the ``*_inline`` forms
(:func:`predict_linear_inline`, :func:`measure_inline`,
:func:`gain_update_inline`: the same bodies, inlined into the caller, so a
one-run loop pays no call per stage) instead of writing the equations again.

:func:`backend` is the one place that chooses: the compiled kernels when
:data:`USE_COMPILED` (numba installed), else the numpy forms of
:mod:`noisevar.kalman.steps` and the kernels' plain-Python bodies.

Conventions: operands shared by the batch (``F``, ``Q``, ``H``, ``R``) are 3-D
with a leading axis of 1 (shared) or ``B``; ``kind`` is how the measurement is
formed: 0 identity ``H``, 1 a selection of states, 2 a linear ``H``, 3 a
function ``h`` (the caller forms ``h(x)`` and the residual).
"""

from __future__ import annotations

import math
from collections.abc import Callable
from dataclasses import dataclass

import numpy as np

from noisevar.kalman import steps
from noisevar.kalman._strategy_kernels import (
    outer_q,
    sage_husa_diag,
    vb_beta,
    vb_predict,
    window_diag,
)
from noisevar.numeric.jit import HAVE_NUMBA
from noisevar.numeric.jit import inline as _inline
from noisevar.numeric.jit import jit as _jit

#: Filters and strategies started while this is true use the compiled kernels.
USE_COMPILED: bool = HAVE_NUMBA

_PI = math.pi
_TWO_PI = 2.0 * math.pi


@_jit
def _wrap(v: float) -> float:
    # Python's / numba's float % is the floored modulo of np.mod
    return (v + _PI) % _TWO_PI - _PI


@_inline
def _inv_lu(a, out, lu, piv, m):  # pragma: no cover - compiled
    """Inverse of one small matrix by LU with partial pivoting (as LAPACK ``gesv``).

    An exactly zero pivot (a singular matrix) gives NaN, like the LAPACK path.
    """
    for i in range(m):
        for j in range(m):
            lu[i, j] = a[i, j]
        piv[i] = float(i)
    for c in range(m):
        p = c
        best = abs(lu[c, c])
        for i in range(c + 1, m):
            v = abs(lu[i, c])
            if v > best:
                best = v
                p = i
        if lu[p, c] == 0.0:
            for i in range(m):
                for j in range(m):
                    out[i, j] = np.nan
            return
        if p != c:
            for j in range(m):
                t = lu[c, j]
                lu[c, j] = lu[p, j]
                lu[p, j] = t
            t2 = piv[c]
            piv[c] = piv[p]
            piv[p] = t2  # pivot indices stored as floats (exact)
        inv_p = 1.0 / lu[c, c]
        for i in range(c + 1, m):
            lu[i, c] *= inv_p
        for i in range(c + 1, m):
            l_ic = lu[i, c]
            if l_ic != 0.0:
                for j in range(c + 1, m):
                    lu[i, j] -= l_ic * lu[c, j]
    # solve L U X = P I column by column
    for col in range(m):
        for i in range(m):
            out[i, col] = 1.0 if piv[i] == float(col) else 0.0
        for i in range(m):  # forward, unit lower
            s = out[i, col]
            for j in range(i):
                s -= lu[i, j] * out[j, col]
            out[i, col] = s
        for i in range(m - 1, -1, -1):  # backward
            s = out[i, col]
            for j in range(i + 1, m):
                s -= lu[i, j] * out[j, col]
            out[i, col] = s / lu[i, i]


@_inline
def _cov_into(Fb, Pb, Qb, out, T, n):  # pragma: no cover - compiled
    """``out = (F P) Fᵀ + Q`` for one member (``T`` scratch)."""
    # P = FPF' + Q
    for i in range(n):
        for j in range(n):
            s = 0.0
            for k in range(n):
                s += Fb[i, k] * Pb[k, j]
            T[i, j] = s
    for i in range(n):
        for j in range(n):
            s = 0.0
            for k in range(n):
                s += T[i, k] * Fb[j, k]
            out[i, j] = s + Qb[i, j]


@_jit
def predict_linear(F, x, P, Q, x_out, P_out, nt):  # pragma: no cover - compiled
    """``x_out = F x``, ``P_out = F P Fᵀ + Q`` (``F``, ``Q`` of shape (1 or B, n, n))."""
    n = len(nt)
    predict_linear_inline(F, x, P, Q, x_out, P_out, np.empty((n, n)), nt)


@_inline
def predict_linear_inline(F, x, P, Q, x_out, P_out, T, nt):  # pragma: no cover - compiled
    """:func:`predict_linear` with its scratch ``T`` (n, n), inlined where it is called."""
    B = x.shape[0]
    n = len(nt)
    fb = F.shape[0] > 1
    qb = Q.shape[0] > 1
    for b in range(B):
        Fb = F[b if fb else 0]
        for i in range(n):
            s = 0.0
            for k in range(n):
                s += x[b, k] * Fb[i, k]
            x_out[b, i] = s
        _cov_into(Fb, P[b], Q[b if qb else 0], P_out[b], T, n)


@_jit
def predict_cov(F, P, Q, P_out, nt):  # pragma: no cover - compiled
    """``P_out = F P Fᵀ + Q`` (EKF: ``F`` the Jacobian, shape (1 or B, n, n))."""
    B = P.shape[0]
    n = len(nt)
    T = np.empty((n, n))
    fb = F.shape[0] > 1
    qb = Q.shape[0] > 1
    for b in range(B):
        _cov_into(F[b if fb else 0], P[b], Q[b if qb else 0], P_out[b], T, n)


@_inline
def unpack(cfg):  # pragma: no cover - compiled
    """``kind``, state selection and angle components from ``cfg`` (see :func:`config`)."""
    na = cfg[1]
    return cfg[0], cfg[2 + na :], cfg[2 : 2 + na]


@_inline
def _project(Pb, Hb, kind, sel, PHt, HPHt, n, m):  # pragma: no cover - compiled
    """``PHt = P Hᵀ`` and ``HPHt = H P Hᵀ`` of one member (kinds 1-3; 0 is ``P`` itself)."""
    if kind == 1:
        for r in range(n):
            for i in range(m):
                PHt[r, i] = Pb[r, sel[i]]
        for i in range(m):
            for j in range(m):
                HPHt[i, j] = PHt[sel[i], j]
    else:
        for r in range(n):
            for i in range(m):
                s = 0.0
                for k in range(n):
                    s += Pb[r, k] * Hb[i, k]
                PHt[r, i] = s
        for i in range(m):
            for j in range(m):
                s = 0.0
                for k in range(n):
                    s += Hb[i, k] * PHt[k, j]
                HPHt[i, j] = s


@_jit
def measure(z, x_pred, P_pred, H, cfg, z_pred, d, PHt, HPHt, nt, mt):  # pragma: no cover
    """Predicted measurement, innovation ``d = z - z_pred`` (angles wrapped), ``P Hᵀ``, ``H P Hᵀ``.

    ``cfg`` as built by :func:`config`. Kind 0: ``z_pred``, ``PHt``, ``HPHt``
    are the caller's ``x_pred``, ``P_pred`` (untouched); 1: selection; 2:
    linear ``H``; 3: ``z_pred`` given (from ``h``), ``H`` the Jacobian.
    """
    kind, sel, angles = unpack(cfg)
    measure_inline(z, x_pred, P_pred, H, kind, sel, angles, z_pred, d, PHt, HPHt, nt, mt)


@_inline
def measure_inline(  # pragma: no cover - compiled
    z, x_pred, P_pred, H, kind, sel, angles, z_pred, d, PHt, HPHt, nt, mt
):
    """:func:`measure` with ``cfg`` unpacked (:func:`unpack`), inlined where it is called."""
    B = x_pred.shape[0]
    n = len(nt)
    m = len(mt)
    hb = H.shape[0] > 1
    for b in range(B):
        if kind == 0:
            for i in range(m):
                d[b, i] = z[b, i] - x_pred[b, i]
        else:
            Hb = H[b if hb else 0]
            if kind == 1:
                for i in range(m):
                    z_pred[b, i] = x_pred[b, sel[i]]
            elif kind == 2:
                for i in range(m):
                    s = 0.0
                    for k in range(n):
                        s += x_pred[b, k] * Hb[i, k]
                    z_pred[b, i] = s
            _project(P_pred[b], Hb, kind, sel, PHt[b], HPHt[b], n, m)
            for i in range(m):
                d[b, i] = z[b, i] - z_pred[b, i]
        for a in angles:
            d[b, a] = _wrap(d[b, a])


@_jit
def gain_update(
    x_pred, P_pred, R, d, H, cfg, z, final, S, SK, x, P, r, work, nt, mt
):  # pragma: no cover - compiled
    """Gain and update with ``R``, residual unless ``kind == 3`` (:func:`gain_update_inline`)."""
    kind, sel, angles = unpack(cfg)
    gain_update_inline(
        x_pred, P_pred, R, d, H, kind, sel, angles, z, final, S, SK, x, P, r, work, nt, mt
    )


@_inline
def gain_update_inline(  # long: one fused kernel per step (a call per stage costs more than flops)
    x_pred, P_pred, R, d, H, kind, sel, angles, z, final, S, SK, x, P, r, work, nt, mt
):  # pragma: no cover - compiled
    """Gain and update with ``R`` (shape (1 or B, m, m)), residual unless ``kind == 3``.

    ``S = H P Hᵀ + R``, ``K = P Hᵀ S⁻¹``, ``x = x_pred + K d``, with ``S⁻¹``
    and ``K`` written into ``SK`` (shape (B, m + n, m): rows ``:m`` and
    ``m:``, one operand instead of two); ``final``:
    Joseph form ``P = (A P_pred) Aᵀ + (K R) Kᵀ`` symmetrised, ``A = I - K H``;
    otherwise the short form ``P = A P_pred``. Residual ``r = z - H x``
    (angles wrapped). ``P Hᵀ`` and ``H P Hᵀ`` are recomputed from ``P_pred``
    (the same arithmetic as :func:`measure`: fewer operands to pass, which
    costs more than the few flops). ``kind``, ``sel``, ``angles`` from
    :func:`unpack`; ``work`` scratch of shape :func:`work_shape` (no allocation per call).
    Inlined where it is called.
    """
    B = x_pred.shape[0]
    n = len(nt)
    m = len(mt)
    rb = R.shape[0] > 1
    hb = H.shape[0] > 1
    # basic slices of the (7, L, L) scratch (a reshape costs a helper call)
    A = work[0, :n, :n]
    T = work[1, :n, :n]
    M = work[2, :n, :n]
    KR = work[3, :n, :m]
    lu = work[4, :m, :m]
    piv = work[5, 0, :m]
    PHt_w = work[5, 1:, :m][:n]
    HPHt_w = work[6, :m, :m]
    for b in range(B):
        Rb = R[b if rb else 0]
        Sb = S[b]
        Sib = SK[b, :m]
        Kb = SK[b, m:]
        if kind == 0:
            PHt = P_pred[b]
            HPHt = P_pred[b]
        else:
            PHt = PHt_w
            HPHt = HPHt_w
            _project(P_pred[b], H[b if hb else 0], kind, sel, PHt, HPHt, n, m)
        # S = HPH' + R
        for i in range(m):
            for j in range(m):
                Sb[i, j] = HPHt[i, j] + Rb[i, j]
        _inv_lu(Sb, Sib, lu, piv, m)
        # K = PH'S^-1
        for i in range(n):
            for j in range(m):
                s = 0.0
                for k in range(m):
                    s += PHt[i, k] * Sib[k, j]
                Kb[i, j] = s
        for i in range(n):
            s = 0.0
            for k in range(m):
                s += Kb[i, k] * d[b, k]
            x[b, i] = x_pred[b, i] + s  # x = x + Ky
        # A = I - K H
        for i in range(n):
            for j in range(n):
                A[i, j] = 1.0 if i == j else 0.0
        if kind == 0:
            for i in range(n):
                for j in range(n):
                    A[i, j] = A[i, j] - Kb[i, j]
        elif kind == 1:
            for i in range(n):
                for j in range(m):
                    A[i, sel[j]] = A[i, sel[j]] - Kb[i, j]
        else:
            Hb = H[b if hb else 0]
            for i in range(n):
                for j in range(n):
                    s = 0.0
                    for k in range(m):
                        s += Kb[i, k] * Hb[k, j]
                    A[i, j] = A[i, j] - s
        Pp = P_pred[b]
        Pb = P[b]
        if not final:  # P = (I - KH)P
            for i in range(n):
                for j in range(n):
                    s = 0.0
                    for k in range(n):
                        s += A[i, k] * Pp[k, j]
                    Pb[i, j] = s
        else:  # P = (I - KH)P(I - KH)' + KRK', then (P + P') / 2
            for i in range(n):
                for j in range(n):
                    s = 0.0
                    for k in range(n):
                        s += A[i, k] * Pp[k, j]
                    T[i, j] = s
            for i in range(n):
                for j in range(n):
                    s = 0.0
                    for k in range(n):
                        s += T[i, k] * A[j, k]
                    M[i, j] = s
            for i in range(n):
                for j in range(m):
                    s = 0.0
                    for k in range(m):
                        s += Kb[i, k] * Rb[k, j]
                    KR[i, j] = s
            for i in range(n):
                for j in range(n):
                    s = 0.0
                    for k in range(m):
                        s += KR[i, k] * Kb[j, k]
                    M[i, j] += s
            for i in range(n):
                for j in range(n):
                    Pb[i, j] = (M[i, j] + M[j, i]) * 0.5
        if kind == 3:
            continue
        if kind == 0:
            for i in range(m):
                r[b, i] = z[b, i] - x[b, i]
        elif kind == 1:
            for i in range(m):
                r[b, i] = z[b, i] - x[b, sel[i]]
        else:
            Hb = H[b if hb else 0]
            for i in range(m):
                s = 0.0
                for k in range(n):
                    s += x[b, k] * Hb[i, k]
                r[b, i] = z[b, i] - s
        for a in angles:
            r[b, a] = _wrap(r[b, a])


def work_shape(n: int, m: int) -> tuple[int, int, int]:
    """Shape of the ``work`` operand of :func:`gain_update`."""
    L = max(n, m)
    return (7, L + 1, L)


@_jit
def innovation(z, x_pred, cfg, d):  # pragma: no cover - compiled
    """``d = z - x_pred`` with angles wrapped (identity ``H``: ``measure`` of kind 0)."""
    B, m = d.shape
    na = cfg[1]
    for b in range(B):
        for i in range(m):
            d[b, i] = z[b, i] - x_pred[b, i]
        for a in range(na):
            c = cfg[2 + a]
            d[b, c] = _wrap(d[b, c])


def config(kind: int, angles: tuple[int, ...], sel: tuple[int, ...] | None) -> np.ndarray:
    """The integer operand ``cfg`` of :func:`measure` and :func:`gain_update`.

    ``[kind, len(angles), *angles, *sel]``.
    """
    return np.array([kind, len(angles), *angles, *(sel or ())], dtype=np.int64)


def compiled(fn: Callable) -> Callable | None:
    """``fn`` compiled as the kernels are, or None without numba.

    For a model's kernel defined outside this package (a scenario's
    ``StateSpaceModel.transition``): its caller falls back to numpy on None.
    """
    return _jit(fn) if HAVE_NUMBA else None


# --------------------------------------------------------------------------- backend
@dataclass(frozen=True)
class Backend:
    """The step and strategy kernels one filter uses (same signatures either way)."""

    compiled: bool
    predict_linear: Callable[..., None]
    predict_cov: Callable[..., None]
    measure: Callable[..., None]
    innovation: Callable[..., None]
    gain_update: Callable[..., None]
    window_diag: Callable[..., bool]
    outer_q: Callable[..., bool]
    sage_husa_diag: Callable[..., None]
    vb_predict: Callable[..., None]
    vb_beta: Callable[..., None]


def _python(fn: Callable) -> Callable:
    return getattr(fn, "py_func", fn)


_STRATEGY_KERNELS = (window_diag, outer_q, sage_husa_diag, vb_predict, vb_beta)

_COMPILED = Backend(
    True, predict_linear, predict_cov, measure, innovation, gain_update, *_STRATEGY_KERNELS
)
_NUMPY = Backend(
    False,
    steps.predict_linear_into,
    steps.predict_cov_into,
    steps.measure_into,
    steps.innovation_into,
    steps.gain_update_into,
    *(_python(f) for f in _STRATEGY_KERNELS),
)


def backend() -> Backend:
    """The kernels to use now: compiled when :data:`USE_COMPILED`, else numpy / plain Python."""
    return _COMPILED if USE_COMPILED and HAVE_NUMBA else _NUMPY

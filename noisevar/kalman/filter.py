"""The step-by-step filter: :class:`KalmanFilter`, linear or EKF, batched over runs.

Each step is ``predict()`` then ``update(z_k)`` (docs/algorithms.md §G1, §G2);
``x0, P0`` are the estimate one step before the first measurement. The
arithmetic runs in the kernels :func:`noisevar.kalman.kernels.backend`
chooses; a strategy is asked for ``Q_k`` and ``R_k`` through its hooks and
reads the step through the filter's public attributes.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman import kernels, steps
from noisevar.kalman.model import HuberUpdate, StateSpaceModel

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.strategies.base import RStrategy


@dataclass
class _Workspace:
    """Constant kernel operands and reusable buffers of one filter (not part of the API)."""

    kind: int
    sel: list[int] | None
    cfg: NDArray
    work: NDArray
    nt: tuple[None, ...]
    mt: tuple[None, ...]
    F3: NDArray | None
    H3: NDArray
    Q3: NDArray
    R3: NDArray
    F_buf: tuple[NDArray, NDArray]
    SK: tuple[tuple[NDArray, NDArray, NDArray], ...]
    scratch: tuple[NDArray, ...] | None = None


def _sk_buffer(B: int, n: int, m: int) -> tuple[NDArray, NDArray, NDArray]:
    """One ``(B, m + n, m)`` array holding ``S⁻¹`` and ``K``, and those two views."""
    SK = np.empty((B, m + n, m))
    return SK, SK[:, :m], SK[:, m:]


def _workspace(model: StateSpaceModel, B: int) -> _Workspace:
    n, m = model.n_states, model.n_measurements
    sel = model.measured_states
    if sel is not None and sel == tuple(range(n)) and m == n:
        kind = 0  # identity H
    elif sel is not None:
        kind = 1  # H selects states
    else:
        kind = 2 if model.h is None else 3
    return _Workspace(
        kind=kind,
        sel=None if sel is None else list(sel),
        cfg=kernels.config(kind, model.angle_measurements, sel),
        work=np.empty(kernels.work_shape(n, m)),
        nt=(None,) * n,
        mt=(None,) * m,
        F3=None if model.F is None else np.ascontiguousarray(model.F[None]),
        H3=np.zeros((1, m, n)) if model.H is None else np.ascontiguousarray(model.H[None]),
        Q3=model.Q[None],
        R3=model.R[None],
        F_buf=(np.empty((B, n, n)), np.empty((B, n, n))),
        SK=(_sk_buffer(B, n, m), _sk_buffer(B, n, m)),
    )


@dataclass
class KalmanFilter:
    """A linear / extended Kalman filter over a batch of runs, step by step.

    Parameters
    ----------
    model : StateSpaceModel
        The model.
    strategy : RStrategy, optional
        R-adaptation strategy (default: fixed ``model.R``).
    robust : HuberUpdate, optional
        Use the Huber M-estimation update instead of the plain one.
    batch_size : int
        Number of runs ``B`` filtered in lock-step.
    x0 : array_like, shape (n,) or (B, n), optional
        Initial state per run (default ``model.x0`` for every run).

    Attributes
    ----------
    k : int
        Index of the current step (``-1`` before the first ``predict``).
    n, m : int
        State and measurement dimensions.
    x, P : ndarray, shapes (B, n), (B, n, n)
        Latest estimate ``x̂(k|k)`` and covariance.
    x_pred, P_pred : ndarray
        Prediction ``x̂(k|k-1)``, ``P(k|k-1)``.
    z, z_pred, innovation, residual : ndarray, shape (B, m)
        Measurement, ``h(x̂(k|k-1))``, ``d = z - z_pred``, ``r = z - h(x̂(k|k))``.
    F_used, H_used : ndarray
        Transition / measurement Jacobians of the current step.
    Q, R : ndarray
        Covariances of the current step (broadcastable to ``(B, n, n)``, ``(B, m, m)``).
    S, S_inv, K : ndarray
        Innovation covariance, its inverse, the Kalman gain.
    PHt, HPHt : ndarray
        ``P(k|k-1) Hᵀ`` and ``H P(k|k-1) Hᵀ``.
    failed : ndarray of bool, shape (B,)
        Runs whose ``P(k|k-1)`` or ``R`` lost positive definiteness in the Huber update.

    Notes
    -----
    These attributes are the view strategies read: treat them as read-only.
    ``S_inv``, ``K`` and ``F_used`` live in buffers reused two steps later: copy
    them to keep them; the others are new memory at every step.
    """

    model: StateSpaceModel
    strategy: RStrategy | None = None
    robust: HuberUpdate | None = None
    batch_size: int = 1
    x0: ArrayLike | None = None
    k: int = field(init=False, default=-1)

    def __post_init__(self) -> None:
        from noisevar.kalman.strategies.fixed import FixedR

        if not isinstance(self.model, StateSpaceModel):
            raise NoisevarError("model must be a noisevar.kalman.StateSpaceModel")
        if int(self.batch_size) < 1:
            raise NoisevarError(f"batch_size must be at least 1, got {self.batch_size}")
        if self.robust is not None and not isinstance(self.robust, HuberUpdate):
            raise NoisevarError("robust must be a HuberUpdate (or None)")
        self.batch_size = B = int(self.batch_size)
        self.strategy = FixedR() if self.strategy is None else self.strategy
        model = self.model
        self.n, self.m = n, m = model.n_states, model.n_measurements
        self.x = self._initial_state()
        self.P = np.repeat(model.P0[None, :, :], B, axis=0)
        self.x_pred, self.P_pred = self.x.copy(), self.P.copy()
        self.z, self.z_pred = np.zeros((B, m)), np.zeros((B, m))
        self.innovation, self.residual = np.zeros((B, m)), np.zeros((B, m))
        self.F_used: NDArray = model.F if model.F is not None else np.eye(n)
        self.H_used: NDArray = model.H if model.H is not None else np.zeros((m, n))
        self.Q: NDArray = model.Q
        self.R: NDArray = model.R
        self.S = np.repeat(model.R[None], B, axis=0)
        self.S_inv = np.linalg.inv(self.S)
        self.K = np.zeros((B, n, m))
        self.failed = np.zeros(B, dtype=bool)
        self._ws = _workspace(model, B)
        self._ops = kernels.backend()
        self.strategy.start(self)

    def _initial_state(self) -> NDArray:
        n, B = self.model.n_states, self.batch_size
        if self.x0 is None:
            return np.repeat(self.model.x0[None, :], B, axis=0)
        x0 = np.asarray(self.x0, dtype=float)
        if x0.shape not in ((n,), (B, n)) or not np.all(np.isfinite(x0)):
            raise NoisevarError(
                f"x0 must be finite with shape ({n},) or ({B}, {n}), got {x0.shape}"
            )
        return np.array(np.broadcast_to(x0, (B, n)))

    @property
    def compiled(self) -> bool:
        """Whether this filter's arithmetic runs in the compiled kernels."""
        return self._ops.compiled

    # ------------------------------------------------------------------ steps
    def predict(self) -> None:
        """Time update: ``x(k|k-1) = f(x)``, ``P(k|k-1) = F P Fᵀ + Q_k``."""
        self._predict(None, None)

    def _stack3(self, a: ArrayLike, rows: int, cols: int, name: str) -> NDArray:
        """``a`` as a float array of shape (1 or B, rows, cols) for the kernels."""
        if type(a) is not np.ndarray or a.dtype != np.float64:
            a = np.asarray(a, dtype=float)
        if a.ndim == 2 and a.shape == (rows, cols):
            return a[None]
        if a.ndim == 3 and a.shape[1:] == (rows, cols) and a.shape[0] in (1, self.batch_size):
            return a
        try:
            return np.broadcast_to(a, (self.batch_size, rows, cols))
        except ValueError:
            raise NoisevarError(
                f"{name} has shape {a.shape}; expected ({rows}, {cols}) or "
                f"({self.batch_size}, {rows}, {cols})"
            ) from None

    def _predict(self, x_out: NDArray | None, P_out: NDArray | None) -> None:
        """:meth:`predict` into ``x_out``, ``P_out`` (fresh arrays when ``None``)."""
        k = self.k = self.k + 1
        model, ws, ops = self.model, self._ws, self._ops
        B, n = self.batch_size, self.n
        Q = self.strategy.process_covariance(self)
        self.Q = Q = model.Q if Q is None else Q
        Q3 = ws.Q3 if Q is model.Q else self._stack3(Q, n, n, "Q")
        x_out = np.empty((B, n)) if x_out is None else x_out
        P_out = np.empty((B, n, n)) if P_out is None else P_out
        if model.f is None:
            F = model.F
            # x = Fx,  P = FPF' + Q
            ops.predict_linear(ws.F3, self.x, self.P, Q3, x_out, P_out, ws.nt)
        else:
            if model.transition is not None:
                # two alternating buffers: F_used stays valid for a step after
                F = F3 = ws.F_buf[k & 1]
                model.transition(self.x, k, x_out, F)
            else:
                F = model.F_jacobian(self.x, k)
                x_out[...] = model.f(self.x, k)
                F3 = self._stack3(F, n, n, "F_jacobian")
            # P = FPF' + Q
            ops.predict_cov(F3, self.P, Q3, P_out, ws.nt)
        self.x_pred, self.P_pred, self.F_used = x_out, P_out, F

    def _measure(self, z: NDArray, d: NDArray) -> NDArray:
        """Predicted measurement, innovation into ``d``, ``PHt``, ``HPHt``; returns ``H3``."""
        model, ws, ops = self.model, self._ws, self._ops
        B, n, m = self.batch_size, self.n, self.m
        x_pred, P_pred = self.x_pred, self.P_pred
        H, H3 = model.H, ws.H3
        if ws.kind == 0:
            z_pred = x_pred
            PHt = HPHt = P_pred
            # y = z - x
            ops.innovation(z, x_pred, ws.cfg, d)
        else:
            if ws.kind == 3:
                H = model.H_jacobian(x_pred, self.k)
                H3 = self._stack3(H, m, n, "H_jacobian")
                z_pred = np.asarray(model.h(x_pred, self.k), dtype=float)
            else:
                z_pred = np.empty((B, m))
            PHt, HPHt = np.empty((B, n, m)), np.empty((B, m, m))
            # y = z - Hx,  PH',  HPH'
            ops.measure(z, x_pred, P_pred, H3, ws.cfg, z_pred, d, PHt, HPHt, ws.nt, ws.mt)
        self.PHt, self.HPHt, self.z_pred, self.H_used, self.innovation = PHt, HPHt, z_pred, H, d
        return H3

    def _outputs(self, final: bool, out: tuple[NDArray, ...] | None) -> tuple[NDArray, ...]:
        """``x, P, r, S, SK, S_inv, K`` buffers of one update iteration."""
        B, n, m, ws = self.batch_size, self.n, self.m, self._ws
        if not final:  # feeds only the strategy's next R: scratch memory
            if ws.scratch is None:
                ws.scratch = (
                    np.empty((B, n)),
                    np.empty((B, n, n)),
                    np.empty((B, m)),
                    np.empty((B, m, m)),
                    *_sk_buffer(B, n, m),
                )
            return ws.scratch
        if out is None:
            out = (
                np.empty((B, n)),
                np.empty((B, n, n)),
                None,
                np.empty((B, m)),
                np.empty((B, m, m)),
            )
        x, P, _, r, S = out
        # S⁻¹ and K: two alternating buffers (valid until the update after next)
        return (x, P, r, S, *ws.SK[self.k & 1])

    def _update(self, z: NDArray, out: tuple[NDArray, ...] | None = None) -> None:
        """Measurement update with a validated ``z`` of shape ``(B, m)``.

        ``out`` is ``None`` (fresh arrays) or the record slices
        ``(x, P, innovation, residual, S)`` of this step, written in place.
        """
        ws, strategy = self._ws, self.strategy
        self.z = z
        d = np.empty((self.batch_size, self.m)) if out is None else out[2]
        H3 = self._measure(z, d)
        R = strategy.measurement_covariance(self)
        n_it = strategy.iterations
        for it in range(n_it):
            if it:
                R = strategy.refine(self)
            self.R = R
            R3 = ws.R3 if R is self.model.R else self._stack3(R, self.m, self.m, "R")
            x, P, r, S, SK, S_inv, K = self._outputs(it + 1 == n_it, out)
            # S = HPH' + R,  K = PH'S^-1,  x = x + Ky,  P = (I-KH)P(I-KH)' + KRK'
            self._ops.gain_update(
                self.x_pred, self.P_pred, R3, d, H3, ws.cfg, z, it + 1 == n_it,
                S, SK, x, P, r, ws.work, ws.nt, ws.mt,
            )  # fmt: skip
            self.S, self.S_inv, self.K, self.x, self.P = S, S_inv, K, x, P
            if self.robust is not None:
                self._huber(H3, d, R3)
            if ws.kind == 3 or self.robust is not None:
                self._residual(r)
            else:
                self.residual = r
        strategy.observe(self)

    def _huber(self, H3: NDArray, d: NDArray, R3: NDArray) -> None:
        """Replace ``x(k|k)``, ``P(k|k)`` by the Huber update (docs/algorithms.md §G5)."""
        rob = self.robust
        x, P, psi, failed = steps.huber_update(
            self.x_pred, self.P_pred, d, H3, R3, rob.kappa, rob.iterations, rob.tol
        )
        self.failed |= failed
        self.huber_weights = psi
        self.x[...] = x
        self.P[...] = P

    def _residual(self, out: NDArray) -> None:
        """``r = z - h(x(k|k))`` (angles wrapped) into ``out``."""
        model = self.model
        z_hat = steps.matvec(model.H, self.x) if model.h is None else model.h(self.x, self.k)
        np.subtract(self.z, z_hat, out=out)
        self.residual = steps.wrap_columns(out, model.angle_measurements)

    def update(self, z: ArrayLike) -> None:
        """Measurement update with ``z`` of shape ``(B, m)`` (or ``(m,)`` when ``B = 1``).

        Raises
        ------
        NoisevarError
            When ``z`` has the wrong shape or contains NaN.
        """
        z = np.asarray(z, dtype=float)
        if z.ndim == 1:
            z = z[None, :]
        if z.shape != (self.batch_size, self.m):
            raise NoisevarError(
                f"measurement has shape {z.shape}, expected ({self.batch_size}, {self.m})"
            )
        if not np.all(np.isfinite(z)):
            raise NoisevarError(
                f"measurement at step {self.k} contains NaN or infinite values: "
                "drop or interpolate missing samples (or call skip_update())"
            )
        self._update(z)

    def skip_update(self) -> None:
        """No measurement this step: ``x(k|k) = x(k|k-1)``, ``P(k|k) = P(k|k-1)``.

        Used for a missing sample, or by a fusion centre for a local filter
        flagged faulty (it then adds nothing to the fused information).
        """
        self.x = self.x_pred
        self.P = self.P_pred
        self.innovation = np.full_like(self.innovation, np.nan)
        self.residual = np.full_like(self.residual, np.nan)

    def project(self, P: NDArray) -> NDArray:
        """``H P Hᵀ`` with the current measurement Jacobian (e.g. ``H P(k|k) Hᵀ``).

        Parameters
        ----------
        P : ndarray, shape (B, n, n)

        Returns
        -------
        ndarray, shape (B, m, m)
        """
        ws = self._ws
        if ws.kind == 0:
            return P
        if ws.kind == 1:
            return P[:, ws.sel][:, :, ws.sel]
        H = self.H_used
        return H @ P @ H.mT

    # ------------------------------------------------------------------ health
    def reset_runs(self, runs: NDArray) -> None:
        """Put diverged runs back to ``x0, P0`` so the batch's linear algebra stays finite.

        Parameters
        ----------
        runs : ndarray of bool, shape (B,)
            Runs to reset (their results are reported as diverged by the caller).
        """
        self.x = np.array(self.x)
        self.P = np.array(self.P)
        self.x[runs] = (
            self.model.x0
            if self.x0 is None
            else np.broadcast_to(np.asarray(self.x0, dtype=float), self.x.shape)[runs]
        )
        self.P[runs] = self.model.P0
        self.strategy.reset_runs(self, runs)

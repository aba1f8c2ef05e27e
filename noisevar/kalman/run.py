"""A whole record through the filter: :func:`run_filter` -> :class:`FilterResult`.

The loop writes each step's ``x, P, d, r, S`` (and ``x_pred, P_pred``) straight
into the records, checks divergence every few steps, and computes NIS / NEES
over the stored arrays afterwards (docs/algorithms.md §G4).
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman.divergence import (
    DivergenceCheck,
    check_block,
    check_consistency,
    quadratic_form_inverse,
)
from noisevar.kalman.filter import KalmanFilter
from noisevar.kalman.model import HuberUpdate, StateSpaceModel
from noisevar.kalman.result import FilterResult, wrap_angle

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.strategies.base import RStrategy

#: Result arrays blanked (NaN) after a run blew up.
_STATE_KEYS = (
    "x", "x_pred", "P", "P_pred", "innovation", "innovation_cov", "residual", "nis", "nees",
)  # fmt: skip


def _as_record(z: ArrayLike, m: int, name: str) -> tuple[NDArray, bool]:
    """``z`` as ``(B, N, m)`` floats, and whether it was batched."""
    try:
        arr = np.asarray(z, dtype=float)
    except (TypeError, ValueError):
        raise NoisevarError(f"{name} must be numeric") from None
    if arr.ndim == 1 and m == 1:
        arr = arr[:, None]
    if arr.ndim == 2:
        if arr.shape[1] != m:
            raise NoisevarError(
                f"{name} has shape {arr.shape}; expected (n_steps, {m}) for this model"
            )
        return arr[None], False
    if arr.ndim == 3:
        if arr.shape[2] != m:
            raise NoisevarError(
                f"{name} has shape {arr.shape}; expected (runs, n_steps, {m}) for this model"
            )
        return arr, True
    raise NoisevarError(
        f"{name} must have shape (n_steps, {m}) or (runs, n_steps, {m}), got {arr.shape}"
    )


def _validate(
    model: StateSpaceModel, z: ArrayLike, truth: ArrayLike | None, strategy: RStrategy | None
) -> tuple[NDArray, bool, NDArray | None, RStrategy]:
    """Checked measurements ``(B, N, m)``, batched flag, truth ``(B, N, n)`` and strategy."""
    from noisevar.kalman.strategies import FixedR, RStrategy

    if not isinstance(model, StateSpaceModel):
        raise NoisevarError("model must be a noisevar.kalman.StateSpaceModel")
    n, m = model.n_states, model.n_measurements
    zb, batched = _as_record(z, m, "z")
    if not np.all(np.isfinite(zb)):
        bad = np.argwhere(~np.isfinite(zb))[0]
        raise NoisevarError(
            f"measurements contain NaN or infinite values (first at step {bad[1]}, "
            f"channel {bad[2]}): drop or interpolate missing samples first"
        )
    B, N, _ = zb.shape
    if N == 0:
        raise NoisevarError("the measurement record is empty")
    truth_b = None
    if truth is not None:
        truth_b, _ = _as_record(truth, n, "truth")
        if truth_b.shape[1] != N or truth_b.shape[0] not in (1, B):
            raise NoisevarError(
                f"truth has shape {np.shape(truth)} but the measurements are {zb.shape[:2]} "
                "(runs, steps)"
            )
        truth_b = np.broadcast_to(truth_b, (B, N, n))
    strategy = FixedR() if strategy is None else strategy
    if not isinstance(strategy, RStrategy):
        raise NoisevarError(
            f"strategy must be an RStrategy instance, got {type(strategy).__name__}"
        )
    return zb, batched, truth_b, strategy


class _Records:
    """Per-step records, (step, run) layout; ``R`` / ``Q`` once they differ from the model's."""

    def __init__(self, model: StateSpaceModel, N: int, B: int, store_predicted: bool) -> None:
        n, m = model.n_states, model.n_measurements
        self.model, self.N, self.B = model, N, B
        self.x, self.P = np.empty((N, B, n)), np.empty((N, B, n, n))
        self.d, self.r, self.S = np.empty((N, B, m)), np.empty((N, B, m)), np.empty((N, B, m, m))
        self.xp = np.empty((N, B, n)) if store_predicted else None
        self.Pp = np.empty((N, B, n, n)) if store_predicted else None
        # predictions that are not recorded go to two alternating buffers (a
        # hook may still read the previous step's)
        self._pred_buf = [(np.empty((B, n)), np.empty((B, n, n))) for _ in range(2)]
        self.R: NDArray | None = None
        self.Q: NDArray | None = None

    def predicted(self, k: int) -> tuple[NDArray, NDArray]:
        """Where step ``k`` writes ``x_pred, P_pred``."""
        if self.xp is None:
            return self._pred_buf[k & 1]
        return self.xp[k], self.Pp[k]

    def updated(self, k: int) -> tuple[NDArray, ...]:
        """Where step ``k`` writes ``x, P, innovation, residual, S``."""
        return self.x[k], self.P[k], self.d[k], self.r[k], self.S[k]

    def keep(
        self, k: int, filt: KalmanFilter, pred: tuple[NDArray, ...], out: tuple[NDArray, ...]
    ) -> None:
        """Copy what a hook replaced into the records; record ``R_k``, ``Q_k``.

        ``R`` / ``Q`` records are allocated when a strategy first departs from the model's.
        """
        slots, values = out, (filt.x, filt.P, filt.innovation, filt.residual, filt.S)
        if self.xp is not None:
            slots, values = (*pred, *out), (filt.x_pred, filt.P_pred, *values)
        for slot, value in zip(slots, values, strict=True):
            if value is not slot:
                slot[...] = value
        R, Q = filt.R, filt.Q
        if self.R is not None:
            self.R[k] = R
        elif R is not self.model.R:
            self.R = np.empty(self.S.shape)
            self.R[:k] = self.model.R
            self.R[k] = R
        if self.Q is not None:
            self.Q[k] = Q
        elif Q is not self.model.Q:
            self.Q = np.empty(self.P.shape)
            self.Q[:k] = self.model.Q
            self.Q[k] = Q

    def outputs(self) -> dict[str, NDArray | None]:
        """The records as ``(B, N, ...)`` views (``R`` / ``Q`` never changed: broadcast views)."""
        R = self.R if self.R is not None else np.broadcast_to(self.model.R, self.S.shape)
        Q = self.Q if self.Q is not None else np.broadcast_to(self.model.Q, self.P.shape)
        named = {
            "x": self.x, "x_pred": self.xp, "P": self.P, "P_pred": self.Pp,
            "innovation": self.d, "innovation_cov": self.S, "residual": self.r, "R": R, "Q": Q,
        }  # fmt: skip
        return {k: None if v is None else np.moveaxis(v, 0, 1) for k, v in named.items()}


def _consistency(
    rec: _Records, truth_b: NDArray | None, div: DivergenceCheck, div_step: NDArray, reasons: list
) -> tuple[NDArray, NDArray | None]:
    """NIS, NEES (on the (step, run) layout) and their windowed divergence tests."""
    model = rec.model
    nis = quadratic_form_inverse(rec.S, rec.d).T
    nees = None
    if truth_b is not None:
        err = rec.x - np.moveaxis(truth_b, 1, 0)
        for i in model.angle_states:
            err[..., i] = wrap_angle(err[..., i])
        nees = quadratic_form_inverse(rec.P, err).T
    check_consistency(nis, model.n_measurements, div, div_step, reasons, "NIS", "innovations")
    if nees is not None:
        check_consistency(nees, model.n_states, div, div_step, reasons, "NEES", "estimation errors")
    return nis, nees


def _blank_blown_runs(outs: dict, div_step: NDArray, reasons: list[str]) -> None:
    """NaN out what a run computed after it blew up (not after a NIS/NEES flag)."""
    for b, (s, r) in enumerate(zip(div_step, reasons, strict=True)):
        if s >= 0 and not r.startswith(("NIS", "NEES")):
            for key in _STATE_KEYS:
                if outs[key] is not None:
                    outs[key][b, s:] = np.nan


def run_filter(
    model: StateSpaceModel,
    z: ArrayLike,
    strategy: RStrategy | None = None,
    robust: HuberUpdate | None = None,
    truth: ArrayLike | None = None,
    store_predicted: bool = True,
    divergence: DivergenceCheck | None = None,
    x0: ArrayLike | None = None,
) -> FilterResult:
    """Run the filter over a whole record (or a batch of Monte Carlo records).

    Parameters
    ----------
    model : StateSpaceModel
        The model.
    z : array_like, shape (N, m) or (B, N, m)
        Measurements; a leading axis runs ``B`` independent records in lock-step.
    strategy : RStrategy, optional
        R-adaptation strategy (default :class:`~noisevar.kalman.FixedR`).
        A strategy object keeps state: use a fresh one per call.
    robust : HuberUpdate, optional
        Huber M-estimation update (docs/algorithms.md §G5).
    truth : array_like, shape (N, n) or (B, N, n), optional
        True states; enables NEES, RMSE and the NEES divergence test.
    store_predicted : bool
        Also record ``x_pred`` and ``P_pred`` at every step.
    divergence : DivergenceCheck, optional
        Divergence criteria (default :class:`DivergenceCheck`).
    x0 : array_like, shape (n,) or (B, n), optional
        Initial state per run (default ``model.x0``).

    Returns
    -------
    FilterResult
        Per-step records, NIS/NEES, and an honest divergence report.

    Raises
    ------
    NoisevarError
        For bad shapes, NaN measurements, or an invalid strategy.
    """
    zb, batched, truth_b, strategy = _validate(model, z, truth, strategy)
    B, N, _ = zb.shape
    div = divergence or DivergenceCheck()
    cov_limit = div.covariance_limit
    if cov_limit is None:
        cov_limit = 1e6 * max(float(np.max(np.diag(model.P0))), float(np.max(np.diag(model.R))))
    strategy.prepare(zb, model)
    filt = KalmanFilter(model, strategy=strategy, robust=robust, batch_size=B, x0=x0)
    rec = _Records(model, N, B, store_predicted)
    z_steps = np.ascontiguousarray(np.moveaxis(zb, 1, 0))
    div_step, reasons = np.full(B, -1), [""] * B
    check_every = max(1, int(div.check_every))
    last_check = 0
    # a singular S or a NaN state gives NaN (no exception) and is reported below
    with np.errstate(invalid="ignore", divide="ignore", over="ignore"):
        for k in range(N):
            pred, out = rec.predicted(k), rec.updated(k)
            filt._predict(*pred)
            filt._update(z_steps[k], out)
            rec.keep(k, filt, pred, out)
            if k + 1 == min(last_check + check_every, N):
                newly = check_block(
                    rec.x, filt.P, filt.failed, last_check, k + 1, cov_limit, div_step, reasons
                )
                if newly.any():
                    filt.failed &= ~newly
                    filt.reset_runs(newly)
                last_check = k + 1
    nis, nees = _consistency(rec, truth_b, div, div_step, reasons)
    outs = {**rec.outputs(), "nis": nis, "nees": nees}
    _blank_blown_runs(outs, div_step, reasons)
    diverged = div_step >= 0
    truth_out = None if truth_b is None else np.array(truth_b)
    if not batched:
        outs = {k: (None if v is None else v[0]) for k, v in outs.items()}
        truth_out = None if truth_out is None else truth_out[0]
    return FilterResult(
        strategy=strategy.name + ("+huber" if robust is not None else ""),
        time=np.arange(N) * model.dt,
        truth=truth_out,
        diverged=diverged if batched else bool(diverged[0]),
        divergence_step=div_step if batched else int(div_step[0]),
        divergence_reason=reasons if batched else reasons[0],
        batched=batched,
        state_names=model.state_names,
        measurement_names=model.measurement_names,
        angle_states=model.angle_states,
        **outs,
    )

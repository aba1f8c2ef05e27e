"""Strategies that do not adapt: :class:`FixedR` (the model's ``R``) and :class:`OracleR`."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman.model import check_covariance
from noisevar.kalman.strategies.base import RStrategy

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.filter import KalmanFilter


class FixedR(RStrategy):
    """Fixed ``R``: the model's nominal one, or a given matrix.

    Parameters
    ----------
    R : array_like, shape (m, m), optional
        The covariance to use (default ``model.R``).
    """

    name = "fixed"

    def __init__(self, R: ArrayLike | None = None) -> None:
        self.R = None if R is None else check_covariance(R, "R")

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        if self.R is not None and self.R.shape != filt.model.R.shape:
            raise NoisevarError(
                f"FixedR got R of shape {self.R.shape}, the model measures {filt.m} channels"
            )
        self._R = filt.model.R if self.R is None else self.R

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        return self._R


class OracleR(RStrategy):
    """The true ``R`` at every step: the lower bound for every adaptive filter.

    Parameters
    ----------
    R_true : array_like
        ``(m, m)`` constant, ``(N, m, m)`` per step, or ``(B, N, m, m)`` per
        run and step (a vector ``(m,)`` / ``(N, m)`` / ``(B, N, m)`` is taken
        as variances on the diagonal).
    """

    name = "oracle"

    def __init__(self, R_true: ArrayLike) -> None:
        arr = np.asarray(R_true, dtype=float)
        if not np.all(np.isfinite(arr)) or np.any(arr.reshape(-1) < 0) and arr.ndim <= 1:
            raise NoisevarError("R_true must be finite (and non-negative variances)")
        self.R_true = arr

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        m = filt.m
        arr = self.R_true
        # diagonal forms: the last axis is the channel, not a matrix
        if arr.ndim >= 1 and arr.shape[-1] == m and (arr.ndim < 2 or arr.shape[-2] != m):
            arr = arr[..., :, None] * np.eye(m)
        if arr.ndim == 2:
            check_covariance(arr, "R_true")
            arr = arr[None, None]
        elif arr.ndim == 3:
            arr = arr[None]
        if arr.ndim != 4 or arr.shape[-2:] != (m, m) or arr.shape[0] not in (1, filt.batch_size):
            raise NoisevarError(
                f"R_true has shape {self.R_true.shape}; expected ({m}, {m}), (N, {m}, {m}) "
                f"or ({filt.batch_size}, N, {m}, {m})"
            )
        self._R = np.broadcast_to(arr, (filt.batch_size, *arr.shape[1:]))
        # contiguous, writeable arrays (a read-only broadcast view would be
        # one more compiled variant of the kernels)
        self._R_const = np.ascontiguousarray(self._R[:, 0]) if self._R.shape[1] == 1 else None

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        R = self._R
        if R.shape[1] == 1:
            return self._R_const
        if filt.k >= R.shape[1]:
            raise NoisevarError(f"R_true has {R.shape[1]} steps but the filter is at step {filt.k}")
        Rk = np.ascontiguousarray(R[:, filt.k])
        return self._guard_dead(Rk)

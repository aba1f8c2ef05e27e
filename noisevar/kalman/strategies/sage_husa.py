"""The Sage-Husa recursive estimator with forgetting (docs/algorithms.md §B4)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman.strategies.base import diag
from noisevar.kalman.strategies.windowed import _WindowedR

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.filter import KalmanFilter


class SageHusaR(_WindowedR):
    """Sage-Husa recursive estimator with a forgetting factor (docs/algorithms.md §B4)::

        R_k = (1 - d_k) R_{k-1} + d_k (d dᵀ - H P(k|k-1) Hᵀ),
        d_k = (1 - b) / (1 - b^(k+1))

    It is known to lose positive definiteness (the subtraction); the guard
    drops the ``- H P Hᵀ`` term for a component whose variance would fall
    below ``floor`` times the nominal one (the usual biased-but-positive
    fallback), then clips; ``guard_count`` counts the steps it fired.

    Parameters
    ----------
    forgetting : float
        ``b`` in ``(0, 1)``, typically 0.95 to 0.995.
    diagonal : bool
        Estimate only the variances or the full matrix.
    floor : float
        Guard threshold as a fraction of the nominal variances.
    """

    name = "sage-husa"
    _state_fields = (*_WindowedR._state_fields, "_est")

    def __init__(
        self, forgetting: float = 0.98, diagonal: bool = True, floor: float = 1e-4
    ) -> None:
        if not (0 < forgetting < 1):
            raise NoisevarError(
                f"forgetting factor b must be in (0, 1) (typically 0.95-0.995), got {forgetting}"
            )
        self.forgetting = float(forgetting)
        self.diagonal = bool(diagonal)
        if not (0 < floor < 1):
            raise NoisevarError(f"floor must be in (0, 1), got {floor}")
        self.floor = float(floor)
        self.window = 1
        self.warmup = 1

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        self._est = (
            np.repeat(np.diag(filt.model.R)[None], filt.batch_size, axis=0)
            if self.diagonal
            else np.repeat(filt.model.R[None], filt.batch_size, axis=0)
        )
        self._power = 1.0

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        b = self.forgetting
        self._power *= b  # b^(k+1)
        dk = (1.0 - b) / (1.0 - self._power)
        d = filt.innovation
        hph = diag(filt.HPHt) if self.diagonal else filt.HPHt
        if self.diagonal:
            # R = (1 - d_k) R + d_k (d d' - HPH'), with the fallback and the floor
            B, m = d.shape
            est = np.empty((B, m))
            R = np.empty((B, m, m))
            self._ops.sage_husa_diag(self._est, d, hph, dk, self._floor, self.guard_count, est, R)
            self._est = est
            return self._guard_dead(R)
        outer = self._outer(d, self.diagonal)
        est = (1.0 - dk) * self._est + dk * (outer - hph)
        if self.diagonal:
            low = est < self._floor
            if np.count_nonzero(low):  # cheaper than low.any() on tiny arrays
                self.guard_count += low.any(axis=1)
                est = np.where(low, (1.0 - dk) * self._est + dk * outer, est)
        else:
            low = np.linalg.eigvalsh(est)[:, 0] < float(np.min(self._floor))
            if np.count_nonzero(low):  # cheaper than low.any() on tiny arrays
                self.guard_count += low
                est[low] = (1.0 - dk) * self._est[low] + dk * outer[low]
        self._est = est
        return self._to_R(est)

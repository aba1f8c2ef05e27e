"""Variational-Bayes adaptive KF, one inverse-gamma per channel (docs/algorithms.md §B2)."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman.strategies.base import RStrategy, check_window

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.filter import KalmanFilter


class VariationalBayesR(RStrategy):
    """Variational-Bayes adaptive KF (docs/algorithms.md §B2; Särkkä & Nummenmaa 2009).

    One inverse-gamma ``IG(α_j, β_j)`` per measurement channel (diagonal
    ``R``). Predict ``α⁻ = ρ α``, ``β⁻ = ρ β`` (paper eq. (29)); update
    ``α = α⁻ + 1/2`` and iterate::

        R̂ = diag(β / α);  KF update with R̂;
        β = β⁻ + (z - h(x̂(k|k)))² / 2 + diag(H P(k|k) Hᵀ) / 2        (30)

    using the updated ``x̂, P`` inside the iteration, as in the original
    article (the seed paper's print uses the predicted state).

    Parameters
    ----------
    rho : float
        Forgetting ``ρ`` in ``(0, 1]`` (1: a stationary ``R``; 0.99: the
        paper's, about 100 steps of memory).
    alpha0 : float
        Initial ``α`` (paper: 1).
    beta0 : array_like, optional
        Initial ``β`` per channel (paper: ``[2, 2, 2, 0.1, 0.1, 0.1]``);
        default ``alpha0 · diag(model.R)`` so the first ``R̂`` is the model's.
    iterations : int
        Update iterations per step (Särkkä & Nummenmaa use a few; 3 here).
    """

    name = "vb"
    _state_fields = ("_dead", "_alpha", "_beta", "_beta_pred")

    def __init__(
        self,
        rho: float = 0.99,
        alpha0: float = 1.0,
        beta0: ArrayLike | None = None,
        iterations: int = 3,
    ) -> None:
        if not (0 < rho <= 1):
            raise NoisevarError(f"rho must be in (0, 1] (e.g. 0.99), got {rho}")
        if not (alpha0 > 0):
            raise NoisevarError(f"alpha0 must be positive, got {alpha0}")
        self.rho = float(rho)
        self.alpha0 = float(alpha0)
        self.beta0 = None if beta0 is None else np.asarray(beta0, dtype=float)
        self.iterations = check_window(iterations, "iterations")

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        B, m = filt.batch_size, filt.m
        beta0 = self.alpha0 * np.diag(filt.model.R) if self.beta0 is None else self.beta0
        if beta0.shape != (m,) or not np.all(beta0 > 0):
            raise NoisevarError(f"beta0 must hold {m} positive values, got {beta0!r}")
        # the kernels update α, β, β⁻ in place
        self._alpha = np.full((B, m), self.alpha0)
        self._beta = np.repeat(beta0[None], B, axis=0)
        self._beta_pred = np.empty_like(self._beta)
        self._no_R = np.empty((0, 0, 0))
        self._shape_R = (B, m, m)

    def _beta_update(self, filt: KalmanFilter, want_R: bool) -> NDArray:
        """``β = β⁻ + r²/2 + diag(H P Hᵀ)/2`` (30) and, when ``want_R``, ``R̂ = diag(β/α)``."""
        R = np.empty(self._shape_R) if want_R else self._no_R
        self._ops.vb_beta(
            self._beta_pred,
            filt.residual,
            filt.project(filt.P),
            self._alpha,
            self._beta,
            R,
            want_R,
        )
        return self._guard_dead(R) if self._any_dead and want_R else R

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        R = np.empty(self._shape_R)
        # α = ρα + 1/2,  β⁻ = ρβ,  R̂ = diag(β⁻/α)
        self._ops.vb_predict(self._alpha, self._beta, self.rho, self._beta_pred, R)
        return self._guard_dead(R) if self._any_dead else R

    def refine(self, filt: KalmanFilter) -> NDArray:
        return self._beta_update(filt, True)

    def observe(self, filt: KalmanFilter) -> None:
        self._beta_update(filt, False)

    def reset_runs(self, filt: KalmanFilter, runs: NDArray) -> None:
        super().reset_runs(filt, runs)
        self._alpha[runs] = self.alpha0
        self._beta[runs] = np.diag(filt.model.R) * self.alpha0

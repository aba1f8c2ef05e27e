"""Moving-window strategies: RAE, IAE (docs/algorithms.md §A10), RAE-Q (§B1), MovingMean."""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman.strategies.base import RStrategy, check_window, diag, diag_matrix

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.filter import KalmanFilter


class MovingMean:
    """Mean of the last ``size`` pushed arrays (batched), running mean before that.

    The windowed averages of the residual-based strategies (RAE, IAE, the
    AEKF of :mod:`noisevar.systems.carrier`). O(1) per push: a running sum with a
    circular buffer, re-summed exactly once per wrap-around so rounding
    cannot drift.

    Parameters
    ----------
    size : int
        Window length (pushes).
    shape : tuple of int
        Shape of each pushed array (a batch axis first, for Monte Carlo runs).
    """

    def __init__(self, size: int, shape: tuple[int, ...]) -> None:
        self.size = size
        self.buf = np.zeros((size, *shape))
        self.sum = np.zeros(shape)
        self.count = 0
        self.pos = 0

    def push(self, v: NDArray) -> None:
        """Add one array to the window (dropping the oldest once it is full)."""
        if self.count >= self.size:
            self.sum -= self.buf[self.pos]
        self.buf[self.pos] = v
        self.sum += v
        self.count += 1
        self.pos += 1
        if self.pos == self.size:
            self.pos = 0
            self.sum = self.buf.sum(axis=0)

    def mean(self) -> NDArray:
        """Mean over the window (over every push so far, before the window fills)."""
        return self.sum / min(self.count, self.size)

    def advance(self) -> None:
        """Count a push a compiled kernel made (it updated ``buf`` and ``sum`` in place)."""
        self.count += 1
        self.pos += 1
        if self.pos == self.size:
            self.pos = 0


class _WindowedR(RStrategy):
    """Common parts of the moving-window estimators (RAE, IAE, B1)."""

    _state_fields = ("_dead", "_R", "guard_count")

    def __init__(
        self,
        window: int = 50,
        diagonal: bool = True,
        warmup: int | None = None,
        floor: float = 1e-4,
    ) -> None:
        self.window = check_window(window)
        self.diagonal = bool(diagonal)
        self.warmup = self.window if warmup is None else check_window(warmup, "warmup")
        if not (0 < floor < 1):
            raise NoisevarError(
                f"floor must be in (0, 1) (a fraction of the nominal R), got {floor}"
            )
        self.floor = float(floor)

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        B, m = filt.batch_size, filt.m
        shape = (B, m) if self.diagonal else (B, m, m)
        self._cov = MovingMean(self.window, shape)
        self._R = np.repeat(filt.model.R[None], B, axis=0)
        self._floor = self.floor * np.diag(filt.model.R)
        self.guard_count = np.zeros(B, dtype=np.int64)
        self._no_R = np.empty((0, 0, 0))

    def _window_step(self, u: NDArray, hph: NDArray, sign: float) -> NDArray | None:
        """Compiled push of ``u²`` and, once warmed up, ``R = diag(mean ± hph)`` (guarded)."""
        cov = self._cov
        adapt = cov.count + 1 >= self.warmup
        B, m = u.shape
        R = np.empty((B, m, m)) if adapt else self._no_R
        self._ops.window_diag(
            cov.buf,
            cov.sum,
            cov.count,
            cov.pos,
            u,
            hph,
            sign,
            adapt,
            self._floor,
            self.guard_count,
            R,
        )
        cov.advance()
        return self._guard_dead(R) if adapt else None

    @staticmethod
    def _outer(v: NDArray, diagonal: bool) -> NDArray:
        return v * v if diagonal else v[:, :, None] * v[:, None, :]

    def _to_R(self, est: NDArray) -> NDArray:
        """Positive-definite guard: clip variances (or eigenvalues) to the floor."""
        if self.diagonal:
            low = est < self._floor
            if np.count_nonzero(low):  # cheaper than low.any() on tiny arrays
                self.guard_count += low.any(axis=1)
                est = np.maximum(est, self._floor)
            return self._guard_dead(diag_matrix(est))
        w, V = np.linalg.eigh(est)
        floor = float(np.min(self._floor))
        low = w < floor
        if np.count_nonzero(low):  # cheaper than low.any() on tiny arrays
            self.guard_count += low.any(axis=1)
            w = np.maximum(w, floor)
            est = (V * w[:, None, :]) @ V.mT
        return self._guard_dead(0.5 * (est + est.mT))


class ResidualR(_WindowedR):
    """Residual-based adaptive estimation (RAE), docs/algorithms.md §A10::

        R_k = mean_{j in window}(r_j r_jᵀ) + H P(k-1|k-1) Hᵀ

    ``r_j = z_j - h(x̂(j|j))`` over the last ``window`` steps (the paper's
    eq. (3) prints the sign of ``HPHᵀ`` the other way round; this is the
    standard, correct one). The current residual needs ``R_k``, so the
    window ends at the previous step. Always positive definite.

    Parameters
    ----------
    window : int
        Moving-window length ``N``.
    diagonal : bool
        Estimate only the variances (the paper's Table 1) or the full matrix.
    warmup : int, optional
        Steps of residuals to collect before adapting (default ``window``);
        until then the model's ``R`` is used.
    floor : float
        Positive-definite guard: variances are kept above ``floor`` times the
        nominal ones (counted in ``guard_count``).
    """

    name = "rae"

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        return self._guard_dead(self._R)  # updated in observe() once warmed up

    def observe(self, filt: KalmanFilter) -> None:
        r = filt.residual
        HPHt = filt.project(filt.P)
        if self.diagonal:
            # R = mean(r r') + HPH'   (a compiled kernel when available)
            R = self._window_step(r, diag(HPHt), 1.0)
            if R is not None:
                self._R = R
            return
        self._cov.push(self._outer(r, self.diagonal))
        if self._cov.count >= self.warmup:
            hph = diag(HPHt) if self.diagonal else HPHt
            self._R = self._to_R(self._cov.mean() + hph)


class InnovationR(_WindowedR):
    """Innovation-based adaptive estimation (IAE), docs/algorithms.md §A10::

        R_k = mean_{j in window}(d_j d_jᵀ) - H P(k|k-1) Hᵀ

    ``d_j = z_j - h(x̂(j|j-1))`` over the last ``window`` steps, the current
    one included (it is known before the update). The difference can lose
    positive definiteness: the guard clips variances (eigenvalues) to
    ``floor`` times the nominal ones and counts it in ``guard_count``.

    Parameters
    ----------
    window, diagonal, warmup, floor
        As for :class:`ResidualR`.
    """

    name = "iae"

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        if self.diagonal:
            # R = mean(d d') - HPH'
            R = self._window_step(filt.innovation, diag(filt.HPHt), -1.0)
            return self._guard_dead(self._R) if R is None else R
        self._cov.push(self._outer(filt.innovation, self.diagonal))
        if self._cov.count < self.warmup:
            return self._guard_dead(self._R)
        hph = diag(filt.HPHt) if self.diagonal else filt.HPHt
        return self._to_R(self._cov.mean() - hph)


class ResidualQR(ResidualR):
    """Residual-based ``R`` with innovation-based ``Q`` (docs/algorithms.md §B1, eqs. [14]-[26])::

        Ĉ_d = mean of d dᵀ  (running mean for k <= W, then last W steps)   [14]
        R̂  = Ĉ_r + H P(k|k) Hᵀ                                           [22]
        Q̂  = K Ĉ_d Kᵀ                                                     [26]

    ``R̂`` is the RAE estimate (positive definite by construction); ``Q̂``
    replaces the model's ``Q`` from the step after the first observation.
    With fewer measurements than states ``Q̂`` has rank ``m`` only.

    Parameters
    ----------
    window : int
        ``W``.
    diagonal : bool
        Diagonal ``R̂`` (``Q̂`` is always full).
    warmup : int
        Steps before adapting (default 1: the paper's running mean).
    floor : float
        Positive-definite guard on ``R̂``.
    """

    name = "rae-q"
    _state_fields = (*_WindowedR._state_fields, "_Q")

    def __init__(
        self, window: int = 50, diagonal: bool = True, warmup: int | None = 1, floor: float = 1e-4
    ) -> None:
        super().__init__(window=window, diagonal=diagonal, warmup=warmup, floor=floor)

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        self._innov = MovingMean(self.window, (filt.batch_size, filt.m, filt.m))
        self._Q: NDArray | None = None

    def process_covariance(self, filt: KalmanFilter) -> NDArray | None:
        if self._Q is not None and self._any_dead:
            self._Q[self._dead] = filt.model.Q
        return self._Q

    def observe(self, filt: KalmanFilter) -> None:
        super().observe(filt)
        d = filt.innovation
        innov = self._innov
        adapt = innov.count + 1 >= self.warmup
        Q = np.empty((filt.batch_size, filt.n, filt.n)) if adapt else self._no_R
        # C_d = mean(d d'),  Q = K C_d K'
        self._ops.outer_q(innov.buf, innov.sum, innov.count, innov.pos, d, adapt, filt.K, Q)
        innov.advance()
        if adapt:
            self._Q = Q

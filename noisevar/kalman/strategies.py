"""R-adaptation strategies: small objects that plug into the one filter core.

A strategy is asked, at every step, for the measurement covariance ``R_k``
(and may override the process covariance ``Q_k``). It sees the filter's
current quantities (batched, see :class:`~noisevar.kalman.core.KalmanFilter`)
and keeps its own state across steps. A new strategy is one new subclass of
:class:`RStrategy`; it never copies the filter.

Hooks, in the order the core calls them at step ``k``:

``process_covariance(filt)``
    before the time update; ``Q_k`` or ``None`` (use ``model.Q``).
``measurement_covariance(filt)``
    after the innovation ``d_k = z_k - h(x(k|k-1))`` and ``H P(k|k-1) Hᵀ``
    (``filt.HPHt``) are known; returns ``R_k``.
``refine(filt)``
    only for ``iterations > 1`` (variational Bayes): after each update
    iteration, returns the next ``R_k`` given ``x(k|k), P(k|k)``.
``observe(filt)``
    after the final update: residual ``r_k``, gain ``K_k``, ``P(k|k)``.

Strategies here:

=================  =========================================================
``fixed``          the model's ``R`` (or one given)
``oracle``         the true ``R`` (time-varying allowed): the lower bound
``somd-online``    our SOMD estimator over a trailing window per channel,
                   re-estimated every ``N`` steps, independent of the filter
``rae``            residual-based, spec A10
``iae``            innovation-based, spec A10
``rae-q``          residual-based ``R`` and ``Q = K C_d Kᵀ`` (spec B1)
``sage-husa``      recursive with forgetting factor (spec B4)
``vb``             variational Bayes, inverse-gamma per channel (spec B2)
=================  =========================================================

The robust Huber update (spec B3) is not a strategy but an option of the
core (:class:`~noisevar.kalman.core.HuberUpdate`) and combines with all of
these.
"""

from __future__ import annotations

import warnings
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman import core
from noisevar.kalman.core import check_covariance
from noisevar.params import ParamSpec

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.core import KalmanFilter, StateSpaceModel


class RStrategy:
    """Base class: the interface every R-adaptation strategy implements.

    Attributes
    ----------
    name : str
        Short name used in results and tables.
    iterations : int
        Number of measurement-update iterations per step (1 except for VB).
    """

    name = "base"
    iterations = 1

    def prepare(self, z: NDArray, model: StateSpaceModel) -> None:  # noqa: B027
        """Called by :func:`~noisevar.kalman.core.run_filter` with the whole record.

        Strategies independent of the filter's state (oracle, somd-online)
        may precompute here; step-by-step use never calls it.

        Parameters
        ----------
        z : ndarray, shape (B, N, m)
            All measurements.
        model : StateSpaceModel
            The model.
        """

    def start(self, filt: KalmanFilter) -> None:
        """Initialise per-run state (called once by the filter's constructor)."""
        self._dead = np.zeros(filt.batch_size, dtype=bool)
        self._any_dead = False
        self._R0 = filt.model.R

    def process_covariance(self, filt: KalmanFilter) -> NDArray | None:
        """``Q_k`` for the coming time update, or ``None`` for ``model.Q``."""
        return None

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        """``R_k`` for the coming measurement update (shape ``(B, m, m)`` or ``(m, m)``)."""
        raise NotImplementedError

    def refine(self, filt: KalmanFilter) -> NDArray:
        """Next ``R_k`` after an update iteration (iterative strategies only)."""
        return filt.R

    def observe(self, filt: KalmanFilter) -> None:  # noqa: B027
        """Learn from the finished step (residuals, gain, updated covariance)."""

    def reset_runs(self, filt: KalmanFilter, runs: NDArray) -> None:
        """Runs that diverged: from now on they get ``model.R`` (keeps the batch finite)."""
        self._dead |= runs
        self._any_dead = bool(self._dead.any())

    def _guard_dead(self, R: NDArray) -> NDArray:
        if self._any_dead:
            R = np.array(R)
            R[self._dead] = self._R0
        return R

    def __repr__(self) -> str:
        params = {k: v for k, v in vars(self).items() if not k.startswith("_")}
        inner = ", ".join(f"{k}={v!r}" for k, v in params.items() if np.ndim(v) == 0)
        return f"{type(self).__name__}({inner})"


_EYES: dict[int, NDArray] = {}


def _diag_matrix(v: NDArray) -> NDArray:
    """Batch of diagonal matrices from a batch of vectors ``(B, m) -> (B, m, m)``."""
    m = v.shape[1]
    eye = _EYES.get(m)
    if eye is None:  # cached: np.eye costs as much as the product, at every step
        eye = _EYES[m] = np.eye(m)
        eye.setflags(write=False)
    return v[:, :, None] * eye


def _diag(a: NDArray) -> NDArray:
    """Diagonals of a stack of matrices (a view; the method is ~10x cheaper than np.diagonal)."""
    return a.diagonal(0, -2, -1)


def _check_window(window: Any, name: str = "window") -> int:
    try:
        w = int(window)
    except (TypeError, ValueError):
        raise NoisevarError(f"{name} must be an integer, got {window!r}") from None
    if w < 1 or w != window:
        raise NoisevarError(f"{name} must be a positive integer, got {window!r}")
    return w


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


def _compiled(filt: KalmanFilter) -> bool:
    """Whether the strategy hooks of ``filt`` use the compiled kernels too."""
    return filt._fast


# --------------------------------------------------------------------------- fixed, oracle
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
        # the compiled path gets contiguous, writeable arrays (a read-only
        # broadcast view would be one more compiled variant of the kernels)
        self._contiguous = _compiled(filt)
        self._R_const = (
            np.ascontiguousarray(self._R[:, 0])
            if self._contiguous and self._R.shape[1] == 1
            else None
        )

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        R = self._R
        if R.shape[1] == 1:
            return R[:, 0] if self._R_const is None else self._R_const
        if filt.k >= R.shape[1]:
            raise NoisevarError(f"R_true has {R.shape[1]} steps but the filter is at step {filt.k}")
        Rk = R[:, filt.k]
        if self._contiguous:
            Rk = np.ascontiguousarray(Rk)
        return self._guard_dead(Rk)


# --------------------------------------------------------------------------- RAE / IAE / B1
class _WindowedR(RStrategy):
    """Common parts of the moving-window estimators (RAE, IAE, B1)."""

    def __init__(
        self,
        window: int = 50,
        diagonal: bool = True,
        warmup: int | None = None,
        floor: float = 1e-4,
    ) -> None:
        self.window = _check_window(window)
        self.diagonal = bool(diagonal)
        self.warmup = self.window if warmup is None else _check_window(warmup, "warmup")
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
        self._fast = _compiled(filt) and self.diagonal
        self._no_R = np.empty((0, 0, 0))

    def _window_step(self, u: NDArray, hph: NDArray, sign: float) -> NDArray | None:
        """Compiled push of ``u²`` and, once warmed up, ``R = diag(mean ± hph)`` (guarded)."""
        cov = self._cov
        adapt = cov.count + 1 >= self.warmup
        B, m = u.shape
        R = np.empty((B, m, m)) if adapt else self._no_R
        core._kernels.window_diag(
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
            return self._guard_dead(_diag_matrix(est))
        w, V = np.linalg.eigh(est)
        floor = float(np.min(self._floor))
        low = w < floor
        if np.count_nonzero(low):  # cheaper than low.any() on tiny arrays
            self.guard_count += low.any(axis=1)
            w = np.maximum(w, floor)
            est = (V * w[:, None, :]) @ V.mT
        return self._guard_dead(0.5 * (est + est.mT))


class ResidualR(_WindowedR):
    """Residual-based adaptive estimation (RAE), spec A10::

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
        if self._fast:
            R = self._window_step(r, _diag(HPHt), 1.0)
            if R is not None:
                self._R = R
            return
        self._cov.push(self._outer(r, self.diagonal))
        if self._cov.count >= self.warmup:
            hph = _diag(HPHt) if self.diagonal else HPHt
            self._R = self._to_R(self._cov.mean() + hph)


class InnovationR(_WindowedR):
    """Innovation-based adaptive estimation (IAE), spec A10::

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
        if self._fast:
            R = self._window_step(filt.innovation, _diag(filt.HPHt), -1.0)
            return self._guard_dead(self._R) if R is None else R
        self._cov.push(self._outer(filt.innovation, self.diagonal))
        if self._cov.count < self.warmup:
            return self._guard_dead(self._R)
        hph = _diag(filt.HPHt) if self.diagonal else filt.HPHt
        return self._to_R(self._cov.mean() - hph)


class ResidualQR(ResidualR):
    """Residual-based ``R`` with innovation-based ``Q`` (spec B1, AEKF paper [14]-[26])::

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
        if self._fast:
            innov = self._innov
            adapt = innov.count + 1 >= self.warmup
            Q = np.empty((filt.batch_size, filt.n, filt.n)) if adapt else self._no_R
            core._kernels.outer_q(innov.buf, innov.sum, innov.count, innov.pos, d, adapt, filt.K, Q)
            innov.advance()
            if adapt:
                self._Q = Q
            return
        self._innov.push(d[:, :, None] * d[:, None, :])
        if self._innov.count >= self.warmup:
            K = filt.K
            Q = K @ self._innov.mean() @ K.mT
            self._Q = 0.5 * (Q + Q.mT)


# --------------------------------------------------------------------------- Sage-Husa
class SageHusaR(_WindowedR):
    """Sage-Husa recursive estimator with a forgetting factor (spec B4)::

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
        hph = _diag(filt.HPHt) if self.diagonal else filt.HPHt
        if self._fast:
            B, m = d.shape
            est = np.empty((B, m))
            R = np.empty((B, m, m))
            core._kernels.sage_husa_diag(
                self._est, d, hph, dk, self._floor, self.guard_count, est, R
            )
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


# --------------------------------------------------------------------------- VB
class VariationalBayesR(RStrategy):
    """Variational-Bayes adaptive KF (spec B2; Särkkä & Nummenmaa 2009).

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
        self.iterations = _check_window(iterations, "iterations")

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        B, m = filt.batch_size, filt.m
        beta0 = self.alpha0 * np.diag(filt.model.R) if self.beta0 is None else self.beta0
        if beta0.shape != (m,) or not np.all(beta0 > 0):
            raise NoisevarError(f"beta0 must hold {m} positive values, got {beta0!r}")
        self._alpha = np.full((B, m), self.alpha0)
        self._beta = np.repeat(beta0[None], B, axis=0)
        self._beta_pred = self._beta
        self._fast = _compiled(filt)
        if self._fast:  # the compiled hooks update α, β, β⁻ in place
            self._beta_pred = np.empty_like(self._beta)
            self._no_R = np.empty((0, 0, 0))
            self._shape_R = (B, m, m)

    def _r_hat(self) -> NDArray:
        return self._guard_dead(_diag_matrix(self._beta / self._alpha))

    def _beta_compiled(self, filt: KalmanFilter, want_R: bool) -> NDArray:
        R = np.empty(self._shape_R) if want_R else self._no_R
        core._kernels.vb_beta(
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
        rho = self.rho
        if self._fast:
            R = np.empty(self._shape_R)
            core._kernels.vb_predict(self._alpha, self._beta, rho, self._beta_pred, R)
            return self._guard_dead(R) if self._any_dead else R
        self._alpha = rho * self._alpha + 0.5
        self._beta_pred = rho * self._beta
        self._beta = self._beta_pred
        return self._r_hat()

    def _update_beta(self, filt: KalmanFilter) -> None:
        HPHt = filt.project(filt.P)
        r = filt.residual
        self._beta = self._beta_pred + 0.5 * r * r + 0.5 * _diag(HPHt)

    def refine(self, filt: KalmanFilter) -> NDArray:
        if self._fast:
            R = np.empty(self._shape_R)
            core._kernels.vb_beta(
                self._beta_pred,
                filt.residual,
                filt.project(filt.P),
                self._alpha,
                self._beta,
                R,
                True,
            )
            return self._guard_dead(R) if self._any_dead else R
        self._update_beta(filt)
        return self._r_hat()

    def observe(self, filt: KalmanFilter) -> None:
        if self._fast:
            self._beta_compiled(filt, False)
            return
        self._update_beta(filt)

    def reset_runs(self, filt: KalmanFilter, runs: NDArray) -> None:
        super().reset_runs(filt, runs)
        self._alpha[runs] = self.alpha0
        self._beta[runs] = np.diag(filt.model.R) * self.alpha0


# --------------------------------------------------------------------------- SOMD online
class SomdOnlineR(RStrategy):
    """Our SOMD estimator over a trailing window of each channel (spec A7/A8).

    Every ``every`` steps the variance of each measured channel is estimated
    from its last ``window`` raw samples (the current one included) with
    :func:`noisevar.estimate` (``method``, ``h_smooth`` per channel,
    ``select=False``), independently of the filter's state, so a lagging
    filter cannot corrupt it (the point of the 2016 paper). Until a channel
    has enough samples for its smoothing filter to settle, its nominal ``R``
    is kept.

    Channels listed in the model's ``angle_measurements`` are unwrapped
    before estimating (a heading that turns through ±π is a continuous
    signal to the estimator).

    :func:`~noisevar.kalman.core.run_filter` gives the whole record to
    :meth:`prepare`, which computes the same estimates for every run and
    re-estimation step at once (one ``lfilter`` call per channel), instead
    of ``B · m`` separate calls per re-estimation; the two paths agree to
    rounding (tested).

    Parameters
    ----------
    h_smooth : float or sequence of float
        Smoothing ``h`` per channel (one value for all).
    window : int, optional
        Trailing window length (default: all samples so far).
    every : int
        Re-estimation interval ``N`` in steps.
    method : {"somd", "somd-paper"}
        Bias-corrected SOMD (default) or the paper's factor 1/2.
    """

    name = "somd-online"

    def __init__(
        self,
        h_smooth: float | ArrayLike = 9e-4,
        window: int | None = None,
        every: int = 100,
        method: str = "somd",
    ) -> None:
        if method not in ("somd", "somd-paper"):
            raise NoisevarError(f"method must be 'somd' or 'somd-paper', got {method!r}")
        self.method = method
        self.h_smooth = np.atleast_1d(np.asarray(h_smooth, dtype=float))
        self.window = None if window is None else _check_window(window)
        self.every = _check_window(every, "every")
        self._schedule: NDArray | None = None
        if method == "somd-paper":
            self.name = "somd-paper-online"

    def _h(self, m: int) -> NDArray:
        if self.h_smooth.size == 1:
            return np.repeat(self.h_smooth, m)
        if self.h_smooth.size != m:
            raise NoisevarError(
                f"h_smooth has {self.h_smooth.size} values but the model measures {m} channels"
            )
        return self.h_smooth

    def _bounds(self, k: int) -> tuple[int, int]:
        start = 0 if self.window is None else max(0, k + 1 - self.window)
        return start, k + 1

    def prepare(self, z: NDArray, model: StateSpaceModel) -> None:
        from noisevar.kalman.somd_batch import somd_variance_windows

        B, N, m = z.shape
        hs = self._h(m)
        zc = _unwrap_channels(z, model.angle_measurements, axis=1)
        steps = np.arange(self.every - 1, N, self.every)
        est = np.full((B, steps.size, m), np.nan)
        for j in range(m):
            bounds = [self._bounds(int(k)) for k in steps]
            est[:, :, j] = somd_variance_windows(
                zc[:, :, j], bounds, float(hs[j]), paper=self.method == "somd-paper"
            )
        self._schedule_steps = steps
        self._schedule = est
        self._prepared_shape = (B, N, m)

    def start(self, filt: KalmanFilter) -> None:
        super().start(filt)
        B, m = filt.batch_size, filt.m
        self._hs = self._h(m)
        self._var = np.repeat(np.diag(filt.model.R)[None], B, axis=0)
        self._Rmat = _diag_matrix(self._var)
        self._angles = list(filt.model.angle_measurements)
        # a schedule from prepare() serves the one filter that run_filter starts next
        self._active = (
            self._schedule
            if self._schedule is not None and (self._prepared_shape[0] == B)
            else None
        )
        self._schedule = None
        self._history: list[NDArray] = []
        self._n_est = 0

    def measurement_covariance(self, filt: KalmanFilter) -> NDArray:
        k = filt.k
        if self._active is None:
            self._history.append(np.array(filt.z))
        if (k + 1) % self.every == 0:
            if self._active is not None:
                new = self._active[:, self._n_est]
            else:
                new = self._estimate_from_history(k)
            self._n_est += 1
            ok = np.isfinite(new) & (new > 0)
            if ok.any():
                self._var = np.where(ok, new, self._var)
                self._Rmat = _diag_matrix(self._var)
        return self._guard_dead(self._Rmat)

    def _estimate_from_history(self, k: int) -> NDArray:
        from noisevar import estimate

        start, stop = self._bounds(k)
        zw = np.stack(self._history[start:stop], axis=1)  # (B, L, m)
        zw = _unwrap_channels(zw, self._angles, axis=1)
        B, _, m = zw.shape
        out = np.full((B, m), np.nan)
        for b in range(B):
            for j in range(m):
                try:
                    out[b, j] = estimate(
                        zw[b, :, j], method=self.method, h_smooth=float(self._hs[j]), select=False
                    ).variance
                except NoisevarError:
                    pass  # too few samples for this channel's filter to settle yet
        return out


def _unwrap_channels(z: NDArray, channels: Any, axis: int) -> NDArray:
    channels = list(channels)
    if not channels:
        return z
    z = np.array(z)
    z[..., channels] = np.unwrap(z[..., channels], axis=axis)
    return z


# --------------------------------------------------------------------------- registry
@dataclass(frozen=True)
class StrategySpec:
    """A registered strategy: its class, its user-facing parameters and what it needs to know.

    Parameters
    ----------
    name : str
        Registry name (``"sage-husa"``).
    cls : type
        The :class:`RStrategy` subclass.
    help : str
        One line for lists, ``--help`` and the dashboard.
    params : tuple of ParamSpec
        Tunable parameters with their defaults.
    fixed : dict
        Constructor arguments that define this entry (``method="somd-paper"``).
    needs : tuple of str
        Context it must be given: ``"h_smooth"`` (SOMD) or ``"R_true"`` (oracle).
    """

    name: str
    cls: type[RStrategy]
    help: str
    params: tuple[ParamSpec, ...] = ()
    fixed: dict[str, Any] = field(default_factory=dict)
    needs: tuple[str, ...] = ()

    def defaults(self) -> dict[str, Any]:
        """Default value of every tunable parameter."""
        return {p.name: p.default for p in self.params}


_WINDOW = ParamSpec("window", "int", 50, "moving window N (steps)", lo=1, lo_closed=True)
_SOMD_EVERY = ParamSpec("every", "int", 100, "re-estimate R every N steps", lo=1, lo_closed=True)
_SOMD_WINDOW = ParamSpec(
    "window",
    "int",
    None,
    "trailing window (steps; default: all samples so far)",
    lo=1,
    lo_closed=True,
)
_FORGETTING = ParamSpec("forgetting", "float", 0.98, "Sage-Husa forgetting factor b", lo=0, hi=1)
_RHO = ParamSpec("rho", "float", 0.99, "VB forgetting factor rho", lo=0, hi=1)

STRATEGIES: dict[str, StrategySpec] = {
    s.name: s
    for s in (
        StrategySpec("fixed", FixedR, "the model's nominal R"),
        StrategySpec(
            "oracle", OracleR, "the true R (simulations only): the lower bound", needs=("R_true",)
        ),
        StrategySpec(
            "somd",
            SomdOnlineR,
            "SOMD on a trailing window per channel (bias-corrected)",
            (_SOMD_EVERY, _SOMD_WINDOW),
            needs=("h_smooth",),
        ),
        StrategySpec(
            "somd-paper",
            SomdOnlineR,
            "SOMD on a trailing window, the paper's factor 1/2",
            (_SOMD_EVERY, _SOMD_WINDOW),
            {"method": "somd-paper"},
            ("h_smooth",),
        ),
        StrategySpec("rae", ResidualR, "residual-based moving-window R", (_WINDOW,)),
        StrategySpec("iae", InnovationR, "innovation-based moving-window R", (_WINDOW,)),
        StrategySpec("rae-q", ResidualQR, "residual-based R and Q = K C_d K'", (_WINDOW,)),
        StrategySpec("sage-husa", SageHusaR, "Sage-Husa recursion with forgetting", (_FORGETTING,)),
        StrategySpec("vb", VariationalBayesR, "variational Bayes, inverse-gamma R", (_RHO,)),
    )
}

#: Former names, still accepted by :func:`make_strategy` with a DeprecationWarning.
ALIASES = {"somd-online": "somd", "somd-paper-online": "somd-paper"}


def strategy_spec(name: str) -> StrategySpec:
    """The registry entry of ``name`` (former names accepted with a DeprecationWarning)."""
    if name in ALIASES:
        warnings.warn(
            f"strategy {name!r} is now called {ALIASES[name]!r}", DeprecationWarning, stacklevel=3
        )
        name = ALIASES[name]
    if name not in STRATEGIES:
        raise NoisevarError(f"unknown strategy {name!r}; choose one of: {', '.join(STRATEGIES)}")
    return STRATEGIES[name]


def make_strategy(
    name: str,
    *,
    h_smooth: float | ArrayLike | None = None,
    R_true: ArrayLike | None = None,
    **params: Any,
) -> RStrategy:
    """Build a strategy by name with the registry's defaults.

    Parameters
    ----------
    name : str
        One of ``STRATEGIES``.
    h_smooth : float or sequence of float, optional
        Smoothing ``h`` per channel, for the SOMD strategies.
    R_true : array_like, optional
        The true ``R``, for ``oracle``.
    **params
        Tunable parameters of that strategy (see ``STRATEGIES[name].params``); ``None`` keeps
        the default.

    Returns
    -------
    RStrategy
        A fresh strategy object.
    """
    spec = strategy_spec(name)
    context = {"h_smooth": h_smooth, "R_true": R_true}
    for need in spec.needs:
        if context[need] is None:
            raise NoisevarError(f"strategy {spec.name!r} needs {need}")
    specs = {p.name: p for p in spec.params}
    given = {k: v for k, v in params.items() if v is not None}
    unknown = sorted(set(given) - set(specs))
    if unknown:
        raise NoisevarError(
            f"bad parameters for strategy {spec.name!r}: {', '.join(unknown)} "
            f"(its parameters: {', '.join(specs) or 'none'})"
        )
    kwargs = {**spec.defaults(), **{k: specs[k].validate(v) for k, v in given.items()}}
    kwargs.update(spec.fixed)
    kwargs.update({need: context[need] for need in spec.needs})
    return spec.cls(**kwargs)

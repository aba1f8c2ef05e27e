"""The strategy interface :class:`RStrategy` and helpers shared by the strategies.

Hooks, in the order the filter calls them at step ``k``:

``process_covariance(filt)``
    before the time update; ``Q_k`` or ``None`` (use ``model.Q``).
``measurement_covariance(filt)``
    once ``d_k`` (``filt.innovation``) and ``H P(k|k-1) Hᵀ`` (``filt.HPHt``) are known; ``R_k``.
``refine(filt)``
    only for ``iterations > 1``: the next ``R_k`` given ``x(k|k), P(k|k)``.
``observe(filt)``
    after the final update: residual ``r_k``, gain ``K_k``, ``P(k|k)``.

``filt`` is the :class:`~noisevar.kalman.KalmanFilter`; strategies read its
public attributes (read-only) and never its private fields.
"""

from __future__ import annotations

from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman import kernels

if TYPE_CHECKING:  # pragma: no cover
    from noisevar.kalman.filter import KalmanFilter
    from noisevar.kalman.model import StateSpaceModel


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
    #: Attributes holding per-run arrays (leading axis ``B``): what :meth:`state` saves.
    _state_fields: tuple[str, ...] = ("_dead",)

    def prepare(self, z: NDArray, model: StateSpaceModel) -> None:  # noqa: B027
        """Called by :func:`~noisevar.kalman.run_filter` with the whole record.

        Strategies independent of the filter's state (oracle, somd) may
        precompute here; step-by-step use never calls it.

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
        self._ops = kernels.backend()

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

    def state(self) -> dict[str, NDArray]:
        """Copies of the per-run arrays the strategy carries from step to step.

        Returns
        -------
        dict of str to ndarray
            Arrays with a leading batch axis ``B``; give them to :meth:`restore`.
        """
        out = {}
        for key in self._state_fields:
            value = getattr(self, key, None)
            if isinstance(value, np.ndarray):
                out[key] = np.array(value)
        return out

    def restore(self, state: dict[str, NDArray], runs: NDArray) -> None:
        """Put the runs ``runs`` back to a :meth:`state` saved earlier (others keep theirs).

        Parameters
        ----------
        state : dict of str to ndarray
            From :meth:`state`.
        runs : ndarray of bool, shape (B,)
            Runs to restore.
        """
        for key, value in state.items():
            current = getattr(self, key)
            if isinstance(current, np.ndarray) and current.shape == value.shape:
                current = np.array(current)
                current[runs] = value[runs]
                setattr(self, key, current)
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


def diag_matrix(v: NDArray) -> NDArray:
    """Batch of diagonal matrices from a batch of vectors ``(B, m) -> (B, m, m)``."""
    m = v.shape[1]
    eye = _EYES.get(m)
    if eye is None:  # cached: np.eye costs as much as the product, at every step
        eye = _EYES[m] = np.eye(m)
        eye.setflags(write=False)
    return v[:, :, None] * eye


def diag(a: NDArray) -> NDArray:
    """Diagonals of a stack of matrices (a view)."""
    return a.diagonal(0, -2, -1)


def check_window(window: Any, name: str = "window") -> int:
    """``window`` as a positive integer, or a :class:`~noisevar.errors.NoisevarError`."""
    try:
        w = int(window)
    except (TypeError, ValueError):
        raise NoisevarError(f"{name} must be an integer, got {window!r}") from None
    if w < 1 or w != window:
        raise NoisevarError(f"{name} must be a positive integer, got {window!r}")
    return w

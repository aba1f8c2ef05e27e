"""The one result type of a filter run: :class:`FilterResult`."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray


@dataclass
class FilterResult:
    """Everything a Kalman filter run records, step by step.

    Arrays have a leading Monte Carlo axis ``B`` only when the run was batched
    (``batched=True``); otherwise that axis is dropped. ``N`` is the number of
    steps, ``n`` the state dimension and ``m`` the measurement dimension.
    After a run diverged (see ``diverged``) the state-dependent arrays of that
    run hold NaN from ``divergence_step`` on, so nothing downstream silently
    uses garbage.

    Attributes
    ----------
    strategy : str
        Name of the R-adaptation strategy (plus ``"+huber"`` when the robust
        update was used).
    time : ndarray, shape (N,)
        ``k * dt``.
    x, P : ndarray, shapes ([B,] N, n) and ([B,] N, n, n)
        Updated estimates ``x̂(k|k)`` and their covariances.
    x_pred, P_pred : ndarray or None
        Predictions ``x̂(k|k-1)``, ``P(k|k-1)`` (``None`` when the run was
        made with ``store_predicted=False``).
    innovation : ndarray, shape ([B,] N, m)
        ``d_k = z_k - h(x̂(k|k-1))`` (angles wrapped to ``[-π, π)``).
    innovation_cov : ndarray, shape ([B,] N, m, m)
        ``S_k = H P(k|k-1) Hᵀ + R_k`` with the ``R_k`` of the final update
        iteration.
    residual : ndarray, shape ([B,] N, m)
        ``r_k = z_k - h(x̂(k|k))``.
    R, Q : ndarray, shape ([B,] N, m, m) and ([B,] N, n, n)
        Measurement and process covariances used at each step (a read-only
        broadcast view of the model's matrix when it was used throughout).
    nis : ndarray, shape ([B,] N)
        Normalised innovation squared ``d_kᵀ S_k⁻¹ d_k`` (chi-square with
        ``m`` degrees of freedom when the filter is consistent).
    nees : ndarray, shape ([B,] N) or None
        Normalised estimation error squared ``eᵀ P⁻¹ e``, ``e = x̂ - x_true``
        (chi-square with ``n`` degrees of freedom), when truth was given.
    truth : ndarray, shape ([B,] N, n) or None
        The true states, when given.
    diverged : bool or ndarray of bool, shape (B,)
        Whether the run diverged.
    divergence_step : int or ndarray of int, shape (B,)
        First step at which divergence was detected, ``-1`` if none.
    divergence_reason : str or list of str
        Human-readable reason (``""`` if none).
    batched : bool
        Whether the arrays carry the leading Monte Carlo axis.
    state_names, measurement_names : tuple of str
        Labels for plots and tables.
    angle_states : tuple of int
        State components that are angles (errors wrapped to ``[-π, π)``).
    """

    strategy: str
    time: NDArray
    x: NDArray
    x_pred: NDArray | None
    P: NDArray
    P_pred: NDArray | None
    innovation: NDArray
    innovation_cov: NDArray
    residual: NDArray
    R: NDArray
    Q: NDArray
    nis: NDArray
    nees: NDArray | None
    truth: NDArray | None
    diverged: bool | NDArray
    divergence_step: int | NDArray
    divergence_reason: str | list[str]
    batched: bool = False
    state_names: tuple[str, ...] = ()
    measurement_names: tuple[str, ...] = ()
    angle_states: tuple[int, ...] = field(default_factory=tuple)

    @property
    def n_steps(self) -> int:
        """Number of filter steps ``N``."""
        return int(self.time.shape[0])

    def state_error(self) -> NDArray:
        """Estimation error ``x̂(k|k) - x_true`` (angle states wrapped).

        Returns
        -------
        ndarray, shape ([B,] N, n)

        Raises
        ------
        NoisevarError
            When the run was made without truth.
        """
        from noisevar.errors import NoisevarError

        if self.truth is None:
            raise NoisevarError("this run has no truth: pass truth=... to run_filter")
        err = self.x - self.truth
        for i in self.angle_states:
            err[..., i] = wrap_angle(err[..., i])
        return err

    def rmse(self, states: int | tuple[int, ...], skip: int = 0) -> float | NDArray:
        """Root-mean-square error over steps (and over the given state components).

        ``sqrt(mean_k sum_{i in states} e_i[k]^2)``: for ``states=(0, 1)`` of a
        position ``[pE, pN]`` this is the horizontal position RMSE.

        Parameters
        ----------
        states : int or tuple of int
            State indices whose squared errors are summed.
        skip : int
            Leading steps to leave out (start-up transient).

        Returns
        -------
        float or ndarray, shape (B,)
            One RMSE per run (NaN for a run that diverged).
        """
        idx = (states,) if isinstance(states, int) else tuple(states)
        err = self.state_error()[..., skip:, :][..., list(idx)]
        out = np.sqrt(np.mean(np.sum(err**2, axis=-1), axis=-1))
        return float(out) if np.ndim(out) == 0 else out


def wrap_angle(a: NDArray) -> NDArray:
    """Wrap angles to ``[-π, π)``.

    Parameters
    ----------
    a : ndarray
        Angles in radians.

    Returns
    -------
    ndarray
        ``(a + π) mod 2π - π``.
    """
    return np.mod(a + np.pi, 2.0 * np.pi) - np.pi

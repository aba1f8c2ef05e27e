"""The :class:`Scenario` container and a constant-velocity model for recorded data."""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman import DivergenceCheck, HuberUpdate, StateSpaceModel, run_filter
from noisevar.kalman.result import FilterResult
from noisevar.kalman.strategies import RStrategy
from noisevar.systems.base import BatchResult


@dataclass
class Scenario(BatchResult):
    """Truth, measurements and model of one scenario, for ``B`` Monte Carlo runs.

    Attributes
    ----------
    name : str
        Scenario name.
    model : StateSpaceModel
        The filter model (nominal ``R`` is the filter's initial ``R``).
    time : ndarray, shape (N,)
        Sample times.
    truth : ndarray, shape (B, N, n)
        True states.
    z : ndarray, shape (B, N, m)
        Measurements.
    R_true : ndarray, shape (N, m, m)
        True measurement covariance at every step (same for every run).
    x0 : ndarray, shape (B, n)
        Initial state of each run (from its first measurement).
    first_step : int
        Index of the first sample the filter processes (the samples before
        it initialised ``x0``).
    h_smooth : tuple of float
        Smoothing ``h`` per measured channel for the SOMD estimator.
    angle_channels : tuple of int
        Measured channels that are angles (unwrap before estimating).
    change : tuple of int
        ``(start, end)`` steps of the noise change (``(-1, -1)`` if none).
    outlier_mask : ndarray of bool, shape (B, N, m), optional
        Where gross errors were added.
    description : str
        One paragraph for reports.
    state_groups : dict of str to tuple of int
        Named groups of states for summaries (an RMSE per group, ``filter_summary``); the
        first group's first two states are the horizontal position (the track).
    """

    name: str
    model: StateSpaceModel
    time: NDArray
    truth: NDArray
    z: NDArray
    R_true: NDArray
    x0: NDArray
    first_step: int
    h_smooth: tuple[float, ...]
    angle_channels: tuple[int, ...] = ()
    change: tuple[int, int] = (-1, -1)
    outlier_mask: NDArray | None = None
    description: str = ""
    extra: dict[str, Any] = field(default_factory=dict)
    state_groups: dict[str, tuple[int, ...]] = field(default_factory=dict)

    @property
    def runs(self) -> int:
        """Number of Monte Carlo runs ``B``."""
        return int(self.z.shape[0])

    @property
    def label(self) -> str:
        """The scenario's name."""
        return self.name

    def run(
        self,
        strategy: RStrategy,
        robust: HuberUpdate | None = None,
        store_predicted: bool = False,
        divergence: DivergenceCheck | None = None,
    ) -> FilterResult:
        """Filter every run (batched) from ``first_step`` on, with truth.

        Parameters
        ----------
        strategy : RStrategy
            A fresh strategy object.
        robust : HuberUpdate, optional
            Huber update.
        store_predicted : bool
            Keep ``x_pred`` and ``P_pred`` per step.
        divergence : DivergenceCheck, optional
            Divergence criteria.

        Returns
        -------
        FilterResult
            Batched result (leading axis ``B``).
        """
        s = self.first_step
        return run_filter(
            self.model,
            self.z[:, s:],
            strategy=strategy,
            robust=robust,
            truth=self.truth[:, s:],
            store_predicted=store_predicted,
            divergence=divergence,
            x0=self.x0,
        )

    def measured(self, unwrap: bool = True) -> NDArray:
        """Measurements with angle channels unwrapped (what a variance estimator sees).

        Parameters
        ----------
        unwrap : bool
            Unwrap the angle channels along time.

        Returns
        -------
        ndarray, shape (B, N, m)
        """
        z = np.array(self.z)
        if unwrap and self.angle_channels:
            ch = list(self.angle_channels)
            z[..., ch] = np.unwrap(z[..., ch], axis=1)
        return z


def _check_runs(runs: Any) -> int:
    try:
        b = int(runs)
    except (TypeError, ValueError):
        raise NoisevarError(f"runs must be a positive integer, got {runs!r}") from None
    if b < 1 or b != runs:
        raise NoisevarError(f"runs must be a positive integer, got {runs!r}")
    return b


def constant_velocity_model(
    z0: ArrayLike, sample_period: float, h: float, r0: ArrayLike, names: Sequence[str]
) -> StateSpaceModel:
    """A constant-velocity model per measured channel (for filtering recorded data).

    Channel ``j`` has states ``[p_j, v_j]`` driven by white acceleration of
    spectral density ``q_j = h · r0_j / T³`` (``h`` is the same unit-free
    ratio ``q T³ / r`` as the alpha-beta-gamma filter's), measured with
    noise ``r0_j``. The filter starts at the first sample ``z0``, velocity zero.

    Parameters
    ----------
    z0 : array_like, shape (m,)
        First sample of each channel.
    sample_period : float
        ``T`` (s).
    h : float
        Unit-free process-to-measurement noise ratio ``q T³ / r``.
    r0 : array_like, shape (m,)
        Measurement-noise variance of each channel.
    names : sequence of str
        Channel names.

    Returns
    -------
    StateSpaceModel
    """
    z0 = np.asarray(z0, dtype=float).ravel()
    r0 = np.asarray(r0, dtype=float).ravel()

    T = float(sample_period)
    m = z0.size
    F1 = np.array([[1.0, T], [0.0, 1.0]])
    Qs = np.array([[T**3 / 3.0, T**2 / 2.0], [T**2 / 2.0, T]])
    F = np.kron(np.eye(m), F1)
    Q = np.zeros((2 * m, 2 * m))
    P0 = np.zeros((2 * m, 2 * m))
    H = np.zeros((m, 2 * m))
    x0 = np.zeros(2 * m)
    for j in range(m):
        q = h * r0[j] / T**3
        Q[2 * j : 2 * j + 2, 2 * j : 2 * j + 2] = q * Qs
        P0[2 * j, 2 * j] = r0[j]
        P0[2 * j + 1, 2 * j + 1] = 4.0 * r0[j] / T**2
        H[j, 2 * j] = 1.0
        x0[2 * j] = z0[j]
    state_names = tuple(s for n in names for s in (n, f"d{n}/dt"))
    return StateSpaceModel(
        Q=Q,
        R=np.diag(r0),
        x0=x0,
        P0=P0,
        F=F,
        H=H,
        dt=T,
        state_names=state_names,
        measurement_names=tuple(names),
        name="constant velocity per channel",
    )

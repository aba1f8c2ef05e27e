"""Distributed VB-adaptive fusion with chi-square fault isolation (docs/algorithms.md §B2).

Each sensor has a local Kalman filter (variational-Bayes ``R``, eqs. (29)-(30),
or a fixed / oracle ``R``); the fusion centre adds their information gains,
eq. (24) with eq. (8) (docs/algorithms.md §G6), which equals the centralised
filter on the stacked measurements. A sensor whose NIS exceeds
``χ²_m(1 - false_alarm)`` is isolated for that step (time update only).

Notes
-----
By default every local filter is reset to the fused estimate after each step
(``feedback=True``); a per-run isolation inside a batch updates all runs and
puts the flagged ones back. The scenario lives in
:mod:`noisevar.systems.fusion_scenario` and is re-exported here.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray
from scipy import linalg, stats

from noisevar.errors import NoisevarError
from noisevar.kalman import (
    FilterResult,
    FixedR,
    KalmanFilter,
    OracleR,
    RStrategy,
    StateSpaceModel,
    VariationalBayesR,
    make_strategy,
    quadratic_form_inverse,
    run_filter,
    steps,
    strategy_spec,
)
from noisevar.systems.base import BatchResult
from noisevar.systems.fusion_scenario import (
    FAULTS,
    NOISE_FAULTS,
    FusionData,
    FusionScenario,
    Sensor,
    default_sensors,
    simulate_fusion,
)

__all__ = [
    "ADAPTIVE_LOCAL",
    "FAULTS",
    "LOCAL_STRATEGIES",
    "NOISE_FAULTS",
    "STATE_NAMES",
    "FusionData",
    "FusionResult",
    "FusionScenario",
    "Sensor",
    "default_sensors",
    "max_abs_diff_vs_centralized",
    "position_rmse",
    "run_centralized",
    "run_fusion",
    "simulate_fusion",
]

#: The local filters' ``R`` (names of the strategy registry): the adaptive one of the
#: paper (variational Bayes, §B2), then the references, the nominal and the true ``R``.
ADAPTIVE_LOCAL = VariationalBayesR.name
LOCAL_STRATEGIES = (ADAPTIVE_LOCAL, FixedR.name, OracleR.name)
STATE_NAMES = ("east", "north", "v_east", "v_north")


# ---------------------------------------------------------------------------
# Filters
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class FusionResult(BatchResult):
    """A fused run: estimates, per-sensor ``R`` tracks and isolation flags.

    Attributes
    ----------
    label : str
        ``"<local strategy>[+isolation]"``.
    time : ndarray, shape (N,)
    x : ndarray, shape (B, N, 4)
        Fused estimate ``x̂(k|k)``, eq. (24).
    P : ndarray, shape (B, N, 4, 4)
        Its covariance, eq. (8).
    truth : ndarray, shape (B, N, 4)
    R_track : tuple of ndarray, shapes (B, N, m_i)
        Variances each local filter used (the VB estimate for ``"vb"``); NaN
        where the sensor was isolated.
    true_R : tuple of ndarray, shapes (N, m_i)
        True variances, for comparison.
    isolated : ndarray of bool, shape (B, N, s)
        Whether each sensor was isolated at each step.
    nis : ndarray, shape (B, N, s)
        The isolation test statistic of each sensor.
    threshold : ndarray, shape (s,)
        Chi-square threshold of each sensor (``inf`` without isolation).
    sensor_names : tuple of str
    fault_mask : ndarray of bool, shape (N,)
    """

    label: str
    time: NDArray[np.float64]
    x: NDArray[np.float64]
    P: NDArray[np.float64]
    truth: NDArray[np.float64]
    R_track: tuple[NDArray[np.float64], ...]
    true_R: tuple[NDArray[np.float64], ...]
    isolated: NDArray[np.bool_]
    nis: NDArray[np.float64]
    threshold: NDArray[np.float64]
    sensor_names: tuple[str, ...]
    fault_mask: NDArray[np.bool_]

    @property
    def runs(self) -> int:
        """Number of Monte Carlo runs ``B``."""
        return int(self.x.shape[0])

    def position_error(self) -> NDArray[np.float64]:
        """Horizontal position error ``|p̂ - p|`` (m), shape (B, N)."""
        return np.hypot(*np.moveaxis(self.x[..., :2] - self.truth[..., :2], -1, 0))

    def rmse(self, skip: int = 20) -> float:
        """Position RMSE over runs and steps ``skip..N`` (m)."""
        return position_rmse(self.x, self.truth, skip)

    def isolated_fraction(self, sensor: int = 0) -> tuple[float | None, float | None]:
        """How often ``sensor`` was isolated during the fault and while healthy.

        Returns
        -------
        (in_fault, healthy) : tuple of float or None
            Fractions of (run, step) pairs; None where there is no such step.
        """
        iso = self.isolated[..., sensor]
        fault = self.fault_mask
        in_fault = float(iso[:, fault].mean()) if fault.any() else None
        healthy = float(iso[:, ~fault].mean()) if (~fault).any() else None
        return in_fault, healthy


def max_abs_diff_vs_centralized(
    data: FusionData, feedback: bool = True, central: FilterResult | None = None
) -> float:
    """Largest ``|x̂_fused - x̂_centralised|`` with fixed ``R`` and no isolation.

    The information-form fusion of eq. (24) equals the centralised filter
    exactly in that case; this is the check (rounding: about 1e-11).

    Parameters
    ----------
    data : FusionData
    feedback : bool
        Reset the local filters to the fused estimate after each step.
    central : FilterResult, optional
        :func:`run_centralized` of ``data``, if already computed.

    Returns
    -------
    float
    """
    fused = run_fusion(data, local=FixedR.name, feedback=feedback)
    central = central if central is not None else run_centralized(data)
    return float(np.max(np.abs(fused.x - central.x)))


def position_rmse(x: ArrayLike, truth: ArrayLike, skip: int = 20) -> float:
    """Horizontal position RMSE over runs and steps after ``skip`` (m).

    Parameters
    ----------
    x, truth : array_like, shape (B, N, n) or (N, n)
        Estimates and truth; the first two state components are the position.
    skip : int
        Leading steps (start-up transient) left out.

    Returns
    -------
    float
    """
    e = np.asarray(x)[..., skip:, :2] - np.asarray(truth)[..., skip:, :2]
    return float(np.sqrt(np.mean(np.sum(e**2, axis=-1))))


def _local_model(data: FusionData, sensor: Sensor) -> StateSpaceModel:
    F, Q = data.scenario.model_matrices()
    return StateSpaceModel(
        Q=Q,
        R=np.diag(sensor.noise_std**2),
        x0=data.x0,
        P0=data.P0,
        F=F,
        H=sensor.H,
        dt=data.scenario.dt,
        state_names=STATE_NAMES,
        name=sensor.name,
    )


def _make_strategy(local: str, data: FusionData, i: int, vb_rho: float) -> RStrategy:
    """The local filter's strategy from the registry (``vb_rho`` for the one that takes ρ)."""
    rho = {"rho": vb_rho} if "rho" in strategy_spec(local).defaults() else {}
    return make_strategy(local, R_true=data.true_R(i), **rho)


def run_fusion(
    data: FusionData,
    local: str = ADAPTIVE_LOCAL,
    isolation: bool = False,
    false_alarm: float = 1e-3,
    feedback: bool = True,
    vb_rho: float = 0.99,
) -> FusionResult:
    """Distributed fusion of local filters in information form (eq. (24)).

    Parameters
    ----------
    data : FusionData
        From :func:`simulate_fusion`.
    local : {"vb", "fixed", "oracle"}
        ``R`` of the local filters: variational Bayes (eqs. (29)-(30)), the
        sensors' nominal ``R``, or the true ``R``.
    isolation : bool
        Chi-square fault isolation of the local filters.
    false_alarm : float
        Probability that a healthy sample is rejected; the threshold is
        ``χ²_{m_i}(1 - false_alarm)``.
    feedback : bool
        Reset the local filters to the fused estimate after each step.
    vb_rho : float
        VB forgetting factor ``ρ`` (paper: 0.99).

    Returns
    -------
    FusionResult

    Raises
    ------
    NoisevarError
        For an unknown ``local`` or a ``false_alarm`` outside ``(0, 1)``.
    """
    _check_settings(local, false_alarm)
    scenario = data.scenario
    sensors = scenario.sensors
    B, N = data.runs, int(scenario.n_steps)
    F, Q = scenario.model_matrices()
    filters = [
        KalmanFilter(
            _local_model(data, s), strategy=_make_strategy(local, data, i, vb_rho), batch_size=B
        )
        for i, s in enumerate(sensors)
    ]
    thresholds = np.array(
        [
            stats.chi2.ppf(1.0 - false_alarm, s.n_measurements) if isolation else np.inf
            for s in sensors
        ]
    )
    x = np.repeat(data.x0[None], B, axis=0)
    P = np.repeat(data.P0[None], B, axis=0)
    x_out = np.empty((B, N, 4))
    P_out = np.empty((B, N, 4, 4))
    R_out = [np.empty((B, N, s.n_measurements)) for s in sensors]
    isolated = np.zeros((B, N, len(sensors)), dtype=bool)
    nis = np.zeros((B, N, len(sensors)))
    z_steps = [np.ascontiguousarray(np.moveaxis(z, 1, 0)) for z in data.measurements]
    for k in range(N):  # the filter's time loop is inherent; runs are vectorised
        x_pred, P_pred = steps.predict(x, P, F, Q)
        info = np.linalg.inv(P_pred)
        info_vec = (info @ x_pred[:, :, None])[:, :, 0]
        flags = np.zeros((len(filters), B), dtype=bool)
        for i, filt in enumerate(filters):
            if feedback:
                filt.x, filt.P = x, P
            nis_k = _local_step(filt, z_steps[i][k], thresholds[i], isolation)
            flagged = nis_k > thresholds[i] if isolation else flags[i]
            if isolation:
                nis[:, k, i] = nis_k
            flags[i] = isolated[:, k, i] = flagged
            R_diag = np.diagonal(np.broadcast_to(filt.R, (B, *filt.R.shape[-2:])), 0, -2, -1)
            R_out[i][:, k] = np.where(flagged[:, None], np.nan, R_diag)
        x, P = _fuse(filters, info, info_vec, flags, feedback)
        x_out[:, k] = x
        P_out[:, k] = P
    label = local + ("+isolation" if isolation else "")
    return FusionResult(
        label=label,
        time=data.time,
        x=x_out,
        P=P_out,
        truth=data.truth,
        R_track=tuple(R_out),
        true_R=tuple(data.true_R(i) for i in range(len(sensors))),
        isolated=isolated,
        nis=nis,
        threshold=thresholds,
        sensor_names=tuple(s.name for s in sensors),
        fault_mask=data.fault_mask,
    )


def _check_settings(local: str, false_alarm: float) -> None:
    if local not in LOCAL_STRATEGIES:
        raise NoisevarError(f"local={local!r}; choose one of {', '.join(LOCAL_STRATEGIES)}.")
    if not 0 < false_alarm < 1:
        raise NoisevarError(f"false_alarm={false_alarm} must be in (0, 1), e.g. 1e-3.")


def _local_step(
    filt: KalmanFilter, z: NDArray[np.float64], threshold: float, isolation: bool
) -> NDArray[np.float64]:
    """Predict and update one local filter, skipping the runs whose NIS exceeds ``threshold``.

    Returns the NIS of every run (zeros without isolation); a flagged run keeps its
    prediction and its strategy's state (docs/algorithms.md §B2).
    """
    filt.predict()
    B = filt.x_pred.shape[0]
    nis = np.zeros(B)
    if isolation:
        H = filt.model.H
        # S = HPH' + R,  d = z - Hx,  NIS = d' S⁻¹ d
        _, S, _, _ = steps.gain(filt.P_pred, H, filt.R)
        d = steps.innovation(z, steps.matvec(H, filt.x_pred))
        nis = quadratic_form_inverse(S, d)
    flagged = nis > threshold if isolation else np.zeros(B, dtype=bool)
    if flagged.all():
        filt.skip_update()
        return nis
    saved = filt.strategy.state() if flagged.any() else {}
    filt.update(z)
    if flagged.any():
        filt.x = np.where(flagged[:, None], filt.x_pred, filt.x)
        filt.P = np.where(flagged[:, None, None], filt.P_pred, filt.P)
        filt.strategy.restore(saved, flagged)
    return nis


def _fuse(
    filters: list[KalmanFilter],
    info: NDArray[np.float64],
    info_vec: NDArray[np.float64],
    flags: NDArray[np.bool_],
    feedback: bool,
) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """The fused ``x̂`` and ``P`` of one step from the local filters (eqs. (8), (24))."""
    # every local filter's information gain, all sensors in one inversion
    P_inv = np.linalg.inv(np.stack([f.P for f in filters]))
    x_loc = np.stack([f.x for f in filters])[..., None]
    xp_loc = np.stack([f.x_pred for f in filters])[..., None]
    if feedback:  # the local predictions are the fused one: P_i,pred = P_pred
        Pp_inv = np.broadcast_to(info, P_inv.shape)
    else:
        Pp_inv = np.linalg.inv(np.stack([f.P_pred for f in filters]))
    # P_i⁻¹ - P_i,pred⁻¹ and P_i⁻¹ x̂_i - P_i,pred⁻¹ x̂_i,pred
    info_i = P_inv - Pp_inv
    vec_i = (P_inv @ x_loc - Pp_inv @ xp_loc)[..., 0]
    info_i[flags] = 0.0  # an isolated sensor adds nothing
    vec_i[flags] = 0.0
    # P⁻¹ = P_pred⁻¹ + Σ_i (P_i⁻¹ - P_i,pred⁻¹)   (8)
    info = info + info_i.sum(axis=0)
    info_vec = info_vec + vec_i.sum(axis=0)
    P = np.linalg.inv(info)
    P = 0.5 * (P + P.mT)
    # x̂ = P (P_pred⁻¹ x̂_pred + Σ_i (P_i⁻¹ x̂_i - P_i,pred⁻¹ x̂_i,pred))   (24)
    x = (P @ info_vec[:, :, None])[:, :, 0]
    return x, P


def run_centralized(data: FusionData) -> FilterResult:
    """The centralised Kalman filter on the stacked measurements (eqs. (3)-(10)).

    Built with :func:`noisevar.kalman.run_filter` and the sensors' nominal
    ``R`` (block diagonal, eq. (4)). With no fault and no adaptation the
    distributed filter of :func:`run_fusion` (``local="fixed"``, no
    isolation) must equal it.

    Parameters
    ----------
    data : FusionData

    Returns
    -------
    FilterResult
        Batched over the runs of ``data``.
    """
    sensors = data.scenario.sensors
    F, Q = data.scenario.model_matrices()
    model = StateSpaceModel(
        Q=Q,
        R=linalg.block_diag(*[np.diag(s.noise_std**2) for s in sensors]),
        x0=data.x0,
        P0=data.P0,
        F=F,
        H=np.vstack([s.H for s in sensors]),
        dt=data.scenario.dt,
        state_names=STATE_NAMES,
        name="centralised",
    )
    z = np.concatenate(data.measurements, axis=-1)
    return run_filter(model, z, truth=data.truth)

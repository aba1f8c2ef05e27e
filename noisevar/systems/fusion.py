"""Distributed VB-adaptive fusion with chi-square fault isolation (spec B2).

Seed ``vb-distributed-fusion.txt``. Several sensors observe one target; each
sensor ``i`` has its own local Kalman filter (built on
:class:`noisevar.kalman.KalmanFilter`, with the variational-Bayes
``R``-adaptation strategy :class:`noisevar.kalman.VariationalBayesR`, paper
eqs. (29)-(30), or a fixed / oracle ``R``). The fusion centre combines the
local filters in information form, paper eq. (24) (with eq. (8) for the
covariance)::

    P⁻¹ = P_pred⁻¹ + Σ_i (P_i⁻¹ - P_i,pred⁻¹)                                (8)
    x̂  = P · (P_pred⁻¹ x̂_pred + Σ_i (P_i⁻¹ x̂_i - P_i,pred⁻¹ x̂_i,pred))     (24)

Because ``P_i⁻¹ - P_i,pred⁻¹ = H_iᵀ R_i⁻¹ H_i`` and
``P_i⁻¹ x̂_i - P_i,pred⁻¹ x̂_i,pred = H_iᵀ R_i⁻¹ z_i`` for any Kalman update
(eqs. (21)-(23)), this equals the centralised Kalman filter on the stacked
measurements, whatever the local filters' own priors: we test it to 1e-8.

Fault isolation: before a local update, the sensor's normalised innovation
squared ``NIS = dᵀ (H P_i,pred Hᵀ + R_i)⁻¹ d`` (with the ``R_i`` the local
filter used at its previous update) is compared with the chi-square quantile
``χ²_{m_i}(1 - false_alarm)``. A flagged local filter does only its time
update for that step (``x̂_i = x̂_i,pred``, ``P_i = P_i,pred``), so it adds
nothing to the sums above, and its ``R`` strategy does not learn from the
rejected sample; it contributes again as soon as a sample passes the test
("until it recovers").

Choices stated here (the paper leaves them open):

* **Feedback** (default on): after each fusion, every local filter is reset to
  the fused estimate (the "reset" mode of federated filters). The local
  filters then share the fused prediction; the equivalence above holds either
  way, but without feedback a sensor that sees only velocity has a local
  position covariance that grows without bound. ``feedback=False`` gives the
  paper's independent local filters.
* A per-run isolation inside a batch of Monte Carlo runs is done by updating
  all runs and putting the flagged runs back (state, covariance and the
  strategy's per-run arrays), so the batch stays vectorised.
* Scenario: a 2-D target with a nearly-constant-velocity model (white
  acceleration), two position sensors and one velocity sensor, 1 s steps.
  Faults on one sensor: its noise standard deviation steps up or ramps up
  (``noise_factor`` times), a large bias (``bias_sigmas`` standard
  deviations), or a frozen output (the last good sample repeated).

Entry points: :func:`simulate_fusion` (seeded scenario, batched over runs),
:func:`run_fusion` (distributed filter, isolation optional),
:func:`run_centralized` (the stacked Kalman filter of the core, for the
equivalence), :func:`position_rmse`.
"""

from __future__ import annotations

from dataclasses import dataclass, field

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
    run_filter,
)

FAULTS = ("none", "noise-step", "noise-ramp", "bias", "frozen")
LOCAL_STRATEGIES = ("vb", "fixed", "oracle")
STATE_NAMES = ("east", "north", "v_east", "v_north")


# ---------------------------------------------------------------------------
# Scenario
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class Sensor:
    """One sensor of the fusion scenario: ``z = H x + v``, ``v ~ N(0, diag(std²))``.

    Parameters
    ----------
    name : str
        Label.
    H : array_like, shape (m, 4)
        Measurement matrix on the state ``[east, north, v_east, v_north]``.
    noise_std : array_like, shape (m,)
        Nominal (pre-fault) noise standard deviation of each component.
    """

    name: str
    H: NDArray[np.float64]
    noise_std: NDArray[np.float64]

    def __post_init__(self) -> None:
        H = np.atleast_2d(np.asarray(self.H, dtype=float))
        std = np.atleast_1d(np.asarray(self.noise_std, dtype=float))
        if H.ndim != 2 or H.shape[1] != 4 or std.shape != (H.shape[0],):
            raise NoisevarError(
                f"sensor {self.name!r}: H must be (m, 4) and noise_std (m,); got "
                f"{H.shape} and {std.shape}."
            )
        if not np.all(std > 0):
            raise NoisevarError(f"sensor {self.name!r}: noise_std must be positive.")
        object.__setattr__(self, "H", H)
        object.__setattr__(self, "noise_std", std)

    @property
    def n_measurements(self) -> int:
        """Number of measured components ``m``."""
        return int(self.H.shape[0])


def default_sensors() -> tuple[Sensor, ...]:
    """Two position sensors (10 m and 15 m) and one velocity sensor (0.5 m/s)."""
    pos = np.array([[1.0, 0, 0, 0], [0, 1.0, 0, 0]])
    vel = np.array([[0, 0, 1.0, 0], [0, 0, 0, 1.0]])
    return (
        Sensor("position A", pos, np.array([10.0, 10.0])),
        Sensor("position B", pos, np.array([15.0, 15.0])),
        Sensor("velocity", vel, np.array([0.5, 0.5])),
    )


@dataclass(frozen=True)
class FusionScenario:
    """Parameters of the multi-sensor scenario.

    Parameters
    ----------
    n_steps : int
        Number of fusion steps.
    dt : float
        Step (s).
    accel_psd : float
        Spectral density of the white acceleration (m²/s³) of the
        nearly-constant-velocity model (truth and filters).
    speed : float
        Initial speed (m/s); the heading is drawn at random.
    sensors : tuple of Sensor
        The sensors (default :func:`default_sensors`).
    fault : {"none", "noise-step", "noise-ramp", "bias", "frozen"}
        What happens to sensor ``faulty_sensor``.
    faulty_sensor : int
        Index of the sensor that misbehaves.
    fault_start, fault_end : float
        Fault interval as fractions of the record (the ramp rises over it;
        the step, bias and freeze last over it).
    noise_factor : float
        Noise standard deviation multiplier at the end of the step / ramp.
    bias_sigmas : float
        Bias as a multiple of the sensor's noise standard deviation.
    """

    n_steps: int = 600
    dt: float = 1.0
    accel_psd: float = 0.05
    speed: float = 20.0
    sensors: tuple[Sensor, ...] = field(default_factory=default_sensors)
    fault: str = "none"
    faulty_sensor: int = 0
    fault_start: float = 0.4
    fault_end: float = 1.0
    noise_factor: float = 4.0
    bias_sigmas: float = 20.0

    def validate(self) -> None:
        """Raise :class:`NoisevarError` when a parameter is out of range."""
        if len(self.sensors) == 0:
            raise NoisevarError(
                "the fusion scenario has zero sensors; give at least one Sensor (two or more "
                "to fuse)."
            )
        if int(self.n_steps) != self.n_steps or self.n_steps < 2:
            raise NoisevarError(f"n_steps={self.n_steps} must be an integer >= 2.")
        if not (self.dt > 0 and self.accel_psd >= 0):
            raise NoisevarError("dt must be positive and accel_psd >= 0.")
        if self.fault not in FAULTS:
            raise NoisevarError(f"fault={self.fault!r}; choose one of {', '.join(FAULTS)}.")
        if not 0 <= self.faulty_sensor < len(self.sensors):
            raise NoisevarError(
                f"faulty_sensor={self.faulty_sensor} but there are {len(self.sensors)} sensors."
            )
        if not 0 <= self.fault_start < self.fault_end <= 1:
            raise NoisevarError(
                f"fault interval ({self.fault_start}, {self.fault_end}) must satisfy "
                "0 <= start < end <= 1 (fractions of the record)."
            )
        if not self.noise_factor > 0:
            raise NoisevarError(f"noise_factor={self.noise_factor} must be positive.")

    def model_matrices(self) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
        """``F`` and ``Q`` of the nearly-constant-velocity model."""
        dt, q = self.dt, self.accel_psd
        F = np.eye(4)
        F[0, 2] = F[1, 3] = dt
        block = q * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
        Q = np.zeros((4, 4))
        Q[np.ix_([0, 2], [0, 2])] = block
        Q[np.ix_([1, 3], [1, 3])] = block
        return F, Q


@dataclass(frozen=True)
class FusionData:
    """Simulated truth and measurements of every sensor (batched over runs).

    Attributes
    ----------
    time : ndarray, shape (N,)
        Step times (s).
    truth : ndarray, shape (B, N, 4)
        True states.
    measurements : tuple of ndarray, shapes (B, N, m_i)
        Each sensor's measurements.
    noise_std : tuple of ndarray, shapes (N, m_i)
        Each sensor's true noise standard deviation at each step.
    fault_mask : ndarray of bool, shape (N,)
        Steps inside the fault interval.
    scenario : FusionScenario
        The parameters.
    x0, P0 : ndarray
        Filter prior one step before the first measurement.
    """

    time: NDArray[np.float64]
    truth: NDArray[np.float64]
    measurements: tuple[NDArray[np.float64], ...]
    noise_std: tuple[NDArray[np.float64], ...]
    fault_mask: NDArray[np.bool_]
    scenario: FusionScenario
    x0: NDArray[np.float64]
    P0: NDArray[np.float64]

    @property
    def runs(self) -> int:
        """Number of Monte Carlo runs ``B``."""
        return int(self.truth.shape[0])

    def true_R(self, sensor: int) -> NDArray[np.float64]:
        """True measurement variances of ``sensor`` at each step, shape (N, m)."""
        return self.noise_std[sensor] ** 2


def simulate_fusion(
    scenario: FusionScenario | None = None, seed: int = 0, runs: int = 1
) -> FusionData:
    """Simulate the target and all sensors for ``runs`` Monte Carlo runs.

    Parameters
    ----------
    scenario : FusionScenario, optional
        Parameters (default: no fault).
    seed : int
        Seed of the random generator.
    runs : int
        Number of independent runs ``B`` (one array operation for all).

    Returns
    -------
    FusionData

    Raises
    ------
    NoisevarError
        For bad parameters (zero sensors, a bad fault interval, ...).
    """
    scenario = scenario or FusionScenario()
    scenario.validate()
    if int(runs) != runs or runs < 1:
        raise NoisevarError(f"runs={runs} must be a positive integer.")
    rng = np.random.default_rng(seed)
    n, dt = int(scenario.n_steps), scenario.dt
    F, Q = scenario.model_matrices()
    heading = rng.uniform(0, 2 * np.pi, runs)
    x_init = np.zeros((runs, 4))
    x_init[:, 2] = scenario.speed * np.cos(heading)
    x_init[:, 3] = scenario.speed * np.sin(heading)
    # truth: x[k] = F x[k-1] + w; the filters' prior is one step before k = 0
    L = np.linalg.cholesky(Q + 1e-15 * np.eye(4))
    w = rng.standard_normal((runs, n, 4)) @ L.T
    truth = np.empty((runs, n, 4))
    x = x_init
    for k in range(n):  # a 4-state recursion; n steps of tiny (B, 4) products
        x = x @ F.T + w[:, k]
        truth[:, k] = x

    time = np.arange(n) * dt
    frac = np.arange(n) / max(n - 1, 1)
    fault_mask = (frac >= scenario.fault_start) & (frac <= scenario.fault_end)
    k_start = int(np.argmax(fault_mask))
    measurements, stds = [], []
    for i, sensor in enumerate(scenario.sensors):
        std = np.repeat(sensor.noise_std[None, :], n, axis=0)
        faulty = scenario.fault != "none" and i == scenario.faulty_sensor
        if faulty and scenario.fault == "noise-step":
            std[fault_mask] *= scenario.noise_factor
        elif faulty and scenario.fault == "noise-ramp":
            span = max(scenario.fault_end - scenario.fault_start, 1e-12)
            ramp = np.clip((frac - scenario.fault_start) / span, 0.0, 1.0)
            std *= (1.0 + (scenario.noise_factor - 1.0) * ramp)[:, None]
        z = truth @ sensor.H.T + rng.standard_normal((runs, n, sensor.n_measurements)) * std
        if faulty and scenario.fault == "bias":
            z[:, fault_mask] += scenario.bias_sigmas * sensor.noise_std
        elif faulty and scenario.fault == "frozen":
            hold = z[:, max(k_start - 1, 0)]
            z[:, fault_mask] = hold[:, None, :]
        measurements.append(z)
        stds.append(std)
    P0 = np.diag([100.0**2, 100.0**2, 10.0**2, 10.0**2])
    x0 = np.zeros(4)
    return FusionData(
        time=time,
        truth=truth,
        measurements=tuple(measurements),
        noise_std=tuple(stds),
        fault_mask=fault_mask,
        scenario=scenario,
        x0=x0,
        P0=P0,
    )


# ---------------------------------------------------------------------------
# Filters
# ---------------------------------------------------------------------------
@dataclass(frozen=True)
class FusionResult:
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
    fused = run_fusion(data, local="fixed", feedback=feedback)
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
    if local == "vb":
        return VariationalBayesR(rho=vb_rho)
    if local == "fixed":
        return FixedR()
    return OracleR(data.true_R(i))


def run_fusion(
    data: FusionData,
    local: str = "vb",
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
    if local not in LOCAL_STRATEGIES:
        raise NoisevarError(f"local={local!r}; choose one of {', '.join(LOCAL_STRATEGIES)}.")
    if not 0 < false_alarm < 1:
        raise NoisevarError(f"false_alarm={false_alarm} must be in (0, 1), e.g. 1e-3.")
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
        x_pred = x @ F.T
        P_pred = F @ P @ F.T + Q
        info = np.linalg.inv(P_pred)
        info_vec = (info @ x_pred[:, :, None])[:, :, 0]
        flags = np.zeros((len(filters), B), dtype=bool)
        for i, filt in enumerate(filters):
            if feedback:
                filt.x, filt.P = x, P
            filt.predict()
            z = z_steps[i][k]
            H = filt.model.H
            if isolation:
                S = H @ filt.P_pred @ H.T + filt.R
                d = z - filt.x_pred @ H.T
                nis[:, k, i] = np.einsum("bi,bi->b", d, np.linalg.solve(S, d[:, :, None])[..., 0])
                flagged = nis[:, k, i] > thresholds[i]
            else:
                flagged = flags[i]
            if flagged.all():
                filt.skip_update()
            else:
                saved = filt.strategy.state() if flagged.any() else {}
                filt.update(z)
                if flagged.any():
                    filt.x = np.where(flagged[:, None], filt.x_pred, filt.x)
                    filt.P = np.where(flagged[:, None, None], filt.P_pred, filt.P)
                    filt.strategy.restore(saved, flagged)
            flags[i] = flagged
            isolated[:, k, i] = flagged
            R_diag = np.diagonal(np.broadcast_to(filt.R, (B, *filt.R.shape[-2:])), 0, -2, -1)
            R_out[i][:, k] = np.where(flagged[:, None], np.nan, R_diag)
        # eq. (24): every local filter's information gain, all sensors in one inversion
        P_inv = np.linalg.inv(np.stack([f.P for f in filters]))
        x_loc = np.stack([f.x for f in filters])[..., None]
        xp_loc = np.stack([f.x_pred for f in filters])[..., None]
        if feedback:  # the local predictions are the fused one: P_i,pred = P_pred
            Pp_inv = np.broadcast_to(info, P_inv.shape)
        else:
            Pp_inv = np.linalg.inv(np.stack([f.P_pred for f in filters]))
        info_i = P_inv - Pp_inv
        vec_i = (P_inv @ x_loc - Pp_inv @ xp_loc)[..., 0]
        info_i[flags] = 0.0  # an isolated sensor adds nothing
        vec_i[flags] = 0.0
        info = info + info_i.sum(axis=0)
        info_vec = info_vec + vec_i.sum(axis=0)
        P = np.linalg.inv(info)
        P = 0.5 * (P + P.mT)
        x = (P @ info_vec[:, :, None])[:, :, 0]
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

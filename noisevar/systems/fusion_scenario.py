"""The multi-sensor fusion scenario: sensors, faults and simulated data (docs/algorithms.md §B2)."""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.systems.base import BatchResult

FAULTS = ("none", "noise-step", "noise-ramp", "bias", "frozen")
#: The faults that scale sensor noise by ``noise_factor`` (``"bias"`` is sized by
#: ``bias_sigmas``).
NOISE_FAULTS = ("noise-step", "noise-ramp")


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
class FusionData(BatchResult):
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

    @property
    def label(self) -> str:
        """``"fusion/<fault>"``."""
        return f"fusion/{self.scenario.fault}"

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

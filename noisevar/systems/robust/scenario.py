"""The DME/VOR fly-over: scenario, trajectory and measurements (docs/algorithms.md §B3)."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import cumulative_trapezoid

from noisevar.errors import NoisevarError
from noisevar.kalman import wrap_angle
from noisevar.systems.base import BatchResult

STATE_NAMES = ("east", "north", "v_east", "v_north", "magvar")
MEASUREMENT_NAMES = ("slant range", "magnetic bearing", "v_east", "v_north")


@dataclass(frozen=True)
class RobustScenario:
    """Parameters of the station fly-over.

    The aircraft flies east at ``speed`` on a line passing
    ``overflight_offset_m`` south of the station (nearly overhead), turns
    left at ``turn_rate_deg_s`` and flies north, past the station.

    Parameters
    ----------
    duration_s : float
        Length of the record (s).
    dt : float
        Sample period (s).
    speed : float
        Ground speed (m/s).
    start_east_m : float
        East coordinate of the start (the station is at the origin).
    overflight_offset_m : float
        Distance of the first leg from the station (m); small: it flies over.
    turn_time_s : float
        When the turn starts (s).
    turn_rate_deg_s : float
        Turn rate (deg/s, positive: to the left).
    turn_angle_deg : float
        Total heading change of the turn (deg).
    height_m : float
        Height of the aircraft above the station (known; enters the slant
        range).
    magvar_deg : float
        The station's magnetic variation ``α`` (paper: -5°).
    range_std_m : float
        DME noise (m).
    bearing_std_deg : float
        VOR noise (deg).
    velocity_std : float
        Inertial velocity noise (m/s).
    outliers : bool
        Whether bursts of bearing outliers occur near the station.
    outlier_radius_m : float
        Horizontal distance from the station inside which bursts occur.
    burst_rate : float
        Probability per sample (inside the radius) that a burst starts.
    burst_length : tuple of int
        Range of burst lengths (samples).
    outlier_deg : tuple of float
        Range of the size of a burst's bearing jump (deg, either sign).
    """

    duration_s: float = 600.0
    dt: float = 1.0
    speed: float = 120.0
    start_east_m: float = -40_000.0
    overflight_offset_m: float = 300.0
    turn_time_s: float = 420.0
    turn_rate_deg_s: float = 3.0
    turn_angle_deg: float = 90.0
    height_m: float = 3000.0
    magvar_deg: float = -5.0
    range_std_m: float = 50.0
    bearing_std_deg: float = 1.0
    velocity_std: float = 0.3
    outliers: bool = True
    outlier_radius_m: float = 8000.0
    burst_rate: float = 0.08
    burst_length: tuple[int, int] = (3, 12)
    outlier_deg: tuple[float, float] = (10.0, 40.0)

    def validate(self) -> None:
        """Raise :class:`NoisevarError` when a parameter is out of range."""
        if not (self.duration_s > 0 and self.dt > 0 and self.duration_s >= 10 * self.dt):
            raise NoisevarError(
                f"duration_s={self.duration_s} and dt={self.dt}: both must be positive, with "
                "at least 10 samples."
            )
        for name in ("range_std_m", "bearing_std_deg", "velocity_std"):
            if not getattr(self, name) > 0:
                raise NoisevarError(f"{name}={getattr(self, name)} must be positive.")
        if not (self.speed > 0 and self.height_m >= 0 and self.outlier_radius_m >= 0):
            raise NoisevarError("speed must be positive, height_m and outlier_radius_m >= 0.")
        if not 0 <= self.burst_rate <= 1:
            raise NoisevarError(f"burst_rate={self.burst_rate} is a probability: give 0..1.")
        lo, hi = self.burst_length
        if not 1 <= lo <= hi:
            raise NoisevarError(f"burst_length={self.burst_length} must satisfy 1 <= lo <= hi.")
        if not 0 <= self.outlier_deg[0] <= self.outlier_deg[1]:
            raise NoisevarError(f"outlier_deg={self.outlier_deg} must satisfy 0 <= lo <= hi.")
        if abs(self.magvar_deg) >= 90:
            raise NoisevarError(f"magvar_deg={self.magvar_deg}: a magnetic variation is < 90°.")

    @property
    def R(self) -> NDArray[np.float64]:
        """Nominal measurement covariance (range, bearing, two velocities)."""
        return np.diag(
            [
                self.range_std_m**2,
                np.deg2rad(self.bearing_std_deg) ** 2,
                self.velocity_std**2,
                self.velocity_std**2,
            ]
        )


def trajectory(scenario: RobustScenario) -> tuple[NDArray[np.float64], NDArray[np.float64]]:
    """True planar trajectory: positions and velocities at every sample.

    Returns
    -------
    time : ndarray, shape (N,)
    states : ndarray, shape (N, 4)
        ``[east, north, v_east, v_north]``.
    """
    dt = scenario.dt
    n = int(round(scenario.duration_s / dt))
    time = np.arange(n) * dt
    rate = np.deg2rad(scenario.turn_rate_deg_s)
    turn_len = np.deg2rad(scenario.turn_angle_deg) / max(abs(rate), 1e-12)
    # heading (from east, counter-clockwise) as a function of time; integrate
    # the velocity exactly on a fine grid
    fine = np.linspace(0.0, time[-1] + dt, 20 * n + 1)
    in_turn = np.clip(fine - scenario.turn_time_s, 0.0, turn_len)
    heading = np.sign(rate) * in_turn * abs(rate)
    ve, vn = scenario.speed * np.cos(heading), scenario.speed * np.sin(heading)
    east = scenario.start_east_m + cumulative_trapezoid(ve, fine, initial=0.0)
    north = -scenario.overflight_offset_m + cumulative_trapezoid(vn, fine, initial=0.0)
    states = np.stack(
        [
            np.interp(time, fine, east),
            np.interp(time, fine, north),
            np.interp(time, fine, ve),
            np.interp(time, fine, vn),
        ],
        axis=-1,
    )
    return time, states


@dataclass(frozen=True)
class RobustData(BatchResult):
    """Simulated truth and measurements (batched over runs).

    Attributes
    ----------
    time : ndarray, shape (N,)
    truth : ndarray, shape (N, 5)
        ``[east, north, v_east, v_north, α]`` (the same path for every run).
    z : ndarray, shape (B, N, 4)
        Slant range, magnetic bearing (rad, wrapped), velocities.
    outlier : ndarray of bool, shape (B, N)
        Samples whose bearing carries an outlier.
    near_station : ndarray of bool, shape (N,)
        Samples inside ``outlier_radius_m``.
    scenario : RobustScenario
    """

    time: NDArray[np.float64]
    truth: NDArray[np.float64]
    z: NDArray[np.float64]
    outlier: NDArray[np.bool_]
    near_station: NDArray[np.bool_]
    scenario: RobustScenario

    @property
    def runs(self) -> int:
        """Number of Monte Carlo runs ``B``."""
        return int(self.z.shape[0])

    @property
    def label(self) -> str:
        """``"dme-vor"``."""
        return "dme-vor"


def _measure(states: NDArray, height: float, magvar: NDArray | float) -> NDArray:
    e, n = states[..., 0], states[..., 1]
    rng = np.sqrt(e * e + n * n + height * height)
    bearing = wrap_angle(np.arctan2(e, n) - magvar)
    return np.stack([rng, bearing, states[..., 2], states[..., 3]], axis=-1)


def simulate_robust(
    scenario: RobustScenario | None = None, seed: int = 0, runs: int = 1
) -> RobustData:
    """Simulate the fly-over: DME range, VOR bearing with bias and outliers, velocity.

    Parameters
    ----------
    scenario : RobustScenario, optional
        Parameters (default: the paper-like scenario, -5° variation, outliers on).
    seed : int
        Seed of the random generator.
    runs : int
        Number of Monte Carlo runs ``B`` (noises and outlier bursts differ).

    Returns
    -------
    RobustData
    """
    scenario = scenario or RobustScenario()
    scenario.validate()
    if int(runs) != runs or runs < 1:
        raise NoisevarError(f"runs={runs} must be a positive integer.")
    rng = np.random.default_rng(seed)
    time, states = trajectory(scenario)
    n = time.size
    alpha = np.deg2rad(scenario.magvar_deg)
    clean = _measure(states, scenario.height_m, alpha)
    noise_std = np.sqrt(np.diag(scenario.R))
    z = clean[None] + rng.standard_normal((runs, n, 4)) * noise_std
    near = np.hypot(states[:, 0], states[:, 1]) < scenario.outlier_radius_m
    outlier = np.zeros((runs, n), dtype=bool)
    jump = np.zeros((runs, n))
    if scenario.outliers and scenario.burst_rate > 0:
        starts = (rng.random((runs, n)) < scenario.burst_rate) & near[None]
        lengths = rng.integers(scenario.burst_length[0], scenario.burst_length[1] + 1, (runs, n))
        sizes = np.deg2rad(rng.uniform(*scenario.outlier_deg, (runs, n))) * rng.choice(
            [-1.0, 1.0], (runs, n)
        )
        # a burst covers [start, start + length); later bursts overwrite
        b_idx, k_idx = np.nonzero(starts)
        for b, k in zip(b_idx, k_idx, strict=True):  # a few dozen bursts per run
            stop = min(k + lengths[b, k], n)
            outlier[b, k:stop] = True
            jump[b, k:stop] = sizes[b, k]
        outlier &= near[None]  # bursts end when the aircraft leaves the zone
        z[..., 1] += np.where(outlier, jump, 0.0)
    z[..., 1] = wrap_angle(z[..., 1])
    truth = np.concatenate([states, np.full((n, 1), alpha)], axis=-1)
    return RobustData(
        time=time, truth=truth, z=z, outlier=outlier, near_station=near, scenario=scenario
    )

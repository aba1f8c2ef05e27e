"""Robust M-estimation EKF with a bearing-bias state: DME/VOR-like navigation (spec B3).

Seed ``robust-dme-vor-sins-2022.txt``. A ground station measures the slant
range to an aircraft (DME) and the aircraft's bearing from the station (VOR).
The VOR bearing is referenced to *magnetic* north, so it carries the
station's magnetic variation ``α`` (paper Fig. 1, ``α = ψ - ψ_m``, default
-5°), which the filter estimates as an augmented constant state (paper
eq. (1)). Near the station (the VOR's overhead cone of confusion) the bearing
jumps: bursts of outliers (paper section 1.2, Fig. 2), which the Huber
M-estimation update (paper eqs. (12)-(14)) resists.

We keep the paper's structure in a planar form: the paper's SINS becomes an
inertial velocity measurement (true-north frame), which is what makes ``α``
observable — with range and bearing alone a rotation of the whole
trajectory about the station is another constant-velocity trajectory, and
``α`` could not be told apart from it.

Model (state ``[east, north, v_east, v_north, α]``, nearly constant
velocity, ``α`` constant)::

    z = [ sqrt(e² + n² + h²),        slant range (DME), h the known height
          atan2(e, n) - α,           magnetic bearing (VOR), wrapped
          v_east, v_north ]          inertial velocity

Three filters, all on :mod:`noisevar.kalman`'s one core:

* ``ekf``: the plain EKF with the ``α`` state;
* ``no-bias``: the EKF that ignores the magnetic variation (takes the
  magnetic bearing as a true one); by default with the Huber update, as in
  the paper's section 4.2.1 where both variants use the M-estimation filter,
  so the comparison isolates the bias (``no_bias_robust=False`` for a plain
  EKF);
* ``huber``: the EKF with the ``α`` state and the Huber update
  (:class:`noisevar.kalman.HuberUpdate`, ``κ`` and the iteration count as
  parameters; paper: 1.345 and 10; our default ``κ`` is
  :data:`DEFAULT_KAPPA` = 2.5, chosen from the measurements below).

Choosing ``κ`` (what we measured). The issue's targets are a Huber position
RMSE at most 0.7 times the plain EKF's with outliers and within 1 % of it
without. Over 500 runs (seeds 1-5, 100 runs each: held out from the
benchmark's seed 0), ratio Huber/EKF with a paired bootstrap 95 % interval
(runs resampled, both filters on the same noise)::

    κ       with outliers          without outliers
    1.345   0.662 [0.639, 0.683]   0.991 [0.972, 1.009]
    1.5     0.662 [0.640, 0.683]   0.991 [0.975, 1.006]
    2.0     0.667 [0.647, 0.686]   0.996 [0.987, 1.004]
    2.5     0.676 [0.657, 0.694]   0.998 [0.991, 1.002]
    3.0     0.686 [0.668, 0.704]   1.000 [0.999, 1.001]

The outliers (10-40° against 1° noise) are caught by every ``κ`` up to 3;
what ``κ`` changes is the Gaussian efficiency. The paper's 1.345 meets both
targets on average, but the clean ratio of one 100-run batch scatters from
0.947 to 1.027 across seeds: the "within 1 %" comparison at ``κ = 1.345`` is
dominated by run-to-run noise: 82 % of the clean MSE is in the 100 steps
after the start-up (36-24 km out, where 1° of bearing is 400-600 m of
cross-range), and five runs carry 39 % of the paired Huber-EKF difference
(seed 0). ``κ = 2.5`` is the only value of the grid whose
intervals lie inside both targets; it costs a little outlier rejection
(0.676 against 0.662). Smaller outliers would change the picture: with
3-8° jumps every ``κ`` of the grid stays at 0.99-1.00 x the EKF (seed 0).
:func:`kappa_tradeoff` reproduces the table (``noisy``/``clean`` from
:func:`simulate_robust` with seeds 1-5, 100 runs each; defaults otherwise).

Entry points: :func:`simulate_robust` (seeded scenario, batched over runs),
:func:`run_robust` (the three filters and the metrics),
:func:`kappa_tradeoff` and :func:`paired_rmse_ratio` (the κ study).
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray
from scipy.integrate import cumulative_trapezoid

from noisevar.errors import NoisevarError
from noisevar.kalman import FilterResult, HuberUpdate, StateSpaceModel, run_filter, wrap_angle

STATE_NAMES = ("east", "north", "v_east", "v_north", "magvar")
MEASUREMENT_NAMES = ("slant range", "magnetic bearing", "v_east", "v_north")

#: Error of the filters' initial position/velocity (m, m, m/s, m/s).
START_ERROR = np.array([300.0, -200.0, 2.0, -1.0])
#: The paper's Huber threshold (95 % Gaussian efficiency).
PAPER_KAPPA = 1.345
#: Our default, chosen from the κ study in the module docstring.
DEFAULT_KAPPA = 2.5


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
class RobustData:
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


def build_model(
    scenario: RobustScenario,
    x_start: NDArray[np.float64],
    with_bias: bool = True,
    accel_psd: float = 10.0,
    magvar_prior_deg: float = 10.0,
) -> StateSpaceModel:
    """The (extended) state-space model of the filters.

    Parameters
    ----------
    scenario : RobustScenario
        Supplies ``dt``, the height and the nominal ``R``.
    x_start : ndarray, shape (4,)
        Rough position/velocity one step before the first measurement.
    with_bias : bool
        Augment the state with the magnetic variation ``α`` (prior 0 ±
        ``magvar_prior_deg``). Without it, the bearing is taken as true.
    accel_psd : float
        White-acceleration spectral density (m²/s³) of the
        nearly-constant-velocity model (covers the turn).
    magvar_prior_deg : float
        Prior standard deviation of ``α`` (deg).

    Returns
    -------
    StateSpaceModel
    """
    dt, height = scenario.dt, scenario.height_m
    n_state = 5 if with_bias else 4
    F = np.eye(n_state)
    F[0, 2] = F[1, 3] = dt
    Q = np.zeros((n_state, n_state))
    block = accel_psd * np.array([[dt**3 / 3, dt**2 / 2], [dt**2 / 2, dt]])
    Q[np.ix_([0, 2], [0, 2])] = block
    Q[np.ix_([1, 3], [1, 3])] = block
    if with_bias:
        Q[4, 4] = 1e-12  # a constant, kept from freezing numerically
    x0 = np.zeros(n_state)
    x0[:4] = x_start
    p0 = [1000.0**2, 1000.0**2, 5.0**2, 5.0**2]
    if with_bias:
        p0.append(np.deg2rad(magvar_prior_deg) ** 2)

    def h(x: NDArray, k: int) -> NDArray:
        alpha = x[:, 4] if with_bias else 0.0
        return _measure(x, height, alpha)

    def H_jacobian(x: NDArray, k: int) -> NDArray:
        e, nn = x[:, 0], x[:, 1]
        horiz2 = np.maximum(e * e + nn * nn, 1e-6)
        slant = np.sqrt(horiz2 + height * height)
        J = np.zeros((x.shape[0], 4, n_state))
        J[:, 0, 0] = e / slant
        J[:, 0, 1] = nn / slant
        J[:, 1, 0] = nn / horiz2
        J[:, 1, 1] = -e / horiz2
        if with_bias:
            J[:, 1, 4] = -1.0
        J[:, 2, 2] = 1.0
        J[:, 3, 3] = 1.0
        return J

    return StateSpaceModel(
        Q=Q,
        R=scenario.R,
        x0=x0,
        P0=np.diag(p0),
        F=F,
        h=h,
        H_jacobian=H_jacobian,
        dt=dt,
        angle_states=(4,) if with_bias else (),
        angle_measurements=(1,),
        state_names=STATE_NAMES[:n_state],
        measurement_names=MEASUREMENT_NAMES,
        name="dme-vor" + ("+magvar" if with_bias else ""),
    )


@dataclass(frozen=True)
class RobustResult:
    """The three filters on one scenario, with what the figures and the metrics need.

    Attributes
    ----------
    data : RobustData
    filters : dict of str to FilterResult
        ``"ekf"``, ``"no-bias"``, ``"huber"`` (batched over runs).
    rmse_position : dict of str to float
        Horizontal position RMSE over runs and steps after ``skip`` (m).
    magvar_estimate_deg : ndarray, shape (B,)
        Final ``α`` estimate of the Huber filter, per run (deg).
    magvar_estimate_ekf_deg : ndarray, shape (B,)
        Final ``α`` estimate of the plain EKF, per run (deg).
    kappa, iterations : float, int
        Huber settings.
    skip : int
        Leading steps left out of the RMSE.
    """

    data: RobustData
    filters: dict[str, FilterResult]
    rmse_position: dict[str, float]
    magvar_estimate_deg: NDArray[np.float64]
    magvar_estimate_ekf_deg: NDArray[np.float64]
    kappa: float
    iterations: int
    skip: int

    @property
    def magvar_mean_deg(self) -> float:
        """Magnetic variation estimated by the Huber EKF, mean over runs (degrees)."""
        return float(np.mean(self.magvar_estimate_deg))

    @property
    def magvar_mean_ekf_deg(self) -> float:
        """Magnetic variation estimated by the plain EKF, mean over runs (degrees)."""
        return float(np.mean(self.magvar_estimate_ekf_deg))

    def position_error(self, name: str) -> NDArray[np.float64]:
        """Horizontal position error of filter ``name`` (m), shape (B, N)."""
        res = self.filters[name]
        e = res.x[..., :2] - self.data.truth[None, :, :2]
        return np.hypot(e[..., 0], e[..., 1])

    def position_mse_per_run(self, name: str) -> NDArray[np.float64]:
        """Mean squared horizontal error of each run after ``skip`` (m²), shape (B,).

        ``sqrt(mean(...))`` over the runs is :attr:`rmse_position`.
        """
        e = self.filters[name].x[:, self.skip :, :2] - self.data.truth[None, self.skip :, :2]
        return np.mean(np.sum(e**2, axis=-1), axis=1)


def run_robust(
    data: RobustData,
    kappa: float = DEFAULT_KAPPA,
    iterations: int = 10,
    accel_psd: float = 10.0,
    no_bias_robust: bool = True,
    skip: int = 30,
    filters: tuple[str, ...] = ("ekf", "no-bias", "huber"),
) -> RobustResult:
    """Run the plain EKF, the bias-ignoring EKF and the Huber EKF on ``data``.

    Parameters
    ----------
    data : RobustData
        From :func:`simulate_robust`.
    kappa : float
        Huber threshold ``κ`` on whitened residuals (paper eq. (14): 1.345;
        default :data:`DEFAULT_KAPPA`, see the module docstring).
    iterations : int
        Huber IRLS iterations (paper: 10).
    accel_psd : float
        White-acceleration density of the filters' motion model (m²/s³).
        The default (10) matches the turn (3°/s at 120 m/s is 6.3 m/s²): with
        a model that cannot follow the turn, the Huber update, which also
        weights the *prediction's* whitened residuals (spec B3), downweights
        the prior during the turn and ends up with a covariance far smaller
        than its errors (we measured NEES ~30 with ``accel_psd=1``).
    no_bias_robust : bool
        Use the Huber update in the bias-ignoring filter (paper 4.2.1).
    skip : int
        Leading steps left out of the RMSE (start-up).
    filters : tuple of str
        Which of ``"ekf"``, ``"no-bias"``, ``"huber"`` to run.

    Returns
    -------
    RobustResult
    """
    if not (kappa > 0):
        raise NoisevarError(f"kappa={kappa} must be positive (or inf: the plain update).")
    unknown = set(filters) - {"ekf", "no-bias", "huber"}
    if unknown:
        raise NoisevarError(f"unknown filters {sorted(unknown)}; use ekf, no-bias, huber.")
    robust = HuberUpdate(kappa=kappa, iterations=iterations)
    scen = data.scenario
    # a rough start one sample before the first true state, off by a few hundred metres
    start = data.truth[0, :4] - scen.dt * np.r_[data.truth[0, 2:4], 0.0, 0.0]
    start = start + START_ERROR
    truth5 = np.broadcast_to(data.truth, (data.runs, *data.truth.shape))
    out: dict[str, FilterResult] = {}
    for name in filters:
        with_bias = name != "no-bias"
        model = build_model(scen, start, with_bias=with_bias, accel_psd=accel_psd)
        use_huber = name == "huber" or (name == "no-bias" and no_bias_robust)
        truth = truth5 if with_bias else truth5[..., :4]
        out[name] = run_filter(
            model,
            data.z,
            robust=robust if use_huber else None,
            truth=truth,
        )
    rmse = {}
    for name, res in out.items():
        e = res.x[:, skip:, :2] - data.truth[None, skip:, :2]
        rmse[name] = float(np.sqrt(np.mean(np.sum(e**2, axis=-1))))
    nan = np.full(data.runs, np.nan)
    return RobustResult(
        data=data,
        filters=out,
        rmse_position=rmse,
        magvar_estimate_deg=np.rad2deg(out["huber"].x[:, -1, 4]) if "huber" in out else nan,
        magvar_estimate_ekf_deg=np.rad2deg(out["ekf"].x[:, -1, 4]) if "ekf" in out else nan,
        kappa=float(kappa),
        iterations=int(iterations),
        skip=int(skip),
    )


def paired_rmse_ratio(
    mse_a: NDArray[np.float64],
    mse_b: NDArray[np.float64],
    n_boot: int = 2000,
    seed: int = 0,
    coverage: float = 0.95,
) -> tuple[float, float, float]:
    """RMSE ratio ``a / b`` of two filters on the same runs, with a paired bootstrap interval.

    ``ratio = sqrt(Σ mse_a / Σ mse_b)``; the interval resamples *runs*
    (the same indices for both filters, so the noise they share cancels).

    Parameters
    ----------
    mse_a, mse_b : ndarray, shape (B,)
        Per-run mean squared errors of the two filters on the same runs.
    n_boot : int
        Bootstrap resamples.
    seed : int
        Seed of the resampling.
    coverage : float
        Probability of the two-sided percentile interval.

    Returns
    -------
    (ratio, low, high) : tuple of float
        With a single run the interval is undefined: ``low = high = nan``.
    """
    a = np.asarray(mse_a, dtype=float)
    b = np.asarray(mse_b, dtype=float)
    if a.shape != b.shape or a.ndim != 1 or a.size < 1:
        raise NoisevarError(
            f"paired_rmse_ratio needs two non-empty per-run MSE vectors of the same length, "
            f"got shapes {a.shape} and {b.shape}."
        )
    if int(n_boot) < 1 or not 0 < coverage < 1:
        raise NoisevarError("n_boot must be >= 1 and coverage in (0, 1).")
    if a.size == 1:
        return float(np.sqrt(a.sum() / b.sum())), float("nan"), float("nan")
    idx = np.random.default_rng(seed).integers(0, a.size, (int(n_boot), a.size))
    boot = np.sqrt(a[idx].sum(axis=1) / b[idx].sum(axis=1))
    tail = 100.0 * (1.0 - coverage) / 2.0
    lo, hi = np.percentile(boot, [tail, 100.0 - tail])
    return float(np.sqrt(a.sum() / b.sum())), float(lo), float(hi)


@dataclass(frozen=True)
class KappaTradeoff:
    """Huber/EKF position-RMSE ratios over ``κ``, with and without outliers.

    Attributes
    ----------
    kappa : ndarray, shape (k,)
    ratio_outliers, ratio_clean : ndarray, shape (k,)
        Huber RMSE / plain-EKF RMSE on the same runs.
    ci_outliers, ci_clean : ndarray, shape (k, 2)
        Paired bootstrap intervals of those ratios.
    rmse_huber_outliers, rmse_huber_clean : ndarray, shape (k,)
        Huber position RMSE (m).
    rmse_ekf_outliers, rmse_ekf_clean : float
        Plain-EKF position RMSE (m).
    magvar_estimate_deg : ndarray, shape (k,)
        Mean over runs of the Huber filter's final ``α`` (with outliers).
    runs : int
        Runs pooled per ratio.
    coverage : float
    """

    kappa: NDArray[np.float64]
    ratio_outliers: NDArray[np.float64]
    ci_outliers: NDArray[np.float64]
    ratio_clean: NDArray[np.float64]
    ci_clean: NDArray[np.float64]
    rmse_huber_outliers: NDArray[np.float64]
    rmse_huber_clean: NDArray[np.float64]
    rmse_ekf_outliers: float
    rmse_ekf_clean: float
    magvar_estimate_deg: NDArray[np.float64]
    runs: int
    coverage: float

    def meets(self, with_outliers: float = 0.7, without: float = 0.01) -> NDArray[np.bool_]:
        """Which ``κ`` meet both targets on the point estimates."""
        return (self.ratio_outliers <= with_outliers) & (np.abs(self.ratio_clean - 1) <= without)

    def meets_with_confidence(
        self, with_outliers: float = 0.7, without: float = 0.01
    ) -> NDArray[np.bool_]:
        """Which ``κ`` meet both targets over their whole intervals."""
        return (self.ci_outliers[:, 1] <= with_outliers) & (
            np.abs(self.ci_clean - 1).max(axis=1) <= without
        )


def _as_list(data: RobustData | Sequence[RobustData], name: str) -> list[RobustData]:
    out = [data] if isinstance(data, RobustData) else list(data)
    if not out or not all(isinstance(d, RobustData) for d in out):
        raise NoisevarError(f"{name}: give a RobustData or a non-empty list of them.")
    return out


def kappa_tradeoff(
    noisy: RobustData | Sequence[RobustData],
    clean: RobustData | Sequence[RobustData],
    kappas: Sequence[float] = (PAPER_KAPPA, 1.5, 2.0, 2.5, 3.0),
    iterations: int = 10,
    n_boot: int = 2000,
    seed: int = 0,
    coverage: float = 0.95,
    known: Mapping[float, tuple[RobustResult, RobustResult]] | None = None,
) -> KappaTradeoff:
    """The κ trade-off: Huber/EKF RMSE ratios with and without outliers.

    Every ``κ`` runs on the same records, so the ratios are paired
    (:func:`paired_rmse_ratio`). Several batches (for example several
    seeds) are pooled run by run.

    Parameters
    ----------
    noisy, clean : RobustData or list of RobustData
        Records with outliers and without (same lengths of lists).
    kappas : sequence of float
        Huber thresholds.
    iterations : int
        IRLS iterations.
    n_boot, seed, coverage
        Bootstrap of the intervals.
    known : mapping of float to (RobustResult, RobustResult), optional
        Results already computed for one batch (``noisy`` and ``clean``
        single records), by ``κ``: each pair must hold ``"ekf"`` and
        ``"huber"``; saves re-running them.

    Returns
    -------
    KappaTradeoff
    """
    noisy_l, clean_l = _as_list(noisy, "noisy"), _as_list(clean, "clean")
    if len(noisy_l) != len(clean_l):
        raise NoisevarError("give as many clean records as noisy ones.")
    ks = np.asarray(list(kappas), dtype=float)
    if ks.size == 0 or not np.all(ks > 0):
        raise NoisevarError(f"kappas={list(kappas)}: give positive Huber thresholds.")
    known = dict(known or {})
    if known and len(noisy_l) > 1:
        raise NoisevarError("known results only go with a single noisy/clean batch.")

    def pair(k: float, nd: RobustData, cd: RobustData) -> tuple[RobustResult, RobustResult]:
        if k in known:
            return known[k]
        return (
            run_robust(nd, kappa=k, iterations=iterations, filters=("huber",)),
            run_robust(cd, kappa=k, iterations=iterations, filters=("huber",)),
        )

    ekf_n, ekf_c = [], []
    for nd, cd in zip(noisy_l, clean_l, strict=True):
        if known:
            base_n, base_c = next(iter(known.values()))
        else:
            base_n = run_robust(nd, filters=("ekf",))
            base_c = run_robust(cd, filters=("ekf",))
        ekf_n.append(base_n.position_mse_per_run("ekf"))
        ekf_c.append(base_c.position_mse_per_run("ekf"))
    en, ec = np.concatenate(ekf_n), np.concatenate(ekf_c)
    rows = []
    for k in ks:
        hn, hc, mv = [], [], []
        for nd, cd in zip(noisy_l, clean_l, strict=True):
            rn, rc = pair(float(k), nd, cd)
            hn.append(rn.position_mse_per_run("huber"))
            hc.append(rc.position_mse_per_run("huber"))
            mv.append(rn.magvar_estimate_deg)
        a, b = np.concatenate(hn), np.concatenate(hc)
        rows.append(
            (
                paired_rmse_ratio(a, en, n_boot, seed, coverage),
                paired_rmse_ratio(b, ec, n_boot, seed, coverage),
                float(np.sqrt(a.mean())),
                float(np.sqrt(b.mean())),
                float(np.mean(np.concatenate(mv))),
            )
        )
    return KappaTradeoff(
        kappa=ks,
        ratio_outliers=np.array([r[0][0] for r in rows]),
        ci_outliers=np.array([r[0][1:] for r in rows]),
        ratio_clean=np.array([r[1][0] for r in rows]),
        ci_clean=np.array([r[1][1:] for r in rows]),
        rmse_huber_outliers=np.array([r[2] for r in rows]),
        rmse_huber_clean=np.array([r[3] for r in rows]),
        rmse_ekf_outliers=float(np.sqrt(en.mean())),
        rmse_ekf_clean=float(np.sqrt(ec.mean())),
        magvar_estimate_deg=np.array([r[4] for r in rows]),
        runs=int(en.size),
        coverage=float(coverage),
    )

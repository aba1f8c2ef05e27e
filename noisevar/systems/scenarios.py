"""Seeded scenarios: truth, measurements and a ready filter model.

Each generator returns a :class:`Scenario` holding ``B`` Monte Carlo runs
(same trajectory, independent noise), the true measurement covariance at
every step, the per-channel smoothing ``h`` for the SOMD estimator, and a
:meth:`Scenario.run` that filters all runs at once with any strategy.

* :func:`gps_circle` — the 2016 paper's section 3.2 (spec A9) exactly.
* :func:`noise_step`, :func:`noise_ramp` — a manoeuvring target whose
  position-noise standard deviation steps (ramps) up three-fold mid-run.
* :func:`outliers` — the same target with bursts of gross errors.
"""

from __future__ import annotations

import functools
from collections.abc import Callable, Sequence
from dataclasses import dataclass, field
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman import DivergenceCheck, HuberUpdate, StateSpaceModel, run_filter
from noisevar.kalman.result import FilterResult, wrap_angle
from noisevar.kalman.strategies import RStrategy


@dataclass
class Scenario:
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

    @property
    def runs(self) -> int:
        """Number of Monte Carlo runs ``B``."""
        return int(self.z.shape[0])

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


# --------------------------------------------------------------------------- gps-circle
#: Spec A9 constants.
GPS_RADIUS = 300.0
GPS_OMEGA = np.pi / 100.0
GPS_T = 0.5
GPS_DURATION = 3000.0
GPS_NOISE_STD = (5.0, 5.0, np.sqrt(2.0), 0.01)
GPS_R0 = (100.0, 100.0, 4.0, 0.01)
GPS_H_SMOOTH = (9e-4, 9e-4, 1e-7, 1e-4)
GPS_CHANNELS = ("east", "north", "speed", "heading")


def gps_process_noise(T: float = GPS_T) -> NDArray:
    """Process-noise covariance of the gps-circle model (the paper gives none).

    Model [20] holds speed and heading constant, but on the circle the
    heading grows by ``ωT`` = 0.0157 rad every step: a deterministic ramp
    that the random-walk model can only absorb as process noise, and that
    makes every filter of this model lag in heading (and so, slightly, in
    position). We chose ``Q`` by a consistency scan with the oracle filter
    (true ``R``; 10 runs): per-component normalised errors
    ``mean(e_i² / P_ii)`` after the start-up are 1.00 / 1.05 (east /
    north), 0.96 (heading) and 0.22 (speed, which is truly constant) with

    * east / north position: 0.03 m² per step (3e-3, the Euler-integration
      chord error alone, leaves NEES 3.4 per position: the heading lag
      leaks into position);
    * speed: 1e-4 (m/s)²;
    * heading: 5e-4 rad², about ``2 (ωT)²``.

    Larger ``Q`` raise the RMSE, smaller ones make the filter inconsistent;
    this one minimised the oracle's position RMSE among the values scanned
    (position 0.003 to 0.1, speed 1e-4 to 1e-3, heading 2.5e-4 to 1e-3).

    Parameters
    ----------
    T : float
        Sample period in seconds (the values are for 0.5 s and scale with
        ``T / 0.5``).

    Returns
    -------
    ndarray, shape (4, 4)
    """
    return np.diag([0.03, 0.03, 1e-4, 5e-4]) * (T / GPS_T)


def _gps_f(T: float):
    """Model [20] and its Jacobian for a batch of states ``x`` of shape ``(B, 4)``."""
    eyes: dict[int, NDArray] = {}  # identity stacks per batch size, copied at each call

    def f(x: NDArray, k: int) -> NDArray:
        out = x.copy()
        tv = T * x[:, 2]
        th = x[:, 3]
        out[:, 0] += tv * np.cos(th)
        out[:, 1] += tv * np.sin(th)
        return out

    def F_jacobian(x: NDArray, k: int) -> NDArray:
        th = x[:, 3]
        c, s = np.cos(th), np.sin(th)
        tv = T * x[:, 2]
        B = x.shape[0]
        eye = eyes.get(B)
        if eye is None:
            eye = eyes[B] = np.repeat(np.eye(4)[None], B, axis=0)
        J = eye.copy()
        # products written straight into the Jacobian's entries (no temporaries)
        np.multiply(T, c, out=J[:, 0, 2])
        np.multiply(tv, s, out=J[:, 0, 3])
        np.negative(J[:, 0, 3], out=J[:, 0, 3])
        np.multiply(T, s, out=J[:, 1, 2])
        np.multiply(tv, c, out=J[:, 1, 3])
        return J

    return f, F_jacobian


def _gps_transition(T: float) -> Callable[[NDArray, int, NDArray, NDArray], None] | None:
    """Model [20] and its Jacobian in one compiled kernel (``StateSpaceModel.transition``)."""
    from noisevar.kalman import _kernels

    if not _kernels.HAVE_NUMBA:  # pragma: no cover - numba not installed
        return None
    return functools.partial(_kernels.gps_transition, float(T))  # no Python frame per step


def gps_circle(
    runs: int = 1,
    seed: int | None = 0,
    duration: float = GPS_DURATION,
    Q: NDArray | None = None,
) -> Scenario:
    """The paper's GPS adaptive-filtering experiment (section 3.2, spec A9).

    A vehicle drives counter-clockwise on a circle of radius 300 m at
    ``ω = π/100`` rad/s (speed ``v = 3π`` m/s), sampled every 0.5 s for
    3000 s (6000 samples). The GPS measures east and north position
    (noise std 5 m), speed (√2 m/s) and heading (0.01 rad; heading measured
    from east, counter-clockwise, as model [20] uses it, wrapped to
    ``[-π, π)`` as a receiver reports it). The EKF uses model [20]::

        pE+ = pE + T v cos θ,  pN+ = pN + T v sin θ,  v+ = v,  θ+ = θ  (+ W)

    with all four states measured directly, initial
    ``R = diag(100, 100, 4, 0.01)`` and ``Q`` from :func:`gps_process_noise`.
    Each run's filter starts from its first measurement (``P0`` = initial
    ``R``) and processes the remaining 5999 samples.

    Parameters
    ----------
    runs : int
        Monte Carlo runs ``B``.
    seed : int, optional
        Seed of the noise generator.
    duration : float
        Seconds simulated (default 3000).
    Q : ndarray, shape (4, 4), optional
        Process noise (default :func:`gps_process_noise`).

    Returns
    -------
    Scenario
    """
    B = _check_runs(runs)
    T = GPS_T
    N = int(round(duration / T))
    if N < 10:
        raise NoisevarError(f"duration {duration} s is too short: give at least {10 * T} s")
    t = np.arange(N) * T
    phi = GPS_OMEGA * t
    v = GPS_RADIUS * GPS_OMEGA
    truth1 = np.stack(
        [
            GPS_RADIUS * np.cos(phi),
            GPS_RADIUS * np.sin(phi),
            np.full(N, v),
            phi + np.pi / 2.0,  # direction of motion, continuous (unwrapped)
        ],
        axis=1,
    )
    truth = np.repeat(truth1[None], B, axis=0)
    rng = np.random.default_rng(seed)
    std = np.asarray(GPS_NOISE_STD)
    z = truth + rng.standard_normal((B, N, 4)) * std
    z[..., 3] = wrap_angle(z[..., 3])
    R_true = np.broadcast_to(np.diag(std**2), (N, 4, 4))
    f, F_jac = _gps_f(T)
    model = StateSpaceModel(
        transition=_gps_transition(T),
        Q=gps_process_noise(T) if Q is None else Q,
        R=np.diag(GPS_R0),
        x0=z[0, 0],
        P0=np.diag(GPS_R0),
        f=f,
        F_jacobian=F_jac,
        H=np.eye(4),
        dt=T,
        angle_states=(3,),
        angle_measurements=(3,),
        state_names=("pE", "pN", "v", "theta"),
        measurement_names=GPS_CHANNELS,
        name="gps-circle",
    )
    return Scenario(
        name="gps-circle",
        model=model,
        time=t,
        truth=truth,
        z=z,
        R_true=R_true,
        x0=np.array(z[:, 0]),
        first_step=1,
        h_smooth=GPS_H_SMOOTH,
        angle_channels=(3,),
        description=(
            "Vehicle on a 300 m circle at π/100 rad/s, T = 0.5 s, 3000 s; GPS east/north "
            "position (σ = 5 m), speed (σ = √2 m/s), heading (σ = 0.01 rad); EKF on model [20], "
            "initial R = diag(100, 100, 4, 0.01) (spec A9)."
        ),
    )


# --------------------------------------------------------------------------- manoeuvring target
TARGET_T = 0.1
TARGET_STEPS = 6000
TARGET_SIGMA = 5.0
TARGET_H_SMOOTH = 1e-3
#: Segments of (duration s, tangential acceleration m/s², turn rate rad/s).
TARGET_MANOEUVRES = (
    (60.0, 0.0, 0.0),
    (40.0, 0.0, 0.05),
    (60.0, 0.3, 0.0),
    (50.0, 0.0, -0.04),
    (70.0, -0.2, 0.0),
    (60.0, 0.0, 0.03),
    (80.0, 0.1, 0.0),
    (50.0, 0.0, -0.05),
    (80.0, 0.0, 0.0),
    (50.0, 0.0, 0.02),
)


def _smooth_profile(values: NDArray, t: NDArray, edges: NDArray, ramp: float) -> NDArray:
    """Piecewise-constant profile whose steps are smoothed by linear ramps of ``ramp`` s."""
    out = np.full_like(t, values[0], dtype=float)
    for e, (a, b) in zip(edges[1:-1], zip(values[:-1], values[1:], strict=True), strict=True):
        out += (b - a) * np.clip((t - e) / ramp + 0.5, 0.0, 1.0)
    return out


def _target_truth(N: int, T: float) -> NDArray:
    """A manoeuvring 2-D target: straight legs, turns, speed-ups; state [px, vx, py, vy]."""
    t = np.arange(N) * T
    seg = np.asarray(TARGET_MANOEUVRES)
    reps = int(np.ceil(t[-1] / seg[:, 0].sum())) + 1
    seg = np.tile(seg, (reps, 1))
    edges = np.concatenate([[0.0], np.cumsum(seg[:, 0])])
    acc = _smooth_profile(seg[:, 1], t, edges, ramp=5.0)
    turn = _smooth_profile(seg[:, 2], t, edges, ramp=5.0)
    speed = 20.0 + np.cumsum(acc) * T
    heading = 0.3 + np.cumsum(turn) * T
    vx, vy = speed * np.cos(heading), speed * np.sin(heading)
    px, py = np.cumsum(vx) * T, np.cumsum(vy) * T
    return np.stack([px, vx, py, vy], axis=1)


def _cv_model(T: float, q: float, r0: float, x0: NDArray) -> StateSpaceModel:
    """Constant-velocity model with white-acceleration (spectral density ``q``) noise."""
    F1 = np.array([[1.0, T], [0.0, 1.0]])
    Q1 = q * np.array([[T**3 / 3, T**2 / 2], [T**2 / 2, T]])
    F = np.kron(np.eye(2), F1)
    Q = np.kron(np.eye(2), Q1)
    H = np.array([[1.0, 0, 0, 0], [0, 0, 1.0, 0]])
    return StateSpaceModel(
        Q=Q,
        R=np.eye(2) * r0,
        x0=x0,
        P0=np.diag([r0, 100.0, r0, 100.0]),
        F=F,
        H=H,
        dt=T,
        state_names=("px", "vx", "py", "vy"),
        measurement_names=("x", "y"),
        name="cv-target",
    )


def _target_scenario(
    name: str,
    sigma: NDArray,
    runs: int,
    seed: int | None,
    change: tuple[int, int],
    description: str,
    q: float,
) -> Scenario:
    B = _check_runs(runs)
    T = TARGET_T
    N = sigma.size
    if N < 200:
        raise NoisevarError(f"n_steps must be at least 200, got {N}")
    truth1 = _target_truth(N, T)
    truth = np.repeat(truth1[None], B, axis=0)
    rng = np.random.default_rng(seed)
    z = truth[..., [0, 2]] + rng.standard_normal((B, N, 2)) * sigma[None, :, None]
    R_true = (sigma**2)[:, None, None] * np.eye(2)
    # initial state from the first two measurements (position and a rough velocity)
    x0 = np.stack(
        [z[:, 1, 0], (z[:, 1, 0] - z[:, 0, 0]) / T, z[:, 1, 1], (z[:, 1, 1] - z[:, 0, 1]) / T],
        axis=1,
    )
    model = _cv_model(T, q=q, r0=TARGET_SIGMA**2, x0=x0[0])
    model = StateSpaceModel(
        Q=model.Q,
        R=model.R,
        x0=model.x0,
        P0=np.diag([TARGET_SIGMA**2, 2 * TARGET_SIGMA**2 / T**2] * 2),
        F=model.F,
        H=model.H,
        dt=T,
        state_names=model.state_names,
        measurement_names=model.measurement_names,
        name=name,
    )
    return Scenario(
        name=name,
        model=model,
        time=np.arange(N) * T,
        truth=truth,
        z=z,
        R_true=R_true,
        x0=x0,
        first_step=2,
        h_smooth=(TARGET_H_SMOOTH, TARGET_H_SMOOTH),
        change=change,
        description=description,
    )


def _check_factor(factor: float) -> None:
    if not (np.isfinite(factor) and factor > 0):
        raise NoisevarError(f"factor must be a positive number, got {factor}")


#: White-acceleration spectral density of the target's CV model (m²/s³),
#: about the square of the largest manoeuvre acceleration (1 m/s²) per second.
TARGET_Q = 1.0


def noise_step(
    runs: int = 1, seed: int | None = 0, n_steps: int = TARGET_STEPS, factor: float = 3.0
) -> Scenario:
    """Manoeuvring target whose position-noise std steps up ``factor``-fold at mid-run.

    A 2-D target (straight legs, turns up to 0.05 rad/s, accelerations up
    to 0.3 m/s², speed about 20 m/s, transitions smoothed over 5 s) is
    sampled every 0.1 s; x and y positions are measured with noise std
    5 m, then ``3 × 5`` m from the middle sample on. The filter is a
    constant-velocity KF (white acceleration, ``q = 1`` m²/s³) whose nominal
    ``R`` is the first half's.

    Parameters
    ----------
    runs : int
        Monte Carlo runs.
    seed : int, optional
        Noise seed.
    n_steps : int
        Samples (default 6000, 600 s).
    factor : float
        Ratio of the noise std after / before the step.

    Returns
    -------
    Scenario
        ``change = (mid, mid)``.
    """
    _check_factor(factor)
    mid = int(n_steps) // 2
    sigma = np.where(np.arange(n_steps) < mid, TARGET_SIGMA, factor * TARGET_SIGMA)
    return _target_scenario(
        "noise-step",
        sigma,
        runs,
        seed,
        (mid, mid),
        f"Manoeuvring 2-D target, T = {TARGET_T} s; position noise std steps from "
        f"{TARGET_SIGMA:g} m to {factor * TARGET_SIGMA:g} m at step {mid}; CV Kalman filter.",
        TARGET_Q,
    )


def noise_ramp(
    runs: int = 1, seed: int | None = 0, n_steps: int = TARGET_STEPS, factor: float = 3.0
) -> Scenario:
    """Same target; the position-noise std ramps from 5 m to ``factor · 5`` m.

    The ramp is linear in the standard deviation from 40 % to 60 % of the
    record.

    Parameters
    ----------
    runs, seed, n_steps, factor
        As for :func:`noise_step`.

    Returns
    -------
    Scenario
        ``change = (ramp start, ramp end)``.
    """
    _check_factor(factor)
    a, b = int(0.4 * n_steps), int(0.6 * n_steps)
    k = np.arange(n_steps)
    frac = np.clip((k - a) / max(b - a, 1), 0.0, 1.0)
    sigma = TARGET_SIGMA * (1.0 + (factor - 1.0) * frac)
    return _target_scenario(
        "noise-ramp",
        sigma,
        runs,
        seed,
        (a, b),
        f"Manoeuvring 2-D target, T = {TARGET_T} s; position noise std ramps from "
        f"{TARGET_SIGMA:g} m to {factor * TARGET_SIGMA:g} m between steps {a} and {b}; "
        "CV Kalman filter.",
        TARGET_Q,
    )


def outliers(
    runs: int = 1,
    seed: int | None = 0,
    n_steps: int = TARGET_STEPS,
    n_bursts: int = 6,
    burst_length: int = 30,
    fraction: float = 0.3,
    size: float = 20.0,
) -> Scenario:
    """Same target, constant 5 m noise, with bursts of gross measurement errors.

    In each of ``n_bursts`` bursts of ``burst_length`` samples a
    ``fraction`` of the samples of each channel gets an extra error of
    ``± size · σ`` (uniform between half and the full size).

    Parameters
    ----------
    runs, seed, n_steps
        As for :func:`noise_step`.
    n_bursts, burst_length : int
        Number and length of bursts (evenly spread over the record).
    fraction : float
        Fraction of samples hit inside a burst.
    size : float
        Outlier size in noise standard deviations.

    Returns
    -------
    Scenario
        With ``outlier_mask``.
    """
    sigma = np.full(n_steps, TARGET_SIGMA)
    sc = _target_scenario(
        "outliers",
        sigma,
        runs,
        seed,
        (-1, -1),
        f"Manoeuvring 2-D target, T = {TARGET_T} s, noise std {TARGET_SIGMA:g} m, "
        f"{n_bursts} bursts of {burst_length} samples with {fraction:.0%} gross errors of "
        f"{size / 2:g}-{size:g} σ; CV Kalman filter.",
        TARGET_Q,
    )
    rng = np.random.default_rng(None if seed is None else seed + 7919)
    B = sc.runs
    mask = np.zeros((B, n_steps, 2), dtype=bool)
    starts = np.linspace(0.1, 0.9, n_bursts) * n_steps
    for s in starts.astype(int):
        length = min(burst_length, n_steps - s)
        mask[:, s : s + length] = rng.random((B, length, 2)) < fraction
    sign = rng.choice([-1.0, 1.0], size=mask.shape)
    mag = rng.uniform(0.5, 1.0, size=mask.shape) * size * TARGET_SIGMA
    sc.z = sc.z + mask * sign * mag
    sc.outlier_mask = mask
    return sc


SCENARIOS = {
    "gps-circle": gps_circle,
    "noise-step": noise_step,
    "noise-ramp": noise_ramp,
    "outliers": outliers,
}


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

"""The manoeuvring-target scenarios: noise step, noise ramp and outliers."""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman import StateSpaceModel
from noisevar.systems.scenarios.scenario import Scenario, _check_runs

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
        state_groups={"position (m)": (0, 2), "velocity (m/s)": (1, 3)},
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

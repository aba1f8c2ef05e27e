"""The gps-circle scenario: the 2016 paper's section 3.2 (docs/algorithms.md §A9)."""

from __future__ import annotations

import functools
import math
from collections.abc import Callable

import numpy as np
from numpy.typing import NDArray

from noisevar.errors import NoisevarError
from noisevar.kalman import StateSpaceModel, kernels
from noisevar.kalman.result import wrap_angle
from noisevar.systems.scenarios.scenario import Scenario, _check_runs

#: Constants of docs/algorithms.md §A9.
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

    ``diag(0.03, 0.03, 1e-4, 5e-4)`` per 0.5 s step (east, north, speed,
    heading), chosen by a consistency scan with the oracle filter: the
    heading grows by ``ωT`` every step, a ramp model [20] can only absorb as
    process noise (heading about ``2 (ωT)²``).

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


def _transition_kernel(T, x, k, x_out, F_out):  # pragma: no cover - compiled
    """Model [20] and its Jacobian for a batch ``x`` (B, 4), into ``x_out``, ``F_out``.

    ``functools.partial(kernel, T)`` is a ``StateSpaceModel.transition``
    (``k``, the step index, is unused); :func:`_gps_f` is its numpy form.
    """
    B, n = x.shape
    for b in range(B):
        th = x[b, 3]
        c = math.cos(th)
        s = math.sin(th)
        tv = T * x[b, 2]
        for i in range(n):
            x_out[b, i] = x[b, i]
            for j in range(n):
                F_out[b, i, j] = 1.0 if i == j else 0.0
        x_out[b, 0] += tv * c
        x_out[b, 1] += tv * s
        F_out[b, 0, 2] = T * c
        F_out[b, 0, 3] = -(tv * s)
        F_out[b, 1, 2] = T * s
        F_out[b, 1, 3] = tv * c


_TRANSITION = kernels.compiled(_transition_kernel)


def gps_transition(T: float) -> Callable[[NDArray, int, NDArray, NDArray], None] | None:
    """Model [20] and its Jacobian in one compiled kernel (``StateSpaceModel.transition``).

    Parameters
    ----------
    T : float
        Sample period (s).

    Returns
    -------
    callable or None
        ``transition(x, k, x_out, F_out)``; None without numba (the model then
        uses its numpy ``f`` and ``F_jacobian``).
    """
    if _TRANSITION is None:  # pragma: no cover - numba not installed
        return None
    return functools.partial(_TRANSITION, float(T))  # no Python frame per step


def gps_circle(
    runs: int = 1,
    seed: int | None = 0,
    duration: float = GPS_DURATION,
    Q: NDArray | None = None,
) -> Scenario:
    """The paper's GPS adaptive-filtering experiment (section 3.2, docs/algorithms.md §A9).

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
        transition=gps_transition(T),
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
            "initial R = diag(100, 100, 4, 0.01) (docs/algorithms.md §A9)."
        ),
        state_groups={"position (m)": (0, 1), "speed (m/s)": (2,), "heading (rad)": (3,)},
    )

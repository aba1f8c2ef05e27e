"""filterpy: a per-axis ``KalmanFilter`` with the IMU's exact discrete Q.

The state of one axis is ``[angle (or velocity), bias]``, ``F = [[1, -dt], [0, 1]]``; with
white rate noise of density N and a bias random walk of density K the exact discrete Q over
``dt = 1/f`` is ``[[N² dt + K² dt³/3, -K² dt²/2], [-K² dt²/2, K² dt]]`` (Van Loan's integral
of ``Φ(s) diag(N², K²) Φ(s)ᵀ``; filterpy's ``KalmanFilter.Q`` is that discrete matrix,
``filterpy/kalman/kalman_filter.py``, ``predict``: ``P = F P Fᵀ + Q``).
"""

from __future__ import annotations

import math

from noisevar.noise_model.exports.base import Consumer, ExportFile, density, discrete
from noisevar.noise_model.exports.model import ImuModel


def write(model: ImuModel) -> ExportFile:
    """A Python module defining ``gyro_axis()`` and ``accel_axis()`` (filterpy filters)."""
    dt = 1.0 / model.rate
    values = (
        density(model, "gyroscope", "N", "N_GYRO"),
        density(model, "gyroscope", "K", "K_GYRO"),
        density(model, "accelerometer", "N", "N_ACCEL"),
        density(model, "accelerometer", "K", "K_ACCEL"),
    )
    lines = ['"""IMU noise for filterpy, written by noisevar."""', ""]
    lines += [f"# {h}" for h in model.header("filterpy")]
    lines += [
        "import numpy as np",
        "from filterpy.kalman import KalmanFilter",
        "",
        f"DT = {dt!r}  # s, {discrete(model.rate)}",
    ]
    lines += [f"{v.name} = {v.value!r}  # {v.comment()}" for v in values]
    lines += [
        "",
        "",
        "def axis_filter(n, k, dt=DT):",
        '    """One axis: state [angle or velocity, bias]; the exact discrete Q."""',
        "    kf = KalmanFilter(dim_x=2, dim_z=1)",
        "    kf.F = np.array([[1.0, -dt], [0.0, 1.0]])",
        "    kf.Q = np.array([[n * n * dt + k * k * dt**3 / 3, -k * k * dt**2 / 2],",
        "                     [-k * k * dt**2 / 2, k * k * dt]])",
        "    return kf",
        "",
        "",
        "def gyro_axis():",
        "    return axis_filter(N_GYRO, K_GYRO)",
        "",
        "",
        "def accel_axis():",
        "    return axis_filter(N_ACCEL, K_ACCEL)",
        "",
    ]
    return ExportFile("filterpy", "imu_filterpy.py", "\n".join(lines), values)


def exact_q(n: float, k: float, dt: float) -> tuple[float, float, float]:
    """``(Q11, Q12, Q22)`` of the exact discrete Q (for checking the written module)."""
    return n * n * dt + k * k * dt**3 / 3, -k * k * dt**2 / 2, k * k * dt


def parse(text: str) -> dict[str, float]:
    """The module's constants (its assignments read by ``ast``, nothing executed)."""
    import ast

    out = {}
    for node in ast.parse(text).body:
        if isinstance(node, ast.Assign) and isinstance(node.value, ast.Constant):
            out[node.targets[0].id] = float(node.value.value)  # type: ignore[attr-defined]
    if not math.isfinite(out.get("DT", math.nan)):
        raise ValueError("no DT in the filterpy module")
    return out


CONSUMER = Consumer("filterpy", "filterpy KalmanFilter (Python)", "imu_filterpy.py", write, parse)

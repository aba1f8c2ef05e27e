"""ArduPilot EKF3 parameters as a ``.param`` file: discrete stds at the EKF3 rate.

Meaning, from ArduPilot's code (ArduPilot/ardupilot at 363e7e9): ``libraries/AP_NavEKF3/
AP_NavEKF3_core.cpp``, ``NavEKF3_core::CovariancePrediction``: ``daxVar = dayVar = dazVar =
sq(dt*_gyrNoise)`` and ``dvxVar = ... = sq(dt*_accNoise)`` per prediction step, and the
delta-angle/velocity bias states (bias · dt, rad and m/s) get ``dAngBiasVar =
sq(sq(dt) * _gyroBiasProcessNoise)`` per step: a rate-bias change of
``dt · EK3_GBIAS_P_NSE`` per step.
``AP_NavEKF3_core.h``: ``#define EKF_TARGET_DT 0.012f`` (12 ms, 83.3 Hz), the IMU being
down-sampled to it. So ``EK3_GYRO_P_NSE`` is ``N √f_ekf`` (rad/s), ``EK3_GBIAS_P_NSE``
``K √f_ekf`` (rad/s²). GNSS: ``AP_NavEKF3.cpp`` ``@Param: POSNE_M_NSE`` "GPS horizontal
position measurement noise (m)" and ``VELNE_M_NSE`` (m/s): EKF3 has no ``EK3_GPS_P_NSE``;
the GNSS stds go there.
"""

from __future__ import annotations

from noisevar.noise_model.exports.base import (
    Consumer,
    ExportFile,
    ascii_text,
    ekf_step_values,
)
from noisevar.noise_model.exports.model import ImuModel

#: EKF3's prediction step (``EKF_TARGET_DT``, s).
TARGET_DT = 0.012


def write(model: ImuModel, *, target_dt: float = TARGET_DT) -> ExportFile:
    """EKF3's IMU (and GNSS, when measured) noise parameters at its prediction rate."""
    f = 1.0 / target_dt
    at = f"EKF3 step {target_dt * 1e3:g} ms"
    values = ekf_step_values(
        model,
        f,
        at,
        ("EK3_GYRO_P_NSE", "EK3_ACC_P_NSE", "EK3_GBIAS_P_NSE", "EK3_ABIAS_P_NSE"),
        ("EK3_POSNE_M_NSE", "EK3_VELNE_M_NSE"),
    )
    lines = [f"# {h}" for h in model.header("ArduPilot EKF3")]
    lines += [
        "# AMBIGUOUS in the parameter docs (no rate given); EKF3's code adds (dt*value)^2",
        f"# per step of EKF_TARGET_DT = {target_dt:g} s: discrete stds at {f:g} Hz.",
    ]
    if "position" not in model.gnss:
        lines.append("# EK3_POSNE_M_NSE, EK3_VELNE_M_NSE: not written (no GNSS record given)")
    for v in values:
        lines.append(f"# {v.name}: {v.comment()}")
        lines.append(f"{v.name},{v.value:.12g}")
    return ExportFile(
        "ardupilot", "ardupilot_ekf3.param", ascii_text("\n".join(lines) + "\n"), tuple(values)
    )


def parse(text: str) -> dict[str, float]:
    """``NAME -> value`` of a ``.param`` file (``NAME,VALUE`` or ``NAME VALUE`` lines)."""
    out = {}
    for line in text.splitlines():
        body = line.split("#", 1)[0].strip()
        if body:
            name, value = body.replace(",", " ").split()
            out[name] = float(value)
    return out


CONSUMER = Consumer("ardupilot", "ArduPilot EKF3 .param", "ardupilot_ekf3.param", write, parse)

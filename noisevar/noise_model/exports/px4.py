"""PX4 EKF2 parameters as a QGroundControl ``.params`` file: discrete stds at the EKF rate.

Meaning, from PX4's code (PX4/PX4-Autopilot at 765f284): ``src/modules/ekf2/EKF/
covariance.cpp``, ``Ekf::predictCovariance``: ``gyro_var = sq(_params.gyro_noise)`` and
``accel_var = sq(accel_noise)`` go to ``sym::PredictCovariance(..., gyro_var, dt)``, which
adds ``gyro_var · dt²`` to the angle error per prediction step (the generator,
``EKF/python/ekf_derivation/derivation.py``, ``predict_covariance``: ``P_new = A P Aᵀ +
G var_u Gᵀ``; at 0754cab its caller passed ``d_ang_var = sq(dt * gyro_noise)``, the same
thing); the bias states get
``sq(dt * _params.gyro_bias_p_noise)`` per step. The step ``dt`` is EKF2's prediction
period ``EKF2_PREDICT_US`` (default 10000 µs: 100 Hz), the IMU being down-sampled (its
delta angles summed) to it; before that parameter, PX4-ECL's compiled-in
``FILTER_UPDATE_PERIOD_MS`` (:data:`COMPILED_US`, by the ULog's firmware release). So
``EKF2_GYR_NOISE`` is the std of the rate averaged over one
EKF step, ``N √f_ekf`` (rad/s), and ``EKF2_GYR_B_NOISE`` the bias change per step over the
step time, ``K √f_ekf`` (rad/s²). ``EKF2_GPS_P_NOISE`` and ``EKF2_GPS_V_NOISE`` are GNSS
measurement stds (m, m/s), from a GNSS record's R when one is given.

Ambiguity, said in the file: PX4's parameter reference calls them "noise for covariance
prediction" without a rate; its defaults (0.015 rad/s, 0.35 m/s²) budget vibration and
unmodelled errors, far above a still sensor's floor. Our value is the still floor at the
EKF's rate; the conservative set or a flight log's motion regimes raise it.
"""

from __future__ import annotations

from collections.abc import Mapping

from noisevar.noise_model.exports.base import (
    Consumer,
    ExportFile,
    ascii_text,
    ekf_step_values,
    range_warning,
)
from noisevar.noise_model.exports.model import ImuModel

#: EKF2's default prediction period (``EKF2_PREDICT_US``, µs).
PREDICT_US = 10000
#: The documented ranges (ekf2 parameter definitions' ``@min``/``@max``; None: no bound
#: read): a value outside is written as computed, with a warning line.
RANGES = {
    "EKF2_GYR_NOISE": (0.0001, None),
    "EKF2_ACC_NOISE": (0.01, 1.0),
    "EKF2_GYR_B_NOISE": (0.0, 0.01),
    "EKF2_ACC_B_NOISE": (0.0, 0.01),
}
#: EKF2's compiled-in prediction period (µs) by PX4 release (major, minor), before it was
#: the parameter ``EKF2_PREDICT_US``: PX4-ECL's ``FILTER_UPDATE_PERIOD_MS`` in
#: ``EKF/estimator_interface.h`` on its release branches, 8 on ``Release_v1.10`` and 10 on
#: ``Release_v1.11`` (changed by 8a9d961f, "EKF: Improve covariance prediction stability",
#: 2020-04-23, #795; still 10 at the library's last commit, b3fed06f, 2021-07-26).
COMPILED_US = {(1, 10): 8000, (1, 11): 10000}
#: The ULog information field of the firmware's release (``0xMMmmppTT``), which the ULog
#: reader keeps with the parameters (:func:`noisevar.io.logs.params.log_parameters`).
VERSION_FIELD = "ver_sw_release"
#: MAV_PARAM_TYPE_REAL32: the type column of a QGC parameter file.
_REAL32 = 9


def write(
    model: ImuModel, *, predict_us: int | None = None, params: Mapping[str, float] | None = None
) -> ExportFile:
    """EKF2's IMU (and GNSS, when measured) noise parameters at its prediction rate.

    ``predict_us`` sets the step outright; else the flight log's ``EKF2_PREDICT_US``
    (``params``) when it has one, else PX4's default :data:`PREDICT_US`.
    """
    logged = (params or {}).get("EKF2_PREDICT_US")
    release = px4_release((params or {}).get(VERSION_FIELD))
    if predict_us is not None:
        how = "given"
    elif logged:
        how, predict_us = "read from the flight log", int(logged)
    elif release in COMPILED_US:
        predict_us = COMPILED_US[release]
        how = (
            f"not a parameter of the flight's PX4 v{release[0]}.{release[1]} (its ULog "
            f"{VERSION_FIELD}): its EKF's compiled-in FILTER_UPDATE_PERIOD_MS (PX4-ECL "
            f"Release_v{release[0]}.{release[1]}, EKF/estimator_interface.h)"
        )
    else:
        how, predict_us = "assumed", PREDICT_US
    f = 1e6 / predict_us
    at = f"EKF step {predict_us} µs"
    values = ekf_step_values(
        model,
        f,
        at,
        ("EKF2_GYR_NOISE", "EKF2_ACC_NOISE", "EKF2_GYR_B_NOISE", "EKF2_ACC_B_NOISE"),
        ("EKF2_GPS_P_NOISE", "EKF2_GPS_V_NOISE"),
    )
    lines = [f"# {h}" for h in model.header("PX4 EKF2")]
    lines += [
        "# AMBIGUOUS in PX4's docs (no rate given); its code (covariance.cpp) adds",
        "# (dt*value)^2 per EKF step: these are discrete stds at the EKF rate",
        f"# 1/EKF2_PREDICT_US = {f:g} Hz (not the IMU's {model.rate:g} Hz).",
    ]
    if "position" not in model.gnss:
        lines.append("# EKF2_GPS_P_NOISE, EKF2_GPS_V_NOISE: not written (no GNSS record given)")
    lines.append(f"# EKF2_PREDICT_US {how}: {predict_us}")
    lines.append("# Vehicle-Id\tComponent-Id\tName\tValue\tType")
    for v in values:
        lines.append(f"# {v.name}: {v.comment()}")
        warning = range_warning(v.name, v.value, RANGES.get(v.name, (None, None)))
        if warning:
            lines.append(f"# {warning}")
        lines.append(v.line(f"1\t1\t{v.name}\t{v.value:.12g}\t{_REAL32}"))
    return ExportFile("px4", "px4_ekf2.params", ascii_text("\n".join(lines) + "\n"), tuple(values))


def px4_release(value: float | None) -> tuple[int, int] | None:
    """``(major, minor)`` of a ULog's ``ver_sw_release`` (``0xMMmmppTT``), None without one."""
    if value is None or not value > 0:
        return None
    v = int(value)
    return (v >> 24) & 0xFF, (v >> 16) & 0xFF


def parse(text: str) -> dict[str, float]:
    """``Name -> value`` of a QGC ``.params`` file (tab-separated, ``#`` comments)."""
    out = {}
    for line in text.splitlines():
        if line.strip() and not line.startswith("#"):
            _vid, _cid, name, value, _type = line.split("\t")
            out[name] = float(value)
    return out


#: The flight-log parameters the writer reads (:data:`Consumer.log_params`).
LOG_PARAMS = ("EKF2_PREDICT_US", VERSION_FIELD)

CONSUMER = Consumer(
    "px4", "PX4 EKF2 .params", "px4_ekf2.params", write, parse, LOG_PARAMS, merged=True
)

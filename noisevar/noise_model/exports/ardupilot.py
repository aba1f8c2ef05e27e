"""ArduPilot EKF3 (or EKF2) parameters as a ``.param`` file: discrete stds at the EKF's step.

Meaning, from ArduPilot's code (ArduPilot/ardupilot at 363e7e9): ``libraries/AP_NavEKF3/
AP_NavEKF3_core.cpp``, ``NavEKF3_core::CovariancePrediction``: ``daxVar = dayVar = dazVar =
sq(dt*_gyrNoise)`` and ``dvxVar = ... = sq(dt*_accNoise)`` per prediction step, and the
delta-angle/velocity bias states (bias · dt, rad and m/s) get ``dAngBiasVar =
sq(sq(dt) * _gyroBiasProcessNoise)`` per step: a rate-bias change of
``dt · EK3_GBIAS_P_NSE`` per step. EKF2's ``NavEKF2_core::CovariancePrediction``
(``AP_NavEKF2_core.cpp``) adds the same ``sq(dt*_gyrNoise)``. So ``EK3_GYRO_P_NSE`` is
``N √f_ekf`` (rad/s), ``EK3_GBIAS_P_NSE`` ``K √f_ekf`` (rad/s²).

The step: ``NavEKF3_core::setup_core`` sets ``dtEkfAvg = MAX(1/loop_rate, EKF_TARGET_DT)``
(``#define EKF_TARGET_DT 0.012f`` in ``AP_NavEKF3_core.h``; EKF2's is 0.01 s), the IMU
being down-sampled to it: a vehicle whose main loop (``SCHED_LOOP_RATE``) is slower than
the target, Plane's 50 Hz, predicts once per loop. From a flight log the writer reads
``SCHED_LOOP_RATE`` and ``AHRS_EKF_TYPE`` (2: the ``EK2_`` names at EKF2's step);
without them it assumes EKF3 and a loop at least as fast as its target, and says so.
GNSS: ``AP_NavEKF3.cpp`` ``@Param: POSNE_M_NSE`` "GPS horizontal position measurement
noise (m)" and ``VELNE_M_NSE`` (m/s): EKF3 has no ``EK3_GPS_P_NSE``; the GNSS stds go there.
"""

from __future__ import annotations

from collections.abc import Mapping

from noisevar.errors import NoisevarError
from noisevar.noise_model.exports.base import (
    Consumer,
    ExportFile,
    ascii_text,
    ekf_step_values,
    range_warning,
)
from noisevar.noise_model.exports.model import ImuModel

#: Each EKF's prediction target (``EKF_TARGET_DT`` of ``AP_NavEKF2_core.h`` and
#: ``AP_NavEKF3_core.h``, s).
TARGET_DT = {3: 0.012, 2: 0.01}
#: The EKF written when the flight's ``AHRS_EKF_TYPE`` is not known.
DEFAULT_EKF = 3
#: The flight-log parameters the writer reads (:data:`Consumer.log_params`).
LOG_PARAMS = ("SCHED_LOOP_RATE", "AHRS_EKF_TYPE")
#: The file's name, after the EKF whose names it holds (``ardupilot_ekf2.param`` holds
#: ``EK2_*``): the CLI, Python and the dashboard's download all take the written file's.
FILENAME = "ardupilot_ekf{ekf}.param"
#: The documented ranges (``@Range`` of ``AP_NavEKF2.cpp``/``AP_NavEKF3.cpp``), by name
#: without the ``EKn_`` prefix; EKF2's accelerometer bias range is narrower.
RANGES = {
    "GYRO_P_NSE": (0.0001, 0.1),
    "ACC_P_NSE": (0.01, 1.0),
    "GBIAS_P_NSE": (0.00001, 0.001),
    "ABIAS_P_NSE": (0.00001, 0.02),
}
_EKF2_ABIAS = (0.00001, 0.005)


def ekf_step(ekf: int, loop_rate: float | None) -> float:
    """The EKF's prediction step (s): ``max(1/loop_rate, EKF_TARGET_DT)``, the target alone
    when the loop rate is not known."""
    if ekf not in TARGET_DT:
        raise NoisevarError(f"ArduPilot EKF {ekf!r}: the file is written for EKF2 or EKF3")
    target = TARGET_DT[ekf]
    return target if not loop_rate or loop_rate <= 0 else max(1.0 / loop_rate, target)


def _flight(params: Mapping[str, float] | None) -> tuple[int, float | None, list[str]]:
    """The EKF and loop rate a flight log gives (``AHRS_EKF_TYPE``, ``SCHED_LOOP_RATE``),
    and what the file says about where each came from."""
    params = params or {}
    said = []
    ekf = int(params.get("AHRS_EKF_TYPE", DEFAULT_EKF))
    if "AHRS_EKF_TYPE" in params:
        said.append(f"AHRS_EKF_TYPE = {ekf:d} read from the flight log")
    if ekf not in TARGET_DT:  # 0 (DCM), 10 (SITL), 11 (external): no EKF noise parameters
        said.append(f"AHRS_EKF_TYPE {ekf:d} is not EKF2 or EKF3: EKF3's names are written")
        ekf = DEFAULT_EKF
    loop = params.get("SCHED_LOOP_RATE")
    if loop:
        said.append(f"SCHED_LOOP_RATE = {loop:g} Hz read from the flight log")
    else:
        said.append(
            "SCHED_LOOP_RATE not known: assumed at least 1/EKF_TARGET_DT (a slower loop, e.g. "
            "Plane's 50 Hz, is the EKF's step: give the flight log)"
        )
    return ekf, loop, said


def write(
    model: ImuModel,
    *,
    target_dt: float | None = None,
    params: Mapping[str, float] | None = None,
) -> ExportFile:
    """The EKF's IMU (and GNSS, when measured) noise parameters at its prediction rate.

    ``target_dt`` sets the step (s) outright; else it is :func:`ekf_step` of the flight
    log's ``params`` (``AHRS_EKF_TYPE``, ``SCHED_LOOP_RATE``), EKF3's target without them.
    """
    ekf, loop, said = _flight(params)
    dt = target_dt if target_dt is not None else ekf_step(ekf, loop)
    f = 1.0 / dt
    p = f"EK{ekf}_"
    at = f"EKF{ekf} step {dt * 1e3:g} ms"
    values = ekf_step_values(
        model,
        f,
        at,
        tuple(p + n for n in ("GYRO_P_NSE", "ACC_P_NSE", "GBIAS_P_NSE", "ABIAS_P_NSE")),
        (p + "POSNE_M_NSE", p + "VELNE_M_NSE"),
    )
    lines = [f"# {h}" for h in model.header(f"ArduPilot EKF{ekf}")]
    lines += [
        f"# AMBIGUOUS in the parameter docs (no rate given); EKF{ekf}'s code adds (dt*value)^2",
        f"# per prediction step dt = max(1/SCHED_LOOP_RATE, EKF_TARGET_DT = {TARGET_DT[ekf]:g} s)"
        f" = {dt:g} s: discrete stds at {f:g} Hz.",
        *(f"# {s}" for s in said),
    ]
    if "position" not in model.gnss:
        lines.append(f"# {p}POSNE_M_NSE, {p}VELNE_M_NSE: not written (no GNSS record given)")
    ranges = RANGES | ({"ABIAS_P_NSE": _EKF2_ABIAS} if ekf == 2 else {})
    for v in values:
        lines.append(f"# {v.name}: {v.comment()}")
        warning = range_warning(v.name, v.value, ranges.get(v.name[len(p) :], (None, None)))
        if warning:
            lines.append(f"# {warning}")
        lines.append(v.line(f"{v.name},{v.value:.12g}"))
    return ExportFile(
        "ardupilot", FILENAME.format(ekf=ekf), ascii_text("\n".join(lines) + "\n"), tuple(values)
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


CONSUMER = Consumer(
    "ardupilot",
    "ArduPilot EKF3 (or EKF2) .param",
    FILENAME.format(ekf=DEFAULT_EKF),
    write,
    parse,
    LOG_PARAMS,
    merged=True,
)

"""OpenVINS ``kalibr_imu_chain.yaml``: continuous-time densities.

Meaning, from OpenVINS (rpng/open_vins at 6948812): ``ov_msckf/src/core/
VioManagerOptions.h:159-162`` reads ``imu0/gyroscope_noise_density`` into ``sigma_w`` (and
the random walks into ``sigma_wb``, ``sigma_ab``); ``ov_msckf/src/state/Propagator.cpp:
225-228`` discretises them as ``Qc = sigma_w² / dt`` with ``G`` carrying ``dt`` ("we need to
convert our continuous time noises to discrete", Trawny eq. 129-130). So the values are
densities, written as fitted. The file layout follows ``config/euroc_mav/
kalibr_imu_chain.yaml`` (identity intrinsics, model "kalibr").
"""

from __future__ import annotations

from noisevar.noise_model.exports.base import Consumer, ExportFile, ascii_text, density, number
from noisevar.noise_model.exports.model import ImuModel

_EYE = ["    - [1.0, 0.0, 0.0]", "    - [0.0, 1.0, 0.0]", "    - [0.0, 0.0, 1.0]"]
_ZERO = ["    - [0.0, 0.0, 0.0]"] * 3


def write(model: ImuModel, *, rostopic: str = "/imu0") -> ExportFile:
    """OpenVINS's IMU chain file of ``model`` (densities as fitted)."""
    values = (
        density(model, "accelerometer", "N", "accelerometer_noise_density"),
        density(model, "accelerometer", "K", "accelerometer_random_walk"),
        density(model, "gyroscope", "N", "gyroscope_noise_density"),
        density(model, "gyroscope", "K", "gyroscope_random_walk"),
    )
    lines = ["%YAML:1.0", *(f"# {h}" for h in model.header("OpenVINS")), "", "imu0:"]
    lines += [
        "  T_i_b:",
        "    - [1.0, 0.0, 0.0, 0.0]",
        "    - [0.0, 1.0, 0.0, 0.0]",
        "    - [0.0, 0.0, 1.0, 0.0]",
        "    - [0.0, 0.0, 0.0, 1.0]",
    ]
    lines += [f"  {v.name}: {number(v.value)}  # {v.comment()}" for v in values]
    lines += [
        f"  rostopic: {rostopic}",
        "  time_offset: 0.0",
        f"  update_rate: {model.rate:.1f}",
        '  model: "kalibr"',
    ]
    for key, rows in (
        ("Tw", _EYE),
        ("R_IMUtoGYRO", _EYE),
        ("Ta", _EYE),
        ("R_IMUtoACC", _EYE),
        ("Tg", _ZERO),
    ):
        lines += [f"  {key}:", *rows]
    return ExportFile(
        "openvins", "kalibr_imu_chain.yaml", ascii_text("\n".join(lines) + "\n"), values
    )


def parse(text: str) -> dict[str, float]:
    """The numbers of ``imu0`` (YAML; OpenCV's ``%YAML:1.0`` directive line dropped)."""
    import yaml

    body = "\n".join(ln for ln in text.splitlines() if not ln.startswith("%YAML"))
    imu = yaml.safe_load(body)["imu0"]
    return {k: float(v) for k, v in imu.items() if isinstance(v, int | float)}


CONSUMER = Consumer(
    "openvins", "OpenVINS kalibr_imu_chain.yaml", "kalibr_imu_chain.yaml", write, parse
)

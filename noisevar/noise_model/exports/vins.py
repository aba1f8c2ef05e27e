"""VINS-Mono / VINS-Fusion config entries ``acc_n``, ``gyr_n``, ``acc_w``, ``gyr_w``.

Meaning, from VINS-Fusion's code (HKUST-Aerial-Robotics/VINS-Fusion at be55a93):
``vins_estimator/src/estimator/parameters.cpp:98-101`` reads them;
``vins_estimator/src/factor/integration_base.h:30-36`` puts ``ACC_N²``, ``GYR_N²`` (one per
IMU reading of the midpoint step) and ``ACC_W²``, ``GYR_W²`` on the diagonal of ``noise``,
and ``integration_base.h:118-134`` propagates ``V noise Vᵀ`` with ``V`` holding ``0.5 dt``
for the reading noises and ``dt`` for the bias noises. So ``gyr_n`` is the std of the noise
of ONE reading at the IMU rate (``N √f``), and a bias step is ``gyr_w · dt`` (so
``gyr_w = K √f``): both discrete, at the IMU's sample rate.

Ambiguity, said in the file: the configs call them "noise standard deviation" and are
commonly filled with Kalibr's densities, a factor ``√f`` smaller (14x at 200 Hz: the
"multiply the Allan values by 10-20" advice of VINS-Mono #102/#125 is this factor). Its
midpoint step also takes the two readings' noises as independent of the neighbouring
steps', which makes its propagated angle std ``√2`` smaller than the continuous model's.
"""

from __future__ import annotations

from noisevar.noise_model.exports.base import (
    Consumer,
    ExportFile,
    ascii_text,
    number,
    walk_sigma,
    white_sigma,
)
from noisevar.noise_model.exports.model import ImuModel


def write(model: ImuModel) -> ExportFile:
    """The four noise entries of a VINS config, discrete at the IMU rate."""
    f = model.rate
    values = (
        white_sigma(model, "accelerometer", "acc_n", f, "std of one reading (VINS's code)"),
        white_sigma(model, "gyroscope", "gyr_n", f, "std of one reading (VINS's code)"),
        walk_sigma(model, "accelerometer", "acc_w", f, "bias step / dt (VINS's code)"),
        walk_sigma(model, "gyroscope", "gyr_w", f, "bias step / dt (VINS's code)"),
    )
    lines = ["%YAML:1.0", *(f"# {h}" for h in model.header("VINS-Mono/Fusion"))]
    lines += [
        "# AMBIGUOUS in VINS: its configs say 'noise standard deviation' and are often filled",
        "# with Kalibr's continuous densities (sqrt(f) smaller). These follow its code",
        "# (integration_base.h): discrete stds at the IMU rate. The continuous densities are",
        f"#   acc N {model.accel.N:.6g}, gyr N {model.gyro.N:.6g}, acc K {model.accel.K:.6g},"
        f" gyr K {model.gyro.K:.6g}",
        "# Merge these lines into your VINS config.",
    ]
    lines += [v.line(f"{v.name}: {number(v.value)}  # {v.comment()}") for v in values]
    return ExportFile("vins", "vins_imu.yaml", ascii_text("\n".join(lines) + "\n"), values)


def parse(text: str) -> dict[str, float]:
    """The numbers of the entries (YAML; the OpenCV directive line dropped)."""
    import yaml

    body = "\n".join(ln for ln in text.splitlines() if not ln.startswith("%YAML"))
    return {k: float(v) for k, v in yaml.safe_load(body).items()}


CONSUMER = Consumer(
    "vins", "VINS-Mono/Fusion config entries", "vins_imu.yaml", write, parse, merged=True
)

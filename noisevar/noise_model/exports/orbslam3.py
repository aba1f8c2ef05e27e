"""ORB-SLAM3 settings ``IMU.NoiseGyro``, ``IMU.NoiseAcc``, ``IMU.GyroWalk``, ``IMU.AccWalk``,
``IMU.Frequency``: continuous-time densities.

Meaning, from ORB-SLAM3's code (UZ-SLAMLab/ORB_SLAM3): ``src/Tracking.cc``,
``Tracking::ParseIMUParamFile``: ``const float sf = sqrt(mImuFreq); mpImuCalib = new
IMU::Calib(Tbc,Ng*sf,Na*sf,Ngw/sf,Naw/sf);`` and it prints them as "rad/s/sqrt(Hz)",
"rad/s^2/sqrt(Hz)"; ``src/ImuTypes.cc``, ``Calib::Set``: ``Cov.diagonal() << ng2 ...``,
``CovWalk.diagonal() << ngw2 ...``. So the file takes densities and ORB-SLAM3 makes the
discrete stds itself with ``IMU.Frequency``, the IMU's sample rate.
"""

from __future__ import annotations

from noisevar.noise_model.exports.base import (
    Consumer,
    ExportFile,
    Value,
    ascii_text,
    density,
    number,
)
from noisevar.noise_model.exports.model import ImuModel


def write(model: ImuModel) -> ExportFile:
    """The IMU block of an ORB-SLAM3 settings file (densities as fitted)."""
    values = (
        density(model, "gyroscope", "N", "IMU.NoiseGyro"),
        density(model, "accelerometer", "N", "IMU.NoiseAcc"),
        density(model, "gyroscope", "K", "IMU.GyroWalk"),
        density(model, "accelerometer", "K", "IMU.AccWalk"),
        Value(
            "IMU.Frequency",
            float(round(model.rate)),
            "Hz",
            "sample rate",
            "the IMU's sample rate, an integer (ORB-SLAM3 reads it with isInt())",
        ),
    )
    lines = ["%YAML:1.0", *(f"# {h}" for h in model.header("ORB-SLAM3"))]
    lines.append("# Merge these lines into your ORB-SLAM3 settings file.")
    lines += [v.line(f"{v.name}: {number(v.value)}  # {v.comment()}") for v in values[:4]]
    lines.append(f"IMU.Frequency: {int(values[4].value)}  # {values[4].comment()}")
    return ExportFile("orbslam3", "orbslam3_imu.yaml", ascii_text("\n".join(lines) + "\n"), values)


def parse(text: str) -> dict[str, float]:
    """The numbers of the IMU entries (YAML; the OpenCV directive line dropped)."""
    import yaml

    body = "\n".join(ln for ln in text.splitlines() if not ln.startswith("%YAML"))
    return {k: float(v) for k, v in yaml.safe_load(body).items()}


CONSUMER = Consumer(
    "orbslam3", "ORB-SLAM3 settings entries", "orbslam3_imu.yaml", write, parse, merged=True
)

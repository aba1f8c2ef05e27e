"""Kalibr ``imu.yaml``: continuous-time densities (writer: :mod:`noisevar.noise_model.kalibr`).

Meaning, from Kalibr's own reader: ``aslam_offline_calibration/kalibr/python/kalibr_common/
ConfigReader.py``, ``ImuParameters.getAccelerometerStatistics`` (and the gyroscope's twin):
``accelUncertaintyDiscrete = accelerometer_noise_density / sqrt(1.0 / update_rate)``; the
random walks are used as densities. So N and K are written as fitted; ``update_rate`` is the
IMU's sample rate.
"""

from __future__ import annotations

from noisevar.noise_model.exports.base import Consumer, ExportFile, density
from noisevar.noise_model.exports.model import ImuModel
from noisevar.noise_model.kalibr import KalibrImu, parse_kalibr


def write(model: ImuModel, *, rostopic: str = "/imu0") -> ExportFile:
    """Kalibr's ``imu.yaml`` of ``model`` (values as fitted: Kalibr takes densities)."""
    values = (
        density(model, "accelerometer", "N", "accelerometer_noise_density"),
        density(model, "accelerometer", "K", "accelerometer_random_walk"),
        density(model, "gyroscope", "N", "gyroscope_noise_density"),
        density(model, "gyroscope", "K", "gyroscope_random_walk"),
    )
    imu = KalibrImu(
        *(v.value for v in values),
        update_rate=model.rate,
        rostopic=rostopic,
        notes=(*model.header("Kalibr"), *(f"{v.name}: {v.comment()}" for v in values)),
        regimes=model.regimes,
    )
    return ExportFile("kalibr", "imu.yaml", imu.to_yaml(), values)


def parse(text: str) -> dict[str, float]:
    """The numbers of a Kalibr ``imu.yaml`` (through the YAML reader)."""
    d = parse_kalibr(text).to_dict()
    return {k: float(v) for k, v in d.items() if k != "rostopic"}


CONSUMER = Consumer("kalibr", "Kalibr imu.yaml", "imu.yaml", write, parse)

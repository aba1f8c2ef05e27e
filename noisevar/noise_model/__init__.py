"""Noise models of a record for a Kalman filter: Allan deviation, the inertial (IEEE-952)
noise terms, composite IMU models (GMWM), coloured measurement noise, Q with R
(docs/algorithms.md §E4-§E6, §E10), and the temperature model (§E9).
"""

from noisevar.noise_model.allan import AllanResult, allan
from noisevar.noise_model.coloured import ColouredNoiseFit, fit_coloured_noise
from noisevar.noise_model.gmwm import (
    ImuModel,
    InformationBound,
    fisher_bound,
    fit_imu_model,
    fit_imu_records,
)
from noisevar.noise_model.inertial import InertialNoise, NoiseTerm, inertial_noise
from noisevar.noise_model.kalman_fit import KalmanTuning, evaluate_kalman, fit_kalman
from noisevar.noise_model.kalman_run import TunedRun, fit_models, run_tuned
from noisevar.noise_model.temperature import (
    TemperatureExport,
    TemperatureModel,
    matlab_temperature_params,
    temperature_model,
)

__all__ = [
    "AllanResult",
    "ColouredNoiseFit",
    "ImuModel",
    "InertialNoise",
    "InformationBound",
    "KalmanTuning",
    "NoiseTerm",
    "TemperatureExport",
    "TemperatureModel",
    "TunedRun",
    "allan",
    "evaluate_kalman",
    "fisher_bound",
    "fit_coloured_noise",
    "fit_imu_model",
    "fit_imu_records",
    "fit_kalman",
    "inertial_noise",
    "matlab_temperature_params",
    "fit_models",
    "run_tuned",
    "temperature_model",
]

"""Noise models for a Kalman filter: coloured measurement noise and Q with R (docs §E5, §E6)."""

from noisevar.noise_model.coloured import ColouredNoiseFit, fit_coloured_noise
from noisevar.noise_model.kalman_fit import (
    KalmanTuning,
    TunedRun,
    evaluate_kalman,
    fit_kalman,
    run_tuned,
)

__all__ = [
    "ColouredNoiseFit",
    "KalmanTuning",
    "TunedRun",
    "evaluate_kalman",
    "fit_coloured_noise",
    "fit_kalman",
    "run_tuned",
]

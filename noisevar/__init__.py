"""noisevar: how noisy is a measured signal, and what that means for a Kalman filter.

Quick start::

    import noisevar
    est = noisevar.estimate(z)                 # default method "auto"
    est.variance, est.ci95, est.n_used
    noisevar.estimate(z, method="somd", h_smooth=1.5e-5, window=40)
    noisevar.estimate(Z, axis=0).variance     # one estimate per column of Z
    noisevar.methods()
"""

from noisevar.batch import batch
from noisevar.errors import NoisevarError, NoWindowKept
from noisevar.estimators import describe_methods, estimate, estimate_redundant, methods
from noisevar.estimators.results import RedundantEstimate, VarianceEstimate, VarianceEstimates
from noisevar.noise_model import (
    AllanResult,
    InertialNoise,
    KalmanTuning,
    allan,
    fit_coloured_noise,
    fit_kalman,
    inertial_noise,
)
from noisevar.signals import GeneratedSignal, generate, signal_names

__version__ = "0.1.0"
__all__ = [
    "AllanResult",
    "InertialNoise",
    "GeneratedSignal",
    "KalmanTuning",
    "NoWindowKept",
    "NoisevarError",
    "RedundantEstimate",
    "VarianceEstimate",
    "VarianceEstimates",
    "__version__",
    "allan",
    "batch",
    "describe_methods",
    "estimate",
    "estimate_redundant",
    "fit_coloured_noise",
    "fit_kalman",
    "generate",
    "inertial_noise",
    "methods",
    "signal_names",
]

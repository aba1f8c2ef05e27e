"""noisevar: how noisy is a measured signal, and what that means for a Kalman filter.

Quick start::

    import noisevar
    est = noisevar.estimate(z)                 # default method "auto"
    est.variance, est.ci95, est.n_used
    noisevar.estimate(z, method="somd", h_smooth=1.5e-5, window=40)
    noisevar.estimate(Z, axis=0).variance     # one estimate per column of Z
    noisevar.methods()

Notes
-----
``import noisevar`` imports no third-party library: every public name loads its module
on first use (PEP 562), so that a command can refuse a bad file before NumPy and the
estimators are imported, and :func:`estimate` loads only the estimate path (not
:func:`batch`, the noise models, the test signals, pandas or ``scipy.stats``).
"""

from __future__ import annotations

import importlib
import sys
from types import ModuleType
from typing import TYPE_CHECKING, Any

from noisevar._lazy import lazy_names
from noisevar.errors import EmptyCells, NoisevarError, NoWindowKept, StackedSeries

if TYPE_CHECKING:
    from noisevar.batch import batch
    from noisevar.estimators import describe_methods, estimate, estimate_redundant, methods
    from noisevar.estimators.results import (
        RedundantEstimate,
        VarianceEstimate,
        VarianceEstimates,
    )
    from noisevar.noise_model import (
        AllanResult,
        ImuModel,
        InertialNoise,
        KalmanTuning,
        allan,
        fit_coloured_noise,
        fit_imu_model,
        fit_imu_records,
        fit_kalman,
        inertial_noise,
    )
    from noisevar.signals import GeneratedSignal, generate, signal_names

__version__ = "0.1.0"
__all__ = [
    "AllanResult",
    "ImuModel",
    "InertialNoise",
    "GeneratedSignal",
    "KalmanTuning",
    "NoWindowKept",
    "EmptyCells",
    "StackedSeries",
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
    "fit_imu_model",
    "fit_imu_records",
    "fit_kalman",
    "generate",
    "inertial_noise",
    "methods",
    "signal_names",
]

#: Public names loaded on first use, and the module each comes from.
_LAZY = {
    "describe_methods": "noisevar.estimators",
    "estimate": "noisevar.estimators",
    "estimate_redundant": "noisevar.estimators",
    "methods": "noisevar.estimators",
    "RedundantEstimate": "noisevar.estimators.results",
    "VarianceEstimate": "noisevar.estimators.results",
    "VarianceEstimates": "noisevar.estimators.results",
    "AllanResult": "noisevar.noise_model",
    "ImuModel": "noisevar.noise_model",
    "InertialNoise": "noisevar.noise_model",
    "KalmanTuning": "noisevar.noise_model",
    "allan": "noisevar.noise_model",
    "fit_coloured_noise": "noisevar.noise_model",
    "fit_imu_model": "noisevar.noise_model",
    "fit_imu_records": "noisevar.noise_model",
    "fit_kalman": "noisevar.noise_model",
    "inertial_noise": "noisevar.noise_model",
    "GeneratedSignal": "noisevar.signals",
    "generate": "noisevar.signals",
    "signal_names": "noisevar.signals",
}


__getattr__, __dir__ = lazy_names(__name__, _LAZY, __all__)


class _Package(ModuleType):
    """This package's module type: ``noisevar.batch`` is always the function.

    Importing the subpackage :mod:`noisevar.batch` (say, for ``read_table``) sets the
    package attribute ``batch`` to the subpackage; this property keeps the public
    name :func:`noisevar.batch.batch`, as when it was imported eagerly.
    """

    @property
    def batch(self) -> Any:
        return importlib.import_module("noisevar.batch").batch

    @batch.setter
    def batch(self, value: Any) -> None:  # the import system sets the subpackage here
        self.__dict__["batch"] = value


sys.modules[__name__].__class__ = _Package

"""Adaptive Kalman filtering: one filter core, pluggable R-adaptation strategies, scenarios.

Core (:mod:`noisevar.kalman.core`): :class:`StateSpaceModel` (linear or EKF),
:class:`KalmanFilter` (step by step, batched over Monte Carlo runs),
:func:`run_filter` (whole record -> :class:`FilterResult`),
:class:`HuberUpdate` (robust update, spec B3), :class:`DivergenceCheck`.

Strategies (:mod:`noisevar.kalman.strategies`): fixed, oracle, somd-online,
rae, iae, rae-q (spec B1), sage-husa (B4), vb (B2); :func:`make_strategy`.

Scenarios (:mod:`noisevar.systems.scenarios`): gps-circle (spec A9),
noise-step, noise-ramp, outliers.
"""

from noisevar.kalman.core import (
    DivergenceCheck,
    HuberUpdate,
    KalmanFilter,
    StateSpaceModel,
    check_covariance,
    nis_band,
    run_filter,
)
from noisevar.kalman.result import FilterResult, wrap_angle
from noisevar.kalman.strategies import (
    STRATEGIES,
    FixedR,
    InnovationR,
    OracleR,
    ResidualQR,
    ResidualR,
    RStrategy,
    SageHusaR,
    SomdOnlineR,
    VariationalBayesR,
    make_strategy,
)

__all__ = [
    "STRATEGIES",
    "DivergenceCheck",
    "FilterResult",
    "FixedR",
    "HuberUpdate",
    "InnovationR",
    "KalmanFilter",
    "OracleR",
    "RStrategy",
    "ResidualQR",
    "ResidualR",
    "SageHusaR",
    "SomdOnlineR",
    "StateSpaceModel",
    "VariationalBayesR",
    "check_covariance",
    "make_strategy",
    "nis_band",
    "run_filter",
    "wrap_angle",
]

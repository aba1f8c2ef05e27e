"""Adaptive Kalman filtering: one filter, pluggable R-adaptation strategies.

:class:`StateSpaceModel` (linear or EKF), :class:`KalmanFilter` (step by step,
batched over Monte Carlo runs), :func:`run_filter` (a whole record ->
:class:`FilterResult`), :class:`HuberUpdate`, :class:`DivergenceCheck`; the
strategies of :mod:`noisevar.kalman.strategies` and :func:`make_strategy`.
"""

from noisevar.kalman.divergence import DivergenceCheck, nis_band, quadratic_form_inverse
from noisevar.kalman.filter import KalmanFilter
from noisevar.kalman.model import HuberUpdate, StateSpaceModel, check_covariance
from noisevar.kalman.result import FilterResult, wrap_angle
from noisevar.kalman.run import run_filter
from noisevar.kalman.strategies import (
    ALIASES,
    STRATEGIES,
    FixedR,
    InnovationR,
    MovingMean,
    OracleR,
    ResidualQR,
    ResidualR,
    RStrategy,
    SageHusaR,
    SomdOnlineR,
    StrategySpec,
    VariationalBayesR,
    make_strategy,
    strategy_spec,
)

__all__ = [
    "ALIASES",
    "STRATEGIES",
    "DivergenceCheck",
    "FilterResult",
    "FixedR",
    "HuberUpdate",
    "InnovationR",
    "KalmanFilter",
    "MovingMean",
    "OracleR",
    "RStrategy",
    "ResidualQR",
    "ResidualR",
    "SageHusaR",
    "SomdOnlineR",
    "StateSpaceModel",
    "StrategySpec",
    "VariationalBayesR",
    "check_covariance",
    "make_strategy",
    "nis_band",
    "quadratic_form_inverse",
    "run_filter",
    "strategy_spec",
    "wrap_angle",
]

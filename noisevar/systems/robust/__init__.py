"""Robust M-estimation EKF with a bearing-bias state: DME/VOR navigation (docs/algorithms.md §B3).

A ground station measures the slant range (DME) and the magnetic bearing (VOR)
of an aircraft; an inertial velocity makes the station's magnetic variation
``α`` observable as an augmented constant state. Near the station the bearing
carries bursts of outliers, which the Huber update (docs/algorithms.md §G5)
resists. Filters: ``ekf`` (with ``α``), ``no-bias`` (ignores ``α``) and
``huber`` (with ``α`` and the Huber update, ``κ`` = :data:`DEFAULT_KAPPA`).

Submodules: :mod:`~noisevar.systems.robust.scenario` (:func:`simulate_robust`),
:mod:`~noisevar.systems.robust.filters` (:func:`run_robust`),
:mod:`~noisevar.systems.robust.kappa` (:func:`kappa_tradeoff`,
:func:`paired_rmse_ratio`).
"""

from noisevar.systems.robust.filters import (
    DEFAULT_KAPPA,
    PAPER_KAPPA,
    START_ERROR,
    RobustResult,
    build_model,
    run_robust,
)
from noisevar.systems.robust.kappa import KappaTradeoff, kappa_tradeoff, paired_rmse_ratio
from noisevar.systems.robust.scenario import (
    MEASUREMENT_NAMES,
    STATE_NAMES,
    RobustData,
    RobustScenario,
    simulate_robust,
    trajectory,
)

__all__ = [
    "DEFAULT_KAPPA",
    "MEASUREMENT_NAMES",
    "PAPER_KAPPA",
    "START_ERROR",
    "STATE_NAMES",
    "KappaTradeoff",
    "RobustData",
    "RobustResult",
    "RobustScenario",
    "build_model",
    "kappa_tradeoff",
    "paired_rmse_ratio",
    "run_robust",
    "simulate_robust",
    "trajectory",
]

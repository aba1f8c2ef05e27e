"""R-adaptation strategies: small objects the filter asks for ``R_k`` (and ``Q_k``).

=================  =========================================================
``fixed``          the model's ``R`` (or one given)
``oracle``         the true ``R`` (time-varying allowed): the lower bound
``somd``           our SOMD estimator over a trailing window per channel
``rae``, ``iae``   residual / innovation based, docs/algorithms.md §A10
``rae-q``          residual-based ``R`` and ``Q = K C_d Kᵀ`` (§B1)
``sage-husa``      recursive with forgetting factor (§B4)
``vb``             variational Bayes, inverse-gamma per channel (§B2)
=================  =========================================================

The hooks are documented in :mod:`noisevar.kalman.strategies.base`; the robust
Huber update is an option of the filter (:class:`~noisevar.kalman.HuberUpdate`).
"""

from noisevar.kalman.strategies.base import RStrategy
from noisevar.kalman.strategies.fixed import FixedR, OracleR
from noisevar.kalman.strategies.registry import (
    ALIASES,
    STRATEGIES,
    StrategySpec,
    make_strategy,
    strategy_spec,
)
from noisevar.kalman.strategies.sage_husa import SageHusaR
from noisevar.kalman.strategies.somd import SomdOnlineR
from noisevar.kalman.strategies.vb import VariationalBayesR
from noisevar.kalman.strategies.windowed import InnovationR, MovingMean, ResidualQR, ResidualR

__all__ = [
    "ALIASES",
    "STRATEGIES",
    "FixedR",
    "InnovationR",
    "MovingMean",
    "OracleR",
    "RStrategy",
    "ResidualQR",
    "ResidualR",
    "SageHusaR",
    "SomdOnlineR",
    "StrategySpec",
    "VariationalBayesR",
    "make_strategy",
    "strategy_spec",
]

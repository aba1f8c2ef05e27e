"""Deprecated location: the batch SOMD helpers live in :mod:`noisevar.estimators.somd`.

Kept only so that existing imports work until they are switched; new code imports
``somd_variance_windows`` and ``somd_variance_records`` from ``noisevar.estimators.somd``.
"""

from noisevar.estimators.somd import (
    MIN_WINDOWS,
    TRACK_RATIO,
    WINDOW,
    somd_variance_records,
    somd_variance_windows,
)

__all__ = [
    "MIN_WINDOWS",
    "TRACK_RATIO",
    "WINDOW",
    "somd_variance_records",
    "somd_variance_windows",
]

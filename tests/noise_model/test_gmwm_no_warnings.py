"""``fit_imu_model`` on a moving record prints no scipy warning (issue 26, real_audit.py).

On scikit-kinematics' moving Xsens and x-io records, 24 of 36 axes printed scipy's
``RuntimeWarning``s (overflow, divide by zero in ``_lsq/common.py``) and so did
``noisevar imu``: a white-noise parameter the data do not support runs its log down to its
-inf bound, where trf's step arithmetic overflows. The fit is the same without them.
"""

from __future__ import annotations

import warnings

import numpy as np

import noisevar


def moving_axes(seed: int, n: int = 1000, rate: float = 50.0) -> np.ndarray:
    """Three axes of a slow random walk plus a sine (motion), little white noise."""
    rng = np.random.default_rng(seed)
    t = np.arange(n) / rate
    return np.column_stack(
        [
            np.cumsum(rng.normal(size=n)) * 0.05
            + np.sin(2 * np.pi * rng.uniform(0.2, 2) * t) * rng.uniform(0.5, 3)
            + 0.01 * rng.normal(size=n)
            for _ in range(3)
        ]
    )


def test_fit_imu_model_on_motion_warns_nothing() -> None:
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        fits = noisevar.fit_imu_model(moving_axes(0), 50.0)
    assert [str(w.message) for w in caught] == []
    assert all(np.isfinite(p.value) for f in fits for p in f.parameters)

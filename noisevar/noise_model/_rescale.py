"""A Kalman tuning fitted on a scaled copy of the record, in the record's units (§F5.8)."""

from __future__ import annotations

from dataclasses import replace
from typing import TYPE_CHECKING, Any

import numpy as np

from noisevar.estimators import scale_back

if TYPE_CHECKING:
    from noisevar.noise_model.kalman_fit import KalmanTuning


def rescale_tuning(t: KalmanTuning, e: int) -> KalmanTuning:
    """A tuning fitted on ``z 2**e`` in the units of ``z``: variances (q, r, Q, R, P, P0)
    x ``2**-2e``, the start state x ``2**-e``, the log-likelihood + ``e ln 2`` per term;
    h, the gain, the NIS and the whiteness test do not change."""

    def var(v: Any, what: str = "noise variance") -> Any:
        return scale_back(v, -2 * e, what)

    with np.errstate(over="ignore"):  # a covariance beyond the float range: said below
        P, P0 = np.ldexp(t.P, -2 * e), np.ldexp(t.P0, -2 * e)
    notes = t.notes
    if not (np.isfinite(P).all() and np.isfinite(P0).all()):
        notes += (
            "the filter's state covariance exceeds the largest floating-point number in "
            "these units (shown as null): rescale the record to use it",
        )
    return replace(
        t,
        notes=notes,
        q=var(t.q, "process noise"),
        r=var(t.r),
        q_interval=tuple(var(v, "process noise") for v in t.q_interval),
        r_interval=tuple(var(v) for v in t.r_interval),
        Q=var(t.Q, "process noise"),
        R=var(t.R),
        P=P,
        P0=P0,
        x0=np.ldexp(t.x0, -e),
        loglik=t.loglik + e * np.log(2.0) * (t.n - t.start),
    )

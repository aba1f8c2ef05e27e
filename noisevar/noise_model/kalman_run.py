"""Every kinematic model fitted to one record (:func:`fit_models`) and the tuned filter run
on it (:func:`run_tuned` -> :class:`TunedRun`): what the Noise model page shows and the
exports' reference run."""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.estimators.regimes import DEFAULT_REGIMES
from noisevar.kalman.divergence import nis_band
from noisevar.noise_model._steady import filter_pass
from noisevar.noise_model.kalman_fit import (
    AUTO_METHOD,
    MODELS,
    KalmanTuning,
    _check_input,
    fit_kalman,
)
from noisevar.noise_model.kalman_record import record_estimate


@dataclass(frozen=True)
class TunedRun:
    """The tuned filter run on a record: estimates ``x(k|k)``, innovations, NIS, from ``start``."""

    index: NDArray
    states: NDArray
    innovations: NDArray
    s: NDArray
    nis: NDArray
    nis_band: tuple[float, float]


def run_tuned(tuning: KalmanTuning, z: ArrayLike) -> TunedRun:
    """Run a tuned filter on a record, from its exact diffuse start.

    Parameters
    ----------
    tuning : KalmanTuning
    z : array_like, shape (n,)

    Returns
    -------
    TunedRun
        Estimates ``x(k|k)``, innovations, their variances and NIS for
        ``k >= start``.
    """
    arr, _ = _check_input(z, tuning.model, tuning.rate)
    zc = arr - arr[0]
    fp = filter_pass(zc, tuning.F, tuning.H[0], tuning.Q, float(tuning.R[0, 0]))
    states = fp.states.copy()
    states[:, 0] += arr[0]
    nis = fp.innovations**2 / fp.s
    index = np.arange(fp.start, arr.size)
    return TunedRun(index, states, fp.innovations, fp.s, nis, nis_band(1, nis.size))


def fit_models(
    z: ArrayLike,
    rate: float | None = None,
    method: str = AUTO_METHOD,
    regimes: str = DEFAULT_REGIMES,
    progress: Callable[[float], None] | None = None,
    t: ArrayLike | None = None,
) -> dict[str, KalmanTuning]:
    """:func:`~noisevar.noise_model.kalman_fit.fit_kalman` of every kinematic model, the
    record's answer (``estimate``) made once for all of them.

    Parameters
    ----------
    z : array_like, shape (n,)
    rate, method, regimes
        As :func:`~noisevar.noise_model.kalman_fit.fit_kalman`'s.
    progress : callable, optional
        Called with the fraction done over all the models (0 to 1).
    t : array_like, shape (n,), optional
        The samples' times (s): the record's answer is made on them (split at their gaps),
        as ``noisevar estimate``, ``noisevar fit`` and the Estimator page make it.

    Returns
    -------
    dict
        Model name -> its fit, in :data:`~noisevar.noise_model.kalman_fit.MODELS`' order.
    """
    arr = np.asarray(z, dtype=float)
    answer = record_estimate(arr, None if t is None else np.asarray(t, dtype=float))
    record = None if isinstance(answer, str) else answer
    out = {}
    for i, model in enumerate(MODELS):
        step = None if progress is None else (lambda f, i=i: progress((i + f) / len(MODELS)))
        out[model] = fit_kalman(
            arr, model, rate, method, progress=step, regimes=regimes, record=record
        )
    return out

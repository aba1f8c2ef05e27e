"""The tuned filter run on a record (:func:`run_tuned` -> :class:`TunedRun`): what the
Noise model page draws and the exports' reference run."""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.kalman.divergence import nis_band
from noisevar.noise_model._steady import filter_pass
from noisevar.noise_model.kalman_fit import KalmanTuning, _check_input


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

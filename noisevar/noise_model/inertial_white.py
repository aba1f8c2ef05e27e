"""The white level of rate data and N's interval held against it (docs/algorithms.md §E4).

Moved from :mod:`noisevar.noise_model.inertial` (unchanged) to keep that module short.
"""

from __future__ import annotations

import math

import numpy as np
from numpy.typing import ArrayLike, NDArray


def white_level(y: ArrayLike, rate: float) -> float:
    """The white level ``sigma(tau0) sqrt(tau0)`` of rate data (unit/√Hz).

    Parameters
    ----------
    y : array_like, shape (n,)
        Rate samples.
    rate : float
        Sample rate (Hz).

    Returns
    -------
    float

    Notes
    -----
    docs/algorithms.md §E4. At ``tau0 = 1/fs`` the overlapping Allan variance is
    ``mean(diff(y)²) / 2``, so this is the std of first differences over ``sqrt(2 fs)``:
    ``N`` exactly for white rate noise, ``sqrt(N² + 3 Q² fs)`` with quantisation
    (its per-sample variance is ``2 Q² fs²``: counted 1.5x, on the safe side), and
    blind to a slow bias.
    """
    d = np.diff(np.asarray(y, dtype=float))
    return math.sqrt(float(np.mean(d**2)) / 2.0 / rate)


def n_against_white(coef: NDArray, ivals: NDArray, white: float, unit: str) -> list[str]:
    """Keep N's interval honest when Q took the short-tau noise; ``ivals`` is edited in place.

    When N is not told from 0 its upper bound is at least the white level (all of the
    short-tau noise white): the bootstrap, taking the taus as independent, overstates
    how well a short record splits Q from N.
    """
    n_value, q_value = math.sqrt(coef[1]), math.sqrt(coef[0])
    notes = []
    if ivals[1, 0] == 0.0 and ivals[1, 1] < white:
        ivals[1, 1] = white
        why = f" (Q = {q_value:.4g} {unit}·s took the short-tau noise)" if q_value > 0 else ""
        notes.append(
            f"N is not told from 0{why}: its upper bound is the white level "
            f"{white:.4g} {unit}/√Hz, as if all of the short-tau noise were white"
        )
    if q_value > 0 and n_value < white:
        notes.append(
            f"Q holds part of the Allan variance at tau0: N = {n_value:.4g} is below the white "
            f"level {white:.4g} {unit}/√Hz; a model without Q (Kalibr) needs the white level"
        )
    return notes

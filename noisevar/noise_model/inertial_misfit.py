"""Whether the IEEE-952 terms describe the Allan deviation they were fitted to.

docs/algorithms.md §E4 (the misfit check): eq. E4.1 is a static sensor's noise. A
record with a signal in it (motion, a periodic disturbance) has an Allan deviation with
a hump or a dip that no sum of the five terms makes; the fit then returns terms that
describe nothing. This module says so, and the exports' files say it too.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats

#: The misfit is judged only at taus whose Allan variance rests on at least this many
#: degrees of freedom (Greenhall's, under the fitted terms): the long taus' few clusters
#: make their chi-square skewed, correlated and the flicker term's approximation visible.
MISFIT_EDF = 30.0
#: Family-wise false-alarm rate of the check over the taus judged (Bonferroni).
MISFIT_ALPHA = 1e-3
#: The start of the note (the exports' files then warn: :func:`misfit_warnings`).
MISFIT = "the IEEE-952 terms do not describe the Allan deviation"
#: The start of the note of a misfit without a hump (the files say nothing more).
APPROXIMATE = "the IEEE-952 terms miss the Allan deviation"


def misfit_z(avar: NDArray, model: NDArray, edf: NDArray) -> NDArray:
    """The misfit of each tau in standard errors: ``ln(avar / model) / sqrt(2 / edf)``.

    Parameters
    ----------
    avar, model, edf : ndarray
        The data's Allan variances, the fitted terms' (eq. E4.1) and their edf.

    Returns
    -------
    ndarray
        NaN where ``edf < MISFIT_EDF`` (not judged).

    Notes
    -----
    ``avar`` is ``model chi²_edf / edf``; its log has std ``sqrt(2 / edf)`` to first order.
    """
    model = np.maximum(np.asarray(model, dtype=float), np.finfo(float).tiny)
    ratio = np.maximum(np.asarray(avar, dtype=float), np.finfo(float).tiny) / model
    edf = np.asarray(edf, dtype=float)
    z = np.log(ratio) / np.sqrt(2.0 / np.maximum(edf, np.finfo(float).tiny))
    return np.where(edf >= MISFIT_EDF, z, np.nan)


def hump(taus: NDArray, avar: NDArray, edf: NDArray, bound: float) -> int | None:
    """The judged tau where ``avar tau`` rose to and then fell from, or None.

    Parameters
    ----------
    taus, avar, edf : ndarray
        Averaging times, the data's Allan variances and their edf.
    bound : float
        Standard errors a rise and the fall after it must each pass.

    Returns
    -------
    int or None
        The index of the highest such peak.

    Notes
    -----
    ``sigma^2(tau) tau`` is convex for every sum of E4.1's terms (``3Q^2/tau``, ``N^2``,
    and rising ``B``, ``K``, ``R`` parts), so it cannot rise and then fall; nor can a
    Gauss-Markov bias's (it rises to ``2 sigma^2 T^2``). A sine's does: its Allan
    deviation peaks near ``0.37 P`` and falls as ``tau^-1`` after.
    """
    k = np.flatnonzero(np.asarray(edf) >= MISFIT_EDF)
    g = np.log(np.maximum(avar[k] * taus[k], np.finfo(float).tiny))
    se = np.sqrt(2.0 / edf[k])
    peaks = [
        p
        for p in range(1, k.size - 1)
        if np.any(g[p] - g[:p] > bound * np.hypot(se[p], se[:p]))
        and np.any(g[p] - g[p + 1 :] > bound * np.hypot(se[p], se[p + 1 :]))
    ]
    return int(k[max(peaks, key=lambda p: g[p])]) if peaks else None


def misfit_note(taus: NDArray, avar: NDArray, model: NDArray, edf: NDArray) -> list[str]:
    """The note of a fit whose terms do not describe the Allan deviation, or none.

    Parameters
    ----------
    taus, avar, model, edf : ndarray
        Averaging times (s), the data's Allan variances, the fitted terms' and the edf.

    Returns
    -------
    list of str
        One note when some judged tau's misfit (:func:`misfit_z`) passes the Bonferroni
        bound of :data:`MISFIT_ALPHA` over the judged taus: :data:`MISFIT` when the data
        have a :func:`hump` (no still sensor's noise), :data:`APPROXIMATE` otherwise.

    Notes
    -----
    Measured false alarms and detections: docs/algorithms.md §E4.
    """
    z = misfit_z(avar, model, edf)
    judged = np.flatnonzero(np.isfinite(z))
    if judged.size == 0:
        return []
    bound = stats.norm.isf(MISFIT_ALPHA / (2.0 * judged.size))
    worst = judged[np.argmax(np.abs(z[judged]))]
    if abs(z[worst]) <= bound:
        return []
    peak = hump(taus, avar, edf, bound)
    ratio = float(np.sqrt(avar[worst] / model[worst]))  # scale-free: no unit quoted
    if peak is None:  # a still sensor's noise E4.1 lacks (a Gauss-Markov bias), or slow motion
        return [
            f"{APPROXIMATE}: at tau {taus[worst]:.3g} s the data's deviation is {ratio:.3g}x "
            f"the terms' ({abs(z[worst]):.1f} standard errors, bound {bound:.1f}): a bias "
            "that is no term of E4.1 (Gauss-Markov: noisevar.fit_imu_model describes it) or "
            "slow motion; the terms are approximate there"
        ]
    return [
        f"{MISFIT}: at tau {taus[worst]:.3g} s the data's deviation is {ratio:.3g}x the "
        f"terms' ({abs(z[worst]):.1f} standard errors, bound {bound:.1f}), and "
        f"σ²(τ)·τ rises to tau {taus[peak]:.3g} s and falls after, which no noise "
        "term makes: a signal, motion or a "
        "periodic disturbance, not the sensor's noise; the terms and intervals describe "
        "nothing. Record the sensor still, or fit the still regimes only (regimes='still')"
    ]


def misfit_warnings(sensors: Mapping[str, Sequence[Any]]) -> list[str]:
    """The files' warning for each axis whose terms do not describe its Allan deviation.

    Parameters
    ----------
    sensors : mapping of str to sequence of InertialNoise
        Each sensor's axes (e.g. ``{"gyroscope": [...]}``) a filter's file is written from.

    Returns
    -------
    list of str
        One line per such axis (:data:`MISFIT` notes); none when every axis is described.

    Notes
    -----
    The files warn rather than refuse: a vehicle's log has its vibration (a hump at the
    rotors' period: PX4's committed log, accelerometer Z) that its filter will see too,
    and the density written is at least the white level (§E4).
    """
    out = []
    for sensor, fits in sensors.items():
        for i, fit in enumerate(fits):
            for note in (n for n in fit.notes if n.startswith(MISFIT)):
                advice = (
                    "its still stretch too: record the sensor still"
                    if fit.regimes == "still"
                    else "record the sensor still, or fit the still regimes only "
                    "(regimes='still', --regimes still)"
                )
                out.append(
                    f"NOT A STILL SENSOR'S NOISE: {sensor} axis {i}: {note.split(' (', 1)[0]}; "
                    f"its values here describe the record, not the sensor: {advice}"
                )
    return out

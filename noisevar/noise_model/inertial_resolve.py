"""Which IEEE-952 terms a record's Allan deviation resolves (docs/algorithms.md §E4
*Resolution*).

A term is seen where it dominates the Allan variance; on a short record those taus rest
on a few clusters, and a fit that keeps the term there (and a bootstrap drawn from that
fit) gives it a value with an interval that the record does not support. Such a term is
reported as not resolved, with an upper bound only, and the exports' files say so.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import stats

from noisevar.noise_model.inertial_misfit import MISFIT_EDF, misfit_warnings

#: The start of the note of the terms a record does not resolve.
UNRESOLVED = "not resolved"
#: Taus a term must dominate to be resolved: two, the fewest that show its slope (one
#: tau's level is shared by every term there).
SLOPE_POINTS = 2
#: The term always kept (N: :func:`~noisevar.noise_model.inertial.fit_terms`); its upper
#: bound is held against the measured white level instead (``n_against_white``).
ALWAYS = 1


def dominant(a: NDArray, coef: NDArray) -> NDArray:
    """The index of the term holding the largest share of the fitted Allan variance at
    each tau (``a`` the terms' coefficients per tau, ``coef`` the squared terms)."""
    return np.argmax(a * np.asarray(coef)[None, :], axis=1)


def resolved(a: NDArray, coef: NDArray, edf: NDArray) -> NDArray:
    """Whether each fitted term is resolved: it dominates the fitted Allan variance at
    :data:`SLOPE_POINTS` taus or more, whose edf add up to :data:`MISFIT_EDF` or more.

    Parameters
    ----------
    a : ndarray (taus, terms)
        Each term's coefficient at each tau (eq. E4.1).
    coef : ndarray
        The squared terms; a left-out term (0) counts as resolved (it is an upper bound).
    edf : ndarray
        Each tau's edf under the fitted terms.

    Returns
    -------
    ndarray of bool

    Notes
    -----
    The edf summed over overlapping taus overstates what they hold together (their
    estimates are correlated): the rule errs on the side of calling a term resolved, and
    the bar is the one a single tau must pass to be judged by the misfit check.
    """
    top = dominant(a, coef)
    counts = np.bincount(top, minlength=len(coef))
    dof = np.bincount(top, weights=np.asarray(edf, dtype=float), minlength=len(coef))
    out = ((counts >= SLOPE_POINTS) & (dof >= MISFIT_EDF)) | (np.asarray(coef) == 0)
    out[ALWAYS] = True
    return out


def data_bound(a: NDArray, avar: NDArray, edf: NDArray, ci: float) -> NDArray:
    """Each term's largest value the Allan variances allow alone: ``sqrt(min over tau of
    hi(tau) / a(tau))``, ``hi`` the upper ``(1 + ci) / 2`` chi-square bound of each tau's
    Allan variance on its edf (the other terms taken as 0)."""
    lower = stats.chi2.ppf((1.0 - ci) / 2.0, np.maximum(edf, np.finfo(float).eps))
    hi = np.asarray(avar) * edf / np.maximum(lower, np.finfo(float).tiny)
    with np.errstate(divide="ignore"):
        return np.sqrt(np.min(hi[:, None] / a, axis=0))


def resolve(
    a: NDArray,
    coef: NDArray,
    avar: NDArray,
    edf: NDArray,
    ivals: NDArray,
    ci: float,
    labels: Sequence[str],
) -> list[str]:
    """Widen the interval of each unresolved term to ``(0, upper bound)``; ``ivals`` is
    edited in place.

    Parameters
    ----------
    a, coef, edf
        As :func:`resolved`.
    avar : ndarray
        The data's Allan variances.
    ivals : ndarray (terms, 2)
        The terms' intervals (unsquared).
    ci : float
        Their confidence level.
    labels : sequence of str
        Each term's label, e.g. ``"B (bias instability)"``.

    Returns
    -------
    list of str
        The note naming the unresolved terms (none when every term is resolved).

    Notes
    -----
    The upper bound is the larger of the bootstrap's and :func:`data_bound`: the bootstrap
    draws from the fit, which on these taus the record cannot check.
    """
    bound = data_bound(a, avar, edf, ci)
    out = np.flatnonzero(np.asarray(coef) == 0)  # from the fit's bootstrap: a model without it
    ivals[out, 1] = np.maximum(ivals[out, 1], bound[out])
    bad = np.flatnonzero(~resolved(a, coef, edf))
    if bad.size == 0:
        return []
    ivals[bad, 0] = 0.0
    ivals[bad, 1] = np.maximum(ivals[bad, 1], bound[bad])
    named = ", ".join(
        f"{labels[i]} = {np.sqrt(coef[i]):.3g}, up to {ivals[i, 1]:.3g}" for i in bad
    )
    return [
        f"{UNRESOLVED}: {named}: the fit keeps them, but the taus where they dominate are "
        f"fewer than {SLOPE_POINTS} or rest on fewer than {MISFIT_EDF:g} degrees of freedom "
        "together (too few clusters of the record): each is an upper bound, not a measured "
        "value; record the sensor longer to measure them"
    ]


def resolution_warnings(sensors: Mapping[str, Sequence[Any]]) -> list[str]:
    """The files' line for each axis with terms its record does not resolve.

    Parameters
    ----------
    sensors : mapping of str to sequence of InertialNoise
        Each sensor's axes (e.g. ``{"gyroscope": [...]}``) a file is written from.

    Returns
    -------
    list of str
    """
    return [
        f"{sensor} axis {i}: {note.split(': the fit', 1)[0]}: upper bounds, not measured values "
        "(the values written from them are upper bounds too)"
        for sensor, fits in sensors.items()
        for i, fit in enumerate(fits)
        for note in fit.notes
        if note.startswith(UNRESOLVED)
    ]


def axis_warnings(sensors: Mapping[str, Sequence[Any]]) -> list[str]:
    """What a filter's file says first of the axes it is written from: the axes whose terms
    describe nothing (:func:`~noisevar.noise_model.inertial_misfit.misfit_warnings`), then
    the terms a record does not resolve (:func:`resolution_warnings`)."""
    return misfit_warnings(sensors) + resolution_warnings(sensors)


def left_out_note(coef: NDArray, ivals: NDArray, symbols: Sequence[str]) -> list[str]:
    """The note naming the terms the fit left out (0), with their upper bounds."""
    left = [f"{s} (up to {hi:.3g})" for s, c, (_, hi) in zip(symbols, coef, ivals, strict=True)
            if c == 0]  # fmt: skip
    return ["left out, the data do not support them: " + ", ".join(left)] if left else []

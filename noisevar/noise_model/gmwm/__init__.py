"""Composite IMU noise models from the Haar wavelet variance (GMWM; docs/algorithms.md §E10).

:func:`fit_imu_model` fits white noise, quantisation, random walk, drift, Gauss-Markov
and flicker processes per axis, chooses the model, and gives intervals;
:func:`fit_imu_records` fits one model to several records of one unit;
:func:`fisher_bound` is the information bound any estimator of a model meets.
"""

from __future__ import annotations

import os
from collections.abc import Sequence
from concurrent.futures import ThreadPoolExecutor
from dataclasses import replace

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.estimators.regimes import DEFAULT_REGIMES, check_regimes, longest_still_stretch
from noisevar.noise_model.allan import regime_warning
from noisevar.noise_model.gmwm.bound import InformationBound, fisher_bound
from noisevar.noise_model.gmwm.fitting import (
    AUTO,
    DEFAULT_CRITERION,
    as_rows,
    fit_wv,
    pooled,
    unexplained,
    wavelet_variances,
)
from noisevar.noise_model.gmwm.model import (
    HORIZON,
    ONE_SIGMA,
    FilterBias,
    ImuModel,
    ModelRow,
    Parameter,
)
from noisevar.noise_model.gmwm.scaling import scaled

__all__ = [
    "AUTO",
    "FilterBias",
    "ImuModel",
    "InformationBound",
    "ModelRow",
    "Parameter",
    "fisher_bound",
    "fit_imu_model",
    "fit_imu_records",
]


def fit_imu_model(
    x: ArrayLike,
    rate: float,
    *,
    axis: int = 0,
    models: str | Sequence[str] = "auto",
    robust: bool = False,
    unit: str = "u",
    ci: float = ONE_SIGMA,
    criterion: str = DEFAULT_CRITERION,
    horizon: float = HORIZON,
    workers: int | None = 1,
    regimes: str = DEFAULT_REGIMES,
) -> ImuModel | tuple[ImuModel, ...]:
    """Fit a composite noise model to rate data by GMWM, choosing the model.

    Parameters
    ----------
    x : array_like, shape (n,) or (n, axes)
        Rate samples of a still sensor (gyro rate, specific force); several axes
        (e.g. the 6 of an IMU) in a 2-D array.
    rate : float
        Sample rate (Hz).
    axis : int
        The time axis of a 2-D ``x`` (default 0: ``(n, axes)``).
    models : "auto" or list of str
        ``"auto"``: a forward search from white noise, adding the process (QN, FL, GM up
        to twice, RW, DR) that lowers the criterion most, while it does. Or the
        candidate models, e.g. ``["WN+RW", "QN+WN+GM+RW"]``.
    robust : bool
        Use Huber's robust wavelet variance (records with outliers).
    unit : str
        Unit of the rate data, for the parameters' units.
    ci : float
        Confidence level of the intervals.
    criterion : {"hq", "bic", "wvic"}
        The criterion of the choice (:class:`ModelRow` has all three): the objective
        plus, per parameter, ``2 log log n`` (Hannan-Quinn), ``log n`` or 2.
    horizon : float
        Horizon (s) of the random-walk equivalent of the bias (:class:`FilterBias`).
    workers : int or None
        Threads for several axes (None: the number of CPUs). Default 1: the model
        search holds the GIL, so threads add CPU without saving time (on 6 axes x
        7.2e6 samples, 2 threads took 10 % more CPU and no less wall time on a
        2-core machine; BENCHMARKS.md, issue 30).
    regimes : {"all", "still"}
        Fit each axis's whole record, or its longest still stretch only (each axis its
        own, said in ``notes``; :mod:`noisevar.estimators.regimes`).

    Returns
    -------
    ImuModel, or a tuple of them (one per axis) for a 2-D ``x``

    Notes
    -----
    docs/algorithms.md §E10. The wavelet variances of all axes are computed at once;
    each axis is fitted by weighted least squares on the log-parameters, weighted by
    the diagonal of the fitted model's asymptotic covariance of the wavelet variance;
    intervals by the delta method with the full covariance (sandwich form). A fit of
    the whole record that leaves something unexplained (a misfit, N at its bound) says
    whether the record's noise level varies (:func:`motion_note`).
    """
    check_regimes(regimes)
    arr = as_rows(x, axis)
    notes: list[list[str]] = [[] for _ in arr]
    scaled_arr, exps = scaled(arr)  # each axis at its own magnitude (scaling)
    if regimes == "still":  # found on the scaled axis: its whole R may not be a float here
        need = STILL_NEED
        cut = [longest_still_stretch(row, need, "the composite model") for row in scaled_arr]
        notes = [[s.note] for s in cut]
        rows = [scaled(s.take(row)[None, :]) for s, row in zip(cut, arr, strict=True)]
        wvs = [wavelet_variances(r, robust)[0] for r, _ in rows]
        exps = [e for _, (e,) in rows]
    else:
        wvs = wavelet_variances(scaled_arr, robust)
    kw = dict(models=models, robust=robust, unit=unit, ci=ci, criterion=criterion)

    def one(i: int) -> ImuModel:
        fit = fit_wv(wvs[i], rate, horizon=horizon, e=exps[i], **kw)
        extra = notes[i] if regimes == "still" else motion_note(arr[i], fit)
        return replace(fit, notes=(*extra, *fit.notes)) if extra else fit

    if np.ndim(x) == 1:
        return one(0)
    n_workers = max(1, min(len(wvs), workers or os.cpu_count() or 1))
    if n_workers == 1:
        return tuple(one(i) for i in range(len(wvs)))
    with ThreadPoolExecutor(n_workers) as pool:
        return tuple(pool.map(one, range(len(wvs))))


#: Fewest samples of a still stretch a composite fit takes: 3 wavelet scales.
STILL_NEED = 16


def motion_note(row: NDArray, fit: ImuModel) -> list[str]:
    """The regime warning (:func:`~noisevar.noise_model.allan.regime_warning`) of a
    whole-record fit that leaves the data unexplained.

    Parameters
    ----------
    row : ndarray, shape (n,)
        The axis's record.
    fit : ImuModel
        Its fit on the whole record.

    Returns
    -------
    list of str
        The warning when ``fit`` misfits or has N at its bound
        (:func:`~noisevar.noise_model.gmwm.fitting.unexplained`) and the estimate's
        diagnostics say the level varies; else none.

    Notes
    -----
    The diagnostics add about a third to the fit's CPU on a long record; a fit that
    explains the wavelet variance (a still record) is not checked, so the composite
    fit's speed on still records is unchanged.
    """
    return regime_warning(row) if unexplained(fit) else []


def fit_imu_records(
    records: Sequence[ArrayLike],
    rate: float,
    *,
    models: str | Sequence[str] = "auto",
    robust: bool = False,
    unit: str = "u",
    ci: float = ONE_SIGMA,
    criterion: str = DEFAULT_CRITERION,
    horizon: float = HORIZON,
) -> ImuModel:
    """One noise model of a sensor from several still records of it (several nights).

    Parameters
    ----------
    records : sequence of 1-D array_like
        The records (any lengths), all of one axis at one ``rate``.
    rate, models, robust, unit, ci, criterion, horizon
        As :func:`fit_imu_model`.

    Returns
    -------
    ImuModel

    Notes
    -----
    Each record's wavelet variance is computed on its own (no jump between records
    enters it); at each scale they are averaged weighted by their coefficients, and
    the covariance counts all the coefficients. A pooled fit that leaves the data
    unexplained names the records whose noise level varies (:func:`moving_records`).
    """
    if len(records) == 0:
        raise NoisevarError("records is empty: give at least one record.")
    arrs = [as_rows(r, 0) for r in records]
    if any(arr.shape[0] != 1 for arr in arrs):
        raise NoisevarError("each record must be 1-D (one axis).")
    _, (e,) = scaled(np.concatenate(arrs, axis=None)[None, :])  # one scale: one unit
    wvs = [wavelet_variances(np.ldexp(arr, e), robust)[0] for arr in arrs]
    fit = fit_wv(
        pooled(wvs),
        rate,
        e=e,
        models=models,
        robust=robust,
        unit=unit,
        ci=ci,
        criterion=criterion,
        horizon=horizon,
    )
    return replace(fit, notes=(*moving_records(records, fit), *fit.notes))


def moving_records(records: Sequence[ArrayLike], fit: ImuModel) -> list[str]:
    """Which of the pooled ``records`` are not still, when their pooled ``fit`` leaves the
    data unexplained (as :func:`motion_note` of one record; none otherwise)."""
    if not unexplained(fit):
        return []
    return [
        f"record {i}: {w}"
        for i, r in enumerate(records)
        for w in regime_warning(np.ravel(np.asarray(r, dtype=float)))
    ]

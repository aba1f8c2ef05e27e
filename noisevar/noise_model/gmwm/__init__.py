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

from noisevar._distributions import chi2_ppf
from noisevar.errors import NoisevarError
from noisevar.estimators import scale_exponent
from noisevar.estimators.regimes import (
    DEFAULT_REGIMES,
    StillStretch,
    check_regimes,
    longest_still_stretch,
)
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
    stretch: StillStretch | None = None,
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
    stretch : StillStretch, optional
        With ``regimes="still"``: the stretch every axis is fitted on, an IMU's where all
        its axes are still (:func:`~noisevar.noise_model.inertial_axes.imu_still_stretch`).

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
        cut = [
            stretch or longest_still_stretch(row, need, "the composite model")
            for row in scaled_arr
        ]
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
    The diagnostics add about a third to the fit's CPU on a long record; they run
    only when the fit leaves the data unexplained or the one-pass screen
    :func:`level_may_vary` cannot rule out a level that varies (polulu gyr_x: a
    WN+FL+GM fit that absorbs the motion), so a still record's fit costs one more pass.
    """
    return regime_warning(row) if unexplained(fit) or level_may_vary(row) else []


#: Blocks of the screen (:func:`level_may_vary`), at most.
SCREEN_BLOCKS = 256
#: Fewest first differences per block of the screen.
SCREEN_MIN_BLOCK = 32
#: Family-wise level of the screen's χ² bands for one level, over all its blocks.
SCREEN_ALPHA = 0.01
#: The finest blocks' Gaussian band is widened by this factor either way.
SCREEN_SLACK = 1.2


def level_may_vary(row: NDArray) -> bool:
    """A cheap screen before the estimate's regimes: whether the short-scale level of a
    record may change along it.

    Parameters
    ----------
    row : ndarray, shape (n,)
        The axis's record.

    Returns
    -------
    bool
        False when, at every scale of blocks (the finest, then pairs of them merged,
        and so on up to two halves), each block's mean square of first differences lies
        inside the family-wise χ² band of one level about the record's, and the finest
        blocks inside the Gaussian band widened by :data:`SCREEN_SLACK`; True otherwise
        (then the estimate's diagnostics decide,
        :func:`~noisevar.noise_model.allan.regime_warning`).

    Notes
    -----
    One pass over the record. A block mean square of ``b`` differences of white noise
    (lag-1 correlation -1/2) has about ``b / 1.5`` dof, fewer by ``2 / (κ - 1)`` for the
    differences' kurtosis ``κ``; merged blocks add their dof, so a long stretch at a
    slightly higher level (1.3x over a third of the record) stands out at a coarse
    scale. The screen only spares the estimate on records whose level is one beyond
    doubt (a still IMU); it never decides that a level varies.
    """
    n = row.size - 1
    block = max(SCREEN_MIN_BLOCK, -(-n // SCREEN_BLOCKS))
    nb = n // block
    if nb < 2:
        return True
    e = scale_exponent(row)  # the screen is scale-free: squares of 2**e row (exact)
    row = np.ldexp(row, e) if e else row
    d2 = np.square(np.diff(row[: nb * block + 1])).reshape(nb, block)
    sq = d2.sum(axis=1)
    total = float(np.sum(sq))
    if not (np.isfinite(total) and total > 0):
        return True
    scale = total / d2.size
    kurt = float(np.einsum("ij,ij->", d2, d2)) / d2.size / scale**2
    if not np.isfinite(kurt):
        return True
    nu = block / 1.5 * 2.0 / max(kurt - 1.0, 2.0)
    sums, tests = [sq / (block * scale)], nb
    while sums[-1].size >= 4:
        k = sums[-1].size // 2
        sums.append(sums[-1][: 2 * k].reshape(k, 2).sum(axis=1))
        tests += k
    q = SCREEN_ALPHA / (2 * tests)
    # the finest blocks also with Gaussian dof, widened by SCREEN_SLACK: motion in heavy
    # bursts raises the kurtosis, and with it every band above, as much as the level
    g = block / 1.5
    lo, hi = chi2_ppf(q, g) / g / SCREEN_SLACK, chi2_ppf(1.0 - q, g) / g * SCREEN_SLACK
    if np.any(sums[0] < lo) or np.any(sums[0] > hi):
        return True
    for level, r in enumerate(sums):
        m = 2**level  # blocks merged
        lo, hi = chi2_ppf(q, m * nu) / nu, chi2_ppf(1.0 - q, m * nu) / nu
        if np.any(r < lo) or np.any(r > hi) or not np.all(np.isfinite(r)):
            return True
    return False


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

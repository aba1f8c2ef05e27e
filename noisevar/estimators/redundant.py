"""SOMD with real redundant sensors (docs/algorithms.md §A1): a pair, or the three-cornered hat."""

from __future__ import annotations

import numpy as np
from numpy.typing import ArrayLike, NDArray

from noisevar.errors import NoisevarError
from noisevar.estimators._input import as_signal
from noisevar.estimators.results import RedundantEstimate, VarianceEstimate, chi2_interval
from noisevar.estimators.spec import MethodSpec


def redundant_estimate(
    z: NDArray,
    reference: ArrayLike,
    reference_variance: float = 0.0,
    notes: list[str] | None = None,
) -> VarianceEstimate:
    """SOMD with a real redundant sensor, eq. [8]: ``var(V2) = E[(ΔZ1 - ΔZ2)²]/2 - var(V1)``.

    Parameters
    ----------
    z : ndarray
        The sensor whose noise is wanted (``Z2``).
    reference : array_like
        A second sensor of the same quantity (``Z1``), same length.
    reference_variance : float
        Known noise variance of the reference (0: the paper's assumption
        ``var(V1) << var(V2)``; otherwise it is subtracted exactly).
    notes : list of str, optional
        Remarks carried into the result.

    Returns
    -------
    VarianceEstimate
    """
    ref, _ = as_signal(reference)
    if ref.size != z.size:
        raise NoisevarError(
            f"the reference sensor has {ref.size} samples and the signal {z.size}: "
            "give two records of the same length (align them first)"
        )
    dd = np.diff(ref) - np.diff(z)
    # var(V1) + var(V2) = E[(ΔZ1 - ΔZ2)²] / 2
    pair = float(np.mean(dd**2) / 2.0)
    var = pair - float(reference_variance)
    dof = dd.size / 1.5
    lo, hi = chi2_interval(pair, dof)
    return VarianceEstimate(
        "somd-redundant",
        var,
        (lo - reference_variance, hi - reference_variance),
        dd.size,
        z.size,
        dof,
        {"reference_variance": float(reference_variance)},
        list(notes or []),
    )


def estimate_redundant(sensors: ArrayLike) -> RedundantEstimate:
    """Each sensor's noise variance from two or more real sensors (docs/algorithms.md §A1).

    For every pair ``1/2 E[(ΔZi - ΔZj)²] = var_i + var_j``. With three or more sensors
    the pair sums are solved for each variance by least squares (the three-cornered
    hat); with two, only the sum is identifiable and each sensor gets the sum as an
    upper bound.

    Parameters
    ----------
    sensors : array_like, shape (n, k)
        One column per sensor, same sampling instants.

    Returns
    -------
    RedundantEstimate
    """
    Z = np.asarray(sensors, dtype=float)
    if Z.ndim != 2 or Z.shape[1] < 2:
        raise NoisevarError(
            f"give two or more sensors as columns of an (n, k) array, got shape {Z.shape}"
        )
    if not np.all(np.isfinite(Z)):
        raise NoisevarError("the sensor records contain NaN or Inf: clean them first")
    n, k = Z.shape
    if n < 8:
        raise NoisevarError(f"only {n} samples per sensor: give at least 100")
    D = np.diff(Z, axis=0)
    i, j = np.triu_indices(k, 1)
    # var_i + var_j = E[(ΔZi - ΔZj)²] / 2
    sums = np.mean((D[:, i] - D[:, j]) ** 2, axis=0) / 2.0
    pair = np.zeros((k, k))
    pair[i, j] = pair[j, i] = sums
    notes: list[str] = []
    dof_pair = (n - 1) / 1.5
    if k == 2:
        variances = np.array([sums[0], sums[0]])
        notes.append(
            "two sensors give only the sum var1 + var2; each value is that sum (an upper bound)"
        )
        ci = np.array([chi2_interval(sums[0], dof_pair)] * 2)
        return RedundantEstimate(variances, ci, pair, n, notes)
    A = np.zeros((i.size, k))
    A[np.arange(i.size), i] = 1.0
    A[np.arange(i.size), j] = 1.0
    variances, *_ = np.linalg.lstsq(A, sums, rcond=None)
    if np.any(variances < 0):
        notes.append("a negative variance was clipped to 0: that sensor's noise is below detection")
        variances = np.maximum(variances, 0.0)
    # approximate CI: propagate independent pair-sum errors through the solve
    pinv = np.linalg.pinv(A)
    sd_pairs = sums * np.sqrt(2.0 / dof_pair)
    sd = np.sqrt((pinv**2) @ (sd_pairs**2))
    ci = np.column_stack([np.maximum(variances - 1.96 * sd, 0.0), variances + 1.96 * sd])
    return RedundantEstimate(variances, ci, pair, n, notes)


def _somd_redundant(
    z: NDArray,
    notes: list[str],
    reference: ArrayLike | None = None,
    reference_variance: float = 0.0,
) -> VarianceEstimate:
    if reference is None:
        raise NoisevarError(
            "somd-redundant needs a second sensor: pass reference=<array> (CLI: --reference-column)"
        )
    return redundant_estimate(z, reference, reference_variance, notes)


SOMD_REDUNDANT = MethodSpec(
    "somd-redundant",
    "SOMD with a real second sensor, eq. 8",
    "somd",
    _somd_redundant,
    ("reference", "reference_variance"),
    needs_reference=True,
)


#: A pair of columns is flagged as not measuring one quantity when their difference's level
#: or spread, or a redundant R against its single-signal R, is off by more than this factor.
MISMATCH_RATIO = 4.0


def same_quantity_notes(
    sensors: ArrayLike,
    names: list[str],
    single_variances: ArrayLike,
    redundant_variances: ArrayLike | None = None,
) -> list[str]:
    """Why the columns may not measure the same quantity (empty when nothing says so).

    Two sensors of one quantity differ by their noises (and a constant bias): the
    difference ``z_i - z_j`` has variance ``R_i + R_j`` (their single-signal R), and each
    redundant R stays near its single-signal R. A pair is flagged when

    - the spread of ``z_i - z_j`` about its mean exceeds :data:`MISMATCH_RATIO` times
      ``R_i + R_j`` (the difference carries signal: another quantity, axis or unit, or a
      delay);
    - its mean level exceeds :data:`MISMATCH_RATIO` noise std ``sqrt(R_i + R_j)`` (an
      offset: another quantity, or a bias to remove);
    - with three sensors or more (a pair's redundant R is their sum, the spread above), a
      redundant R is more than :data:`MISMATCH_RATIO` times its single-signal R, or less
      than its inverse.

    Parameters
    ----------
    sensors : array_like, shape (n, m)
        One column per sensor.
    names : list of str
        The columns' names.
    single_variances : array_like, shape (m,)
        Each column's single-signal R (NaN where there is none).
    redundant_variances : array_like, shape (m,), optional
        The redundant estimate's R per sensor.

    Returns
    -------
    list of str
    """
    z = np.asarray(sensors, dtype=float)
    r = np.asarray(single_variances, dtype=float)
    notes: list[str] = []
    m = z.shape[1]
    for i in range(m):
        for j in range(i + 1, m):
            noise = r[i] + r[j]
            if not (np.isfinite(noise) and noise > 0):
                continue
            d = z[:, i] - z[:, j]
            d = d[np.isfinite(d)]
            spread, level = float(np.var(d)), abs(float(np.mean(d)))
            if spread > MISMATCH_RATIO * noise:
                notes.append(
                    f"{names[i]} - {names[j]} varies {spread / noise:.3g}x more than their noise "
                    "allows: they do not measure the same quantity (or a delay separates them)"
                )
            if level > MISMATCH_RATIO * np.sqrt(noise):
                notes.append(
                    f"{names[i]} and {names[j]} differ in level by {level / np.sqrt(noise):.3g} "
                    "noise std: another quantity or unit, or a bias to remove"
                )
    if redundant_variances is not None and m >= 3:  # a pair gives only their sum, checked above
        ratio = np.asarray(redundant_variances, dtype=float) / r
        for name, q in zip(names, ratio, strict=True):
            if np.isfinite(q) and (q > MISMATCH_RATIO or q < 1.0 / MISMATCH_RATIO):
                notes.append(f"{name}'s redundant R is {q:.3g}x its single-signal R")
    return notes


#: Rows read from each column to tell which measure one quantity (its first ones).
SAME_QUANTITY_ROWS = 20_000
#: A column follows a signal when its variance is at least this many times its noise's.
SIGNAL_SHARE = 2.0


def same_quantity_columns(
    columns: dict[str, NDArray], units: dict[str, str] | None = None, most: int = 3
) -> list[str]:
    """Up to ``most`` columns that look like sensors of one quantity, else none.

    Two sensors of one quantity differ by their noises: a pair passes when the spread of
    ``z_i - z_j`` and its mean level are within :func:`same_quantity_notes`' bounds
    (:data:`MISMATCH_RATIO` times ``R_i + R_j``, and its square root), each R read as
    ``var(Δ²z) / 6`` on the first :data:`SAME_QUANTITY_ROWS` rows, and each column follows
    a signal (its variance at least :data:`SIGNAL_SHARE` times its noise: columns of noise
    alone, a still IMU's axes or a logger's sample interval, pass any such test). The x, y
    and z axes of one moving sensor, or a signal beside its integral, fail. The pair whose
    difference is nearest its noise is taken, then each column that passes with every one taken; a
    column of another declared unit never joins.

    Parameters
    ----------
    columns : dict of str to ndarray
        Candidate columns (finite, of one length), in the table's order.
    units : dict of str to str, optional
        Each column's declared unit, where it has one.
    most : int
        At most this many columns.

    Returns
    -------
    list of str
        In the table's order; empty when no pair passes (the page then asks for them).
    """
    names = list(columns)
    if len(names) < 2:
        return []
    z = np.array([np.asarray(columns[c], dtype=float)[:SAME_QUANTITY_ROWS] for c in names])
    noise = np.var(np.diff(z, 2, axis=1), axis=1) / 6.0 if z.shape[1] > 3 else np.zeros(len(z))
    signal = np.var(z, axis=1) >= SIGNAL_SHARE * noise  # a signal to follow, not noise alone
    units = units or {}
    m = len(names)
    ratio = np.full((m, m), np.inf)
    for i in range(m):
        for j in range(i + 1, m):
            a, b = units.get(names[i]), units.get(names[j])
            both = noise[i] + noise[j]
            if (a and b and a != b) or not both > 0 or not (signal[i] and signal[j]):
                continue
            d = z[i] - z[j]
            spread, level = float(np.var(d)) / both, abs(float(np.mean(d))) / np.sqrt(both)
            if spread <= MISMATCH_RATIO and level <= MISMATCH_RATIO:
                ratio[i, j] = ratio[j, i] = spread
    i, j = np.unravel_index(int(np.argmin(ratio)), ratio.shape)
    if not np.isfinite(ratio[i, j]):
        return []
    chosen = [int(i), int(j)]
    while len(chosen) < most:
        worst = ratio[:, chosen].max(axis=1)
        worst[chosen] = np.inf
        k = int(np.argmin(worst))
        if not np.isfinite(worst[k]):
            break
        chosen.append(k)
    return [names[k] for k in sorted(chosen)]

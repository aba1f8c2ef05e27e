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

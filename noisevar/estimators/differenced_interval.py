"""R's interval on differenced data: a block jackknife of the corrected statistic (§E2).

R on differenced (MA(q)) noise is the white-noise estimate divided by
``1 + 2 Σ_j r_j α_j(d)`` (:func:`~noisevar.estimators.interval.differenced`), ``r`` fitted
on the diagnostic residual's autocorrelation. Both are read off the same samples, so
their errors are not independent: the interval comes from the whole corrected statistic
recomputed with one block of the record left out at a time (the delete-one-block
jackknife; Künsch 1989), summed per block in one pass, so a streamed record reads each
block once and gives the same numbers.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import replace

import numpy as np
from numpy.typing import NDArray
from scipy import special

from noisevar.diagnostics import NoiseDiagnostics
from noisevar.diagnostics.plan import DIAG_ORDER, DIAG_SPAN
from noisevar.estimators.interval import _lag_alpha
from noisevar.estimators.results import VarianceEstimate
from noisevar.numeric.fir import lagged_products, residual_sequence

#: Blocks the record is cut into; each is left out once.
JACK_BLOCKS = 40
#: Fewest samples per block (times the longer filter's length): shorter records keep the
#: interval :func:`~noisevar.estimators.interval.honest_interval` gives.
BLOCK_FILTERS = 4
#: Lags of the diagnostic residual past each block a block's length allows for (the MA
#: fits use at most ``q + 2``; every lag the whiteness test has is summed: the AR(1) fit's).
FIT_LAGS = 6


def _block_sums(
    read: Callable[[int, int], NDArray], n: int, d: NDArray, u: NDArray, blocks: int, lags: int
) -> tuple[NDArray, NDArray, NDArray, NDArray]:
    """Per block: ``Σ e²`` and its count for ``e = d * z``; ``Σ u_i u_{i+k}`` (``k = 0..
    lags``, the lags the whiteness test has) and their pair counts for the diagnostic
    residual ``u = dd * z``.

    Each residual belongs to the block of its first sample; a pair to that of its first.
    """
    me, mu = n - d.size + 1, n - u.size + 1  # residuals of each filter
    edges = np.linspace(0, n, blocks + 1).astype(int)
    se, ne = np.zeros(blocks), np.zeros(blocks)
    su, nu = np.zeros((blocks, lags + 1)), np.zeros((blocks, lags + 1))
    k = np.arange(lags + 1)
    for b, (a, c) in enumerate(zip(edges[:-1], edges[1:], strict=True)):
        z = np.asarray(read(a, min(n, c + max(d.size, u.size + lags) - 1)), dtype=float)
        e = np.convolve(z, d[::-1], mode="valid")[: max(min(c, me) - a, 0)]
        se[b], ne[b] = lagged_products(e, 0)[0], e.size  # (a BLAS dot: threads woken per block)
        x = np.convolve(z, u[::-1], mode="valid")[: max(min(c + lags, mu) - a, 0)]
        own = max(min(c, mu) - a, 0)  # pairs starting in this block
        su[b] = lagged_products(x, lags) - _tails(x, own, lags)
        nu[b] = np.maximum(np.minimum(own, x.size - k), 0)
    return se, ne, su, nu


def _tails(x: NDArray, own: int, lags: int) -> NDArray:
    """``Σ x_i x_{i+k}`` over the pairs whose first member is past ``own`` (another block's)."""
    rest = x[own:]
    return lagged_products(rest, lags) if rest.size else np.zeros(lags + 1)


def _corrected(
    se: NDArray, ne: NDArray, su: NDArray, nu: NDArray, diag: NoiseDiagnostics, alpha: NDArray
) -> NDArray:
    """The corrected statistic ``mean(e²) / (1 + 2 r·α)`` of each row of sums, ``r``
    refitted on each row by the record's own model
    (:meth:`~noisevar.diagnostics.NoiseDiagnostics.refit_correlation`)."""
    gamma = su / np.maximum(nu, 1.0)
    acf = gamma[:, 1:] / gamma[:, :1]
    w = diag.whiteness  # its null (the filter's own correlation) at every lag it has
    r = np.array([diag.refit_correlation(replace(w, acf=row)) for row in acf])
    return se / ne / (1.0 + 2.0 * r @ alpha)


def jackknife_interval(
    result: VarianceEstimate,
    read: Callable[[int, int], NDArray] | None,
    diag: NoiseDiagnostics,
    d: NDArray,
) -> VarianceEstimate:
    """``result`` (already corrected for differenced noise) with the block jackknife's interval.

    Parameters
    ----------
    result : VarianceEstimate
        The corrected estimate; its variance is kept.
    read : callable or None
        ``read(a, b)``: samples ``a .. b`` of the one-segment record (None: ``result``
        is returned as it is).
    diag : NoiseDiagnostics
        The record's diagnostics (differenced: ``noise_correlation`` not None).
    d : ndarray
        R's residual filter.

    Returns
    -------
    VarianceEstimate
        ``ci95`` ``R exp(± t se)``: ``se²`` the jackknife's variance of ``log R``, ``t``
        Student's 97.5 % quantile on ``blocks - 1`` dof; ``dof`` ``2 / se²`` (a χ²'s of
        that spread); and a note.

    Notes
    -----
    docs/algorithms.md §E2 *The interval on differenced data*.
    """
    u = residual_sequence(DIAG_SPAN, DIAG_ORDER)
    n = diag.n
    blocks = min(JACK_BLOCKS, n // (BLOCK_FILTERS * max(d.size, u.size + FIT_LAGS)))
    if read is None or blocks < JACK_BLOCKS // 2 or diag.whiteness.expected.size < FIT_LAGS:
        return result
    se, ne, su, nu = _block_sums(read, n, d, u, blocks, diag.whiteness.expected.size)
    alpha = _lag_alpha(d, diag.noise_correlation.size)
    drop = _corrected(se.sum() - se, ne.sum() - ne, su.sum(0) - su, nu.sum(0) - nu, diag, alpha)
    if not np.all(np.isfinite(drop) & (drop > 0)):
        return result
    log = np.log(drop)
    var = (blocks - 1) / blocks * float(np.sum((log - log.mean()) ** 2))
    if not var > 0:
        return result
    half = float(special.stdtrit(blocks - 1, 0.975)) * np.sqrt(var)  # the jackknife's dof
    ci = (result.variance * float(np.exp(-half)), result.variance * float(np.exp(half)))
    note = (
        f"R's interval on differenced data is the block jackknife's ({blocks} blocks): the "
        "fitted correlation's error is in it"
    )
    return replace(result, dof=2.0 / var, ci95=ci, notes=[*result.notes, note])

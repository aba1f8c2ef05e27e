"""``auto``: a robust zero-lag polynomial virtual sensor (docs/algorithms.md §F5).

The residual of a centred local polynomial (§F5.1) replaces SOMD's lagging
alpha-beta-gamma prediction; each block of samples takes the longest span that does
not leak signal (§F5.2); jumps (§F5.3) and outliers (§F5.4) are trimmed and the
trimmed mean corrected; §F5.5 gives the estimate and its degrees of freedom.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray
from scipy.ndimage import maximum_filter1d

from noisevar._distributions import norm_cdf, norm_pdf
from noisevar.errors import NoisevarError
from noisevar.estimators._blocks import (
    _block_counts,
    _block_medians,
    _block_square_sums,
    _block_sums,
    _dilate,
    _flagged_per_block,
    _kept_block_sums,
)
from noisevar.estimators._steps import STEP_MAX_FRACTION, _step_mask
from noisevar.estimators.difference import sequence_efficiency
from noisevar.estimators.params import AUTO_ORDER, AUTO_TRIM, MethodSpec
from noisevar.estimators.results import VarianceEstimate, chi2_interval

try:  # compiled residual filters (numba); np.convolve below is the reference
    from noisevar.filters import _fir
except ImportError:  # pragma: no cover - numba not installed
    _fir = None

#: Filter with the compiled kernel of :mod:`noisevar.filters._fir` while this is true
#: (and numba is installed); false selects ``np.convolve`` (the same filter, to rounding).
USE_COMPILED: bool = _fir is not None

AUTO_SPANS = (11, 21, 41, 81)
#: Trimmed samples are widened by half of this span (or of the longest span below it).
AUTO_MASK_SPAN = 41
AUTO_BLOCK = 256
AUTO_LEAK_SE = 3.5
#: The span used on noise that is not white: the shortest, which lets the least of a
#: coloured part (flicker, random walk) into the residual (docs/algorithms.md §F5.6).
AUTO_COLOURED_SPAN = 5


@lru_cache(maxsize=64)
def residual_sequence(span: int, order: int) -> NDArray:
    """Difference sequence ``δ - w`` of a centred local-polynomial (Savitzky-Golay) fit.

    Parameters
    ----------
    span : int
        Odd number of samples of each local fit.
    order : int
        Polynomial degree; the residual is blind to polynomials up to it.

    Returns
    -------
    ndarray, shape (span,)
    """
    h = span // 2
    # w = row h of the hat matrix P = Q Q' of a polynomial fit over the centred window
    # (the Savitzky-Golay smoothing coefficients, as scipy.signal.savgol_coeffs)
    q, _ = np.linalg.qr(np.vander((np.arange(span, dtype=float) - h) / max(h, 1), order + 1))
    w = q @ q[h]
    d = -0.5 * (w + w[::-1])  # exactly symmetric (the fit is to about 1e-15)
    d[h] += 1.0
    d.setflags(write=False)
    return d


@lru_cache(maxsize=64)
def _difference_variance_factor(span_a: int, span_b: int, order: int) -> float:
    """``sum_k (ρ_aa² + ρ_bb² - 2 ρ_ab²)``: n·var(v_a - v_b)/(2σ⁴) for two residual estimators."""
    da = residual_sequence(span_a, order)
    db = residual_sequence(span_b, order)
    da = da / np.sqrt(np.sum(da**2))
    db = db / np.sqrt(np.sum(db**2))
    raa = np.correlate(da, da, mode="full")
    rbb = np.correlate(db, db, mode="full")
    rab = np.correlate(da, db, mode="full")
    return float(np.sum(raa**2) + np.sum(rbb**2) - 2.0 * np.sum(rab**2))


@lru_cache(maxsize=64)
def _edge_residual_rows(span: int, order: int) -> tuple[NDArray, NDArray]:
    """Rows of ``I - P`` for the first and last ``span // 2`` samples of a ``span`` window.

    ``P`` is the hat matrix of a polynomial fit of degree ``order`` over the
    window; row ``h = span // 2`` is the interior sequence ``d``. The edge rows
    let the estimator use every sample, not only those a centred span fits.
    """
    h = span // 2
    i = np.arange(span, dtype=float) - h
    v = np.vander(i / max(h, 1), order + 1)
    q, _ = np.linalg.qr(v)
    resid = np.eye(span) - q @ q.T
    head, tail = resid[:h].copy(), resid[span - h :].copy()
    head.setflags(write=False)
    tail.setflags(write=False)
    return head, tail


def _residual_squares(z: NDArray, span: int, order: int, out: NDArray | None = None) -> NDArray:
    """Normalised squared residuals ``e_k² / (I - P)_kk`` of a local polynomial, every sample.

    Interior samples use the centred sequence ``d`` (``d / |d|``, symmetric:
    the compiled kernel of :mod:`noisevar.filters._fir` when :data:`USE_COMPILED`,
    else one ``np.convolve``, squared straight into ``out``); the first and last
    ``span // 2`` use the one-sided fit over the first (last) ``span``
    samples, so each square has expectation ``σ_k²`` for noise whose variance
    is locally constant.
    """
    n = z.size
    d = residual_sequence(span, order)
    h = span // 2
    out = np.empty(n) if out is None else out
    unit = d / np.sqrt(np.sum(d**2))
    if USE_COMPILED and _fir is not None:
        _fir.symmetric_fir_squares(np.ascontiguousarray(z), unit[h:].copy(), out[h : n - h])
    else:
        e = np.convolve(z, unit[::-1], mode="valid")
        np.multiply(e, e, out=out[h : n - h])
    head, tail = _edge_residual_rows(span, order)
    out[:h] = (head @ z[:span]) ** 2 / np.diag(head[:, :h])
    out[n - h :] = (tail @ z[n - span :]) ** 2 / np.diag(tail[:, span - h :])
    return out


def _truncated_second_moment(kappa: float) -> float:
    """``E[Z² ; |Z| < κ] / P(|Z| < κ)`` for a standard normal ``Z``."""
    p = 2.0 * norm_cdf(kappa) - 1.0
    return float((p - 2.0 * kappa * norm_pdf(kappa)) / p)


def _above_local(x: NDArray, local: NDArray, block: int) -> NDArray:
    """``x`` above the larger local level of the two block centres around each sample.

    Block ``j``'s level holds at its centre ``(j + 1/2) block``; a sample is
    compared with the larger of the levels of the two centres around it (the
    rest of the record after the last block with the last level), so that near a
    change of noise level the threshold is the louder side's (§F5.4). One
    blockwise comparison with the block's own level (a lower bound) finds the few
    candidates; only those are compared with the bracketing level.
    """
    n, nb = x.size, local.size
    hit = np.empty(n, dtype=bool)
    np.greater(
        x[: nb * block].reshape(nb, block), local[:, None], out=hit[: nb * block].reshape(nb, block)
    )
    np.greater(x[nb * block :], local[-1], out=hit[nb * block :])
    idx = np.flatnonzero(hit)
    if idx.size and nb > 1:
        own = np.minimum(idx // block, nb - 1)
        side = np.where(idx - own * block < block // 2, own - 1, own + 1)
        side = np.clip(side, 0, nb - 1)  # the rest of the record: the last block's level
        hit[idx[x[idx] <= np.maximum(local[own], local[side])]] = False
    return hit


def _outlier_mask(
    sq: NDArray,
    kappa: float,
    block: int,
    dilate: int,
    steps: Callable[[Callable[[NDArray], NDArray], float], NDArray] | None,
) -> tuple[NDArray | None, NDArray | None]:
    """Squared residuals that are outliers, and samples next to jumps (the caller widens both).

    Pass 1 takes a robust local scale from block medians of ``e²`` (every
    fourth sample: plenty for a scale whose only use is a generous
    threshold); pass 2 refines it with the mean of each block's kept squares,
    so that a noise level changing along the record is followed (a noise step
    is not mistaken for outliers). Residuals beyond ``κ`` local standard
    deviations are flagged, and so are samples next to a jump found by
    ``steps(above, κ²)`` (:func:`_step_mask`). Pass 1 leaves ``dilate``
    neighbours on each side of what it flags out of the scale (a jump spreads
    over the whole span of the residual sequence); the returned mask is not
    widened, so that the caller can widen it by each span's half. Each is
    None when nothing is flagged (the common case, which then costs no
    masking).
    """
    n = sq.size
    nb = max(1, n // block)
    scale = kappa**2 / 0.4549364231195724  # the median of χ²₁ is 0.4549
    threshold = _block_medians(sq, block, nb, 4) * scale
    first = np.empty(n, dtype=bool)
    np.greater(
        sq[: nb * block].reshape(nb, block),
        threshold[:, None],
        out=first[: nb * block].reshape(nb, block),
    )
    np.greater(sq[nb * block :], threshold[-1], out=first[nb * block :])
    tau = _truncated_second_moment(kappa)
    kept_n = _block_counts(block, nb, n)
    if first.any():
        if dilate > 0:  # leave the whole neighbourhood of a jump out of the scale
            first = _dilate(first, dilate)
        idx = np.flatnonzero(first)
        kept_sum = _kept_block_sums(sq, idx, block, nb)
        kept_n -= _flagged_per_block(idx, block, nb)
    else:
        kept_sum = _block_sums(sq, block, nb)
    # κ² times the local variance of each block (held at its centre; see _above_local)
    threshold = kappa**2 * kept_sum / np.maximum(kept_n, 1.0) / tau

    def above(x: NDArray) -> NDArray:
        return _above_local(x, threshold, block)

    outlier = above(sq)
    jumps = None
    if steps is not None:
        found = steps(above, kappa**2)
        if 0 < np.count_nonzero(found) <= STEP_MAX_FRACTION * n:  # else the signal is too fast
            jumps = found
    return (outlier if outlier.any() else None), jumps


def _near_flagged(
    flagged: NDArray, idx: NDArray, spans: tuple[int, ...], half: int, sq: NDArray
) -> tuple[NDArray, NDArray, NDArray] | None:
    """Samples of the common mask ``idx`` that a shorter span can still use.

    The common mask widens flagged samples by ``half``; the residual of a
    span ``s`` at sample ``k`` reaches ``s // 2`` samples either way, so a
    sample more than ``s // 2`` from every flagged one has a clean residual
    for that span. Returns the indices of such samples, the longest usable
    span index of each, and their squared residuals for the spans up to it
    (before the caller zeroes the masked ones), or None.
    """
    usable = np.full(idx.size, -1)
    for j, s in enumerate(spans):
        if s // 2 >= half:
            break
        usable[~_dilate(flagged, s // 2)[idx]] = j
    keep = usable >= 0
    if not keep.any():
        return None
    near = idx[keep]
    return near, usable[keep], sq[: int(usable.max()) + 1, near].copy()


def _auto_spans(span: int | None, order: int, trim: float, n: int) -> tuple[int, ...]:
    """The candidate spans (§F5.2), after checking ``order``, ``trim`` and ``span``."""
    if not 1 <= order <= 6:
        raise NoisevarError(f"order must be between 1 and 6, got {order}")
    if not trim > 1.0:
        raise NoisevarError(f"trim must be above 1 (standard deviations), got {trim}")
    if span is not None:
        if span % 2 == 0 or span <= order + 1:
            raise NoisevarError(f"span must be odd and larger than order + 1, got {span}")
        spans: tuple[int, ...] = (span,)
    else:
        spans = tuple(s for s in AUTO_SPANS if s > order + 1)
        spans = tuple(s for s in spans if 4 * s <= n) or spans[:1]
    if n < 2 * max(spans):
        raise NoisevarError(
            f"too few samples ({n}) for the auto estimator: give at least {2 * max(spans)}"
        )
    return spans


@dataclass
class _Blocks:
    """Per-block sums of every span's squared residuals, after trimming (§F5.4)."""

    block: int
    nb: int
    kept_count: NDArray  # (nb,) samples kept per block
    block_sum: NDArray  # (n_spans, nb)
    fourth: NDArray  # (nb,) sums of the shortest span's e⁴
    clean_for: NDArray  # (n_spans, nb) span j's residuals untouched by a flagged sample
    recover: tuple[NDArray, NDArray, NDArray] | None  # see _near_flagged
    total_count: NDArray  # (nb,) samples off the jumps (outliers kept: they are noise)
    total_sum: NDArray  # (n_spans, nb) their sums
    outliers: NDArray  # samples that are outliers (one per spike)
    clean_total: NDArray  # (n_spans, nb) as clean_for, for the jumps alone
    recover_total: tuple[NDArray, NDArray, NDArray] | None  # as recover, near the jumps
    jumps: NDArray  # samples left out around jumps (widened; all False when none)


def _flag(z: NDArray, sq0: NDArray, trim: float, block: int, half: int) -> tuple:
    """Outliers and jumps of the record (None when none), from the shortest span's squares."""
    if not np.isfinite(trim):
        return None, None
    return _outlier_mask(sq0, trim, block, half, lambda var, sc: _step_mask(z, var, sc))


def _zero(sq: NDArray, flags: NDArray | None, half: int, block: int, nb: int) -> NDArray:
    """Zero the squares within ``half`` of ``flags`` in place; the samples left out per block."""
    if flags is None:
        return np.zeros(nb)
    idx = np.flatnonzero(_dilate(flags, half) if half > 0 else flags)
    if idx.size == sq.shape[1]:
        raise NoisevarError("every residual was trimmed as an outlier: the signal is not usable")
    sq[:, idx] = 0.0
    return _flagged_per_block(idx, block, nb)


def _recoverable(
    flags: NDArray | None, spans: tuple[int, ...], half: int, sq: NDArray
) -> tuple[NDArray, NDArray, NDArray] | None:
    """:func:`_near_flagged` for the mask of ``flags`` widened by ``half`` (None: no flags)."""
    if flags is None:
        return None
    idx = np.flatnonzero(_dilate(flags, half) if half > 0 else flags)
    return _near_flagged(flags, idx, spans, half, sq)


def _trimmed_blocks(z: NDArray, sq: NDArray, spans: tuple[int, ...], trim: float) -> _Blocks:
    """Flag jumps and outliers, zero their neighbourhoods in ``sq`` and sum the blocks.

    Block sums are taken twice: with only the jumps left out (the total variance:
    outliers are noise) and with outliers left out too (the core, §F5.4).
    """
    m = z.size
    block = AUTO_BLOCK if m >= 2 * AUTO_BLOCK else max(m // 2, 16)
    nb = max(1, m // block)
    # flagged samples are widened by half the longest span up to AUTO_MASK_SPAN; a
    # longer span is used only in blocks that its wider neighbourhood leaves alone
    half = max(s for s in spans if s <= max(AUTO_MASK_SPAN, spans[0])) // 2
    outliers, jumps = _flag(z, sq[0], trim, block, half)
    sq0_copy = sq[0].copy() if outliers is not None else sq[0]
    flagged = jumps if outliers is None else outliers if jumps is None else outliers | jumps
    # before any zeroing: the values near flagged samples (and near jumps, for the total)
    recover = _recoverable(flagged, spans, half, sq)
    recover_total = _recoverable(jumps, spans, half, sq)
    total_count = _block_counts(block, nb, m) - _zero(sq, jumps, half, block, nb)
    total_sum = np.stack([_block_sums(q, block, nb) for q in sq])
    kept_count = _block_counts(block, nb, m) - _zero(sq, flagged, half, block, nb)
    block_sum = np.stack([_block_sums(q, block, nb) for q in sq])
    fourth = _block_square_sums(sq[0], block, nb)
    # one outlying sample spreads over its neighbours' residuals: count the peaks
    peaks = sq[0] if outliers is None else maximum_filter1d(sq0_copy, spans[0])
    out_at = np.zeros(0, dtype=int)
    if outliers is not None:  # residuals next to a jump are the jump's, not outliers
        alone = outliers if jumps is None else outliers & ~_dilate(jumps, half)
        out_at = np.flatnonzero(alone & (sq0_copy == peaks))
    return _Blocks(
        block, nb, kept_count, block_sum, fourth, _clean_for(flagged, spans, half, block, nb),
        recover, total_count, total_sum, out_at, _clean_for(jumps, spans, half, block, nb),
        recover_total, np.zeros(m, dtype=bool) if jumps is None else _dilate(jumps, half),
    )  # fmt: skip


def _clean_for(
    flags: NDArray | None, spans: tuple[int, ...], half: int, block: int, nb: int
) -> NDArray:
    """Per span and block: no flagged sample within the span's reach beyond the mask's."""
    clean = np.ones((len(spans), nb), dtype=bool)
    if flags is None:
        return clean
    per_block = _flagged_per_block(np.flatnonzero(_dilate(flags, half)), block, nb)
    for j, s in enumerate(spans):
        if s // 2 > half:
            wide = _flagged_per_block(np.flatnonzero(_dilate(flags, s // 2)), block, nb)
            clean[j] = wide == per_block
    return clean


def _choose_spans(
    b: _Blocks, spans: tuple[int, ...], order: int, clean_for: NDArray | None = None
) -> NDArray:
    """Each block's span index: lengthen while the mean square does not leak (§F5.2).

    ``clean_for`` (default ``b.clean_for``) says where a span's reach is free of flagged
    samples.
    """
    clean_for = b.clean_for if clean_for is None else clean_for
    with np.errstate(invalid="ignore", divide="ignore"):
        block_mean = b.block_sum / b.kept_count
        rms4 = np.sqrt(b.fourth / b.kept_count / 3.0)  # = σ² for Gaussian noise
    choice = np.zeros(b.nb, dtype=int)
    open_ = np.ones(b.nb, dtype=bool)  # still lengthening the span in this block
    for j in range(1, len(spans)):
        with np.errstate(invalid="ignore", divide="ignore"):  # a block may be all trimmed
            # se = σ² sqrt(2 n var-factor / n_kept) of the difference of two spans' means
            se = rms4 * np.sqrt(
                2.0 * _difference_variance_factor(spans[j - 1], spans[j], order) / b.kept_count
            )
        ok = open_ & clean_for[j] & (block_mean[j] - block_mean[j - 1] <= AUTO_LEAK_SE * se)
        if spans[j] > AUTO_MASK_SPAN and b.nb > 1:
            # a long span reaches into the neighbouring blocks: only where they are smooth
            # too (a fast burst next door leaks into the first samples of this block)
            smooth = choice >= j - 1
            ok[1:] &= smooth[:-1]
            ok[:-1] &= smooth[1:]
        choice[ok] = j
        open_ &= ok
    return choice


def _chosen_sums(b: _Blocks, choice: NDArray, total: bool = False) -> tuple[NDArray, NDArray]:
    """Per-block sums and counts with the chosen spans, masked samples recovered.

    ``total``: the sums with only the jumps left out (outliers kept), else the core's.
    """
    sums, counts, recover = (
        (b.total_sum, b.total_count, b.recover_total)
        if total
        else (b.block_sum, b.kept_count, b.recover)
    )
    chosen_sum = sums[choice, np.arange(b.nb)]
    if recover is not None:
        # samples the common mask left out whose shorter-span residual reaches no flagged
        # sample count with that span (at most the block's own)
        near, usable, values = recover
        rows = np.minimum(near // b.block, b.nb - 1)
        use = np.minimum(choice[rows], usable)
        chosen_sum = chosen_sum + np.bincount(
            rows, weights=values[use, np.arange(near.size)], minlength=b.nb
        )
        counts = counts + np.bincount(rows, minlength=b.nb)
    return chosen_sum, counts


def _auto_notes(
    n: int, n_kept: int, spans: tuple[int, ...], choice: NDArray, kept_count: NDArray, block: int
) -> list[str]:
    notes = []
    trimmed = n - n_kept
    if trimmed > 0.01 * n:
        notes.append(f"{trimmed} residuals ({trimmed / n:.1%}) left out around level jumps")
    short = float(np.sum(kept_count[choice < len(spans) - 1]) / max(n_kept, 1))
    if len(spans) > 1 and short > 0.05:
        notes.append(
            f"{short:.0%} of the record needed a shorter span (a fast signal, or noise that "
            "is not white)"
        )
    if len(spans) > 1:
        span_used = np.asarray(spans)[choice]
        mean_span = float(np.sum(span_used * kept_count) / max(n_kept, 1))
        notes.append(f"span chosen per block of {block} samples: mean {mean_span:.1f}")
    return notes


def auto_estimate(
    z: NDArray,
    *,
    span: int | None = None,
    order: int = AUTO_ORDER,
    trim: float = AUTO_TRIM,
    notes: list[str] | None = None,
) -> VarianceEstimate:
    """Our default: a zero-lag polynomial virtual sensor, exact normalisation, local span, trimming.

    Parameters
    ----------
    z : ndarray
        Validated samples.
    span : int, optional
        Fix one span instead of choosing per block (odd, > order + 1).
    order : int
        Polynomial degree of the virtual sensor (1 to 6).
    trim : float
        Trimming threshold in local standard deviations (``inf``: none).
    notes : list of str, optional
        Remarks carried into the result.

    Returns
    -------
    VarianceEstimate
        ``params["span"]`` is the requested span (None: chosen per block, and a note
        gives the sample-weighted mean span used), so that ``estimate(z, **params)``
        reproduces the estimate.

    Notes
    -----
    docs/algorithms.md §F5: residuals ``e = d * z`` of a centred local polynomial
    (§F5.1), spans per block (§F5.2), jump and outlier trimming with the
    truncated-moment correction ``τ`` (§F5.3, §F5.4), and
    ``var = sum e² / (n_kept τ)`` with ``sum_blocks n_b / sum ρ²`` degrees of freedom
    (§F5.5).
    """
    notes = list(notes or [])
    order, trim = int(order), float(trim)
    span = None if span is None else int(span)
    n = z.size
    spans = _auto_spans(span, order, trim, n)
    sq = np.empty((len(spans), n))
    for j, s in enumerate(spans):
        _residual_squares(z, s, order, out=sq[j])
    blocks = _trimmed_blocks(z, sq, spans, trim)
    choice = _choose_spans(blocks, spans, order)
    chosen_sum, kept_count = _chosen_sums(blocks, choice)
    n_kept = int(kept_count.sum())
    tau = _truncated_second_moment(trim) if np.isfinite(trim) else 1.0
    # core = sum e² / (n_kept τ) over the samples off outliers and jumps
    core = float(chosen_sum.sum() / (n_kept * tau))
    # outliers stay in the total: a span needs only to stay clear of the jumps
    choice = _choose_spans(blocks, spans, order, blocks.clean_total)
    total_sum, total_count = _chosen_sums(blocks, choice, total=True)
    n_total = int(total_count.sum())
    # var = sum e² / n over the samples off the jumps: outliers and tails are noise
    var = float(total_sum.sum() / n_total)
    eff = np.asarray([sequence_efficiency(residual_sequence(s, order)) for s in spans])[choice]
    # ν = sum_b n_b / sum ρ² (Gaussian noise; estimate() widens it for the measured tails)
    dof = float(np.sum(total_count / eff))
    notes += _auto_notes(n, n_total, spans, choice, total_count, blocks.block)
    if blocks.outliers.size:
        k = blocks.outliers.size
        notes.append(
            f"{k} outlying sample{'s' if k > 1 else ''} ({k / n:.2%}; the first at sample "
            f"{blocks.outliers[0]}): noise, so in the variance; left out of core_variance"
        )
    # params are the config form: the requested span, None when it is chosen per block
    params = {"span": span, "order": order, "trim": trim}
    return VarianceEstimate(
        "auto",
        var,
        chi2_interval(var, dof),
        n_total,
        n,
        dof,
        params,
        notes,
        core_variance=core,
        outlier_fraction=blocks.outliers.size / n,
        jumps=blocks.jumps,
    )


def _auto(z: NDArray, notes: list[str], **p: object) -> VarianceEstimate:
    return auto_estimate(z, notes=notes, **p)


AUTO = MethodSpec(
    "auto",
    "robust zero-lag polynomial virtual sensor (our default)",
    "ours",
    _auto,
    ("span", "order", "trim"),
    coloured_params={"span": AUTO_COLOURED_SPAN},
)


def jump_mask(z: NDArray, order: int = AUTO_ORDER, trim: float = AUTO_TRIM) -> NDArray | None:
    """Samples that ``auto`` leaves out around persistent level jumps (None when none).

    Parameters
    ----------
    z : ndarray, shape (n,)
        Finite samples (at least 22).
    order, trim : see :func:`auto_estimate`.

    Returns
    -------
    ndarray of bool or None
        Jump samples widened by the mask half-width (docs/algorithms.md §F5.3, §F5.4).
    """
    spans = _auto_spans(None, order, trim, z.size)
    block = AUTO_BLOCK if z.size >= 2 * AUTO_BLOCK else max(z.size // 2, 16)
    half = max(s for s in spans if s <= max(AUTO_MASK_SPAN, spans[0])) // 2
    _, jumps = _flag(z, _residual_squares(z, spans[0], order), trim, block, half)
    return None if jumps is None else _dilate(jumps, half)

"""``auto``'s estimator: a robust zero-lag polynomial virtual sensor (docs/algorithms.md §F5).

The residual of a centred local polynomial (§F5.1) replaces SOMD's lagging
alpha-beta-gamma prediction; each block of samples takes the longest span that does
not leak signal (§F5.2); jumps (§F5.3) and outliers (§F5.4) are trimmed and the
trimmed mean corrected; §F5.5 gives the estimate and its degrees of freedom.
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from functools import lru_cache

import numpy as np
from numpy.typing import NDArray

from noisevar.diagnostics import NoiseDiagnostics
from noisevar.diagnostics.tails import kurtosis_from_moments
from noisevar.errors import NoisevarError
from noisevar.estimators.auto._edges import (
    detection_squares,
    edge_glitches,
    edge_residual_rows,
)
from noisevar.estimators.auto._trim import (
    AUTO_CORE_TRIM,
    AUTO_MASK_SPAN,
    _Blocks,
    _flag,
    _trimmed_blocks,
    _truncated_second_moment,
    auto_block,
    core_trimmed,
)
from noisevar.estimators.difference import sequence_efficiency
from noisevar.estimators.params import AUTO_ORDER, AUTO_TRIM
from noisevar.estimators.pooling import outlier_note
from noisevar.estimators.results import VarianceEstimate, chi2_interval
from noisevar.numeric.blocks import dilate
from noisevar.numeric.fir import (
    ROUNDING_ULPS,
    centred_rows,
    residual_sequence,
    rounded_fir,
    rounded_fir_squares,
)

AUTO_SPANS = (11, 21, 41, 81)
AUTO_LEAK_SE = 3.5
#: The span used on noise that is not white: the shortest, which lets the least of a
#: coloured part (flicker, random walk) into the residual (docs/algorithms.md §F5.6).
AUTO_COLOURED_SPAN = 5
#: What the estimate of a record too short for the first of ``AUTO_SPANS`` assumes.
SHORT_SPAN_NOTE = (
    "a short record: the residual of a local polynomial of order {order} over {span} samples, "
    "which assumes white noise and a signal that such a polynomial follows over {span} "
    "samples; the interval is from its degrees of freedom"
)


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


def _residual_squares(
    z: NDArray, span: int, order: int, out: NDArray | None = None, peak: float | None = None
) -> NDArray:
    """Normalised squared residuals ``e_k² / (I - P)_kk`` of a local polynomial, every sample.

    Interior samples use the centred sequence ``d`` (``d / |d|``, symmetric, through
    :func:`~noisevar.numeric.fir.centred_fir`, squared straight into ``out``); the first
    and last ``span // 2`` use the one-sided fit over the first (last) ``span``
    samples, so each square has expectation ``σ_k²`` for noise whose variance
    is locally constant. Every residual is read from differences to its own sample: an
    offset cancels exactly and a held stretch gives exactly 0; one at float rounding
    (:func:`~noisevar.numeric.fir.rounded_off`: a held stretch plus a trend) is 0 too
    (issue 26). ``peak``: ``max |z|``, when the caller has it.
    """
    n = z.size
    h = span // 2
    out = np.empty(n) if out is None else out
    rounded_fir(z, _unit_sequence(span, order), out[h : n - h], square=True, peak=peak)
    _edge_squares(z, span, order, out)
    return out


def _unit_sequence(span: int, order: int) -> NDArray:
    """The residual sequence of ``span`` and ``order`` over its norm."""
    d = residual_sequence(span, order)
    return d / np.sqrt(np.sum(d**2))


def _every_span_squares(
    z: NDArray, spans: tuple[int, ...], order: int, out: NDArray, peak: float
) -> NDArray:
    """:func:`_residual_squares` of every span into the rows of ``out``, the filters at once.

    (:func:`~noisevar.numeric.fir.rounded_fir_squares`: the same numbers.)
    """
    rounded_fir_squares(z, [_unit_sequence(s, order) for s in spans], out, peak)
    for s, row in zip(spans, out, strict=True):
        _edge_squares(z, s, order, row)
    return out


def _edge_squares(z: NDArray, span: int, order: int, out: NDArray) -> None:
    """The first and last ``span // 2`` of :func:`_residual_squares`, into ``out``."""
    n, h = z.size, span // 2
    head, tail = edge_residual_rows(span, order)
    out[:h] = centred_rows(head, z[:span], np.arange(h)) ** 2 / np.diag(head[:, :h])
    at = np.arange(span - h, span)
    out[n - h :] = centred_rows(tail, z[n - span :], at) ** 2 / np.diag(tail[:, span - h :])
    for part, x in ((out[:h], z[:span]), (out[n - h :], z[n - span :])):
        part[part <= (ROUNDING_ULPS * np.finfo(float).eps * np.max(np.abs(x))) ** 2] = 0.0


def auto_spans(span: int | None, order: int, trim: float, n: int) -> tuple[int, ...]:
    """The candidate spans of a record of ``n`` samples (§F5.2), arguments checked."""
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
        if n < 2 * spans[0] and AUTO_COLOURED_SPAN > order + 1:
            spans = (AUTO_COLOURED_SPAN,)  # a short record (issue 26): the shortest span
    need = 2 * max(spans)  # coverage of the ci95 at 9 samples: 88-89 % (short_records)
    if n < need:
        raise NoisevarError(f"too few samples ({n}) for the auto estimator: give at least {need}")
    return spans


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


@dataclass
class AutoPart:
    """What ``auto`` sums over the blocks of one stretch of a record (§F5.5).

    A record is one part; a record streamed in chunks is one part per chunk, each
    computed from the chunk and an overlap on both sides, so that every block's
    numbers are those of the whole record.
    """

    n: int  # samples of the stretch
    core_sum: float  # Σ e² off outliers and jumps, chosen spans
    core_count: float
    total_sum: float  # Σ e² off the jumps
    total_count: float
    dof: float  # Σ_b n_b / Σρ²_b
    short: float  # samples in blocks that needed a shorter span than the longest
    span_weight: float  # Σ_b span_b n_b
    outliers: NDArray  # record indices of outlying samples
    jumps: NDArray  # bool over the window: samples left out around jumps
    found: int  # samples the jump detector flagged in the stretch (before its limit)
    tails: tuple[float, float, float] = (0.0, 0.0, 0.0)  # see _tail_sums
    glitches: NDArray = field(default_factory=lambda: np.zeros(0, dtype=int))  # all outliers


def _tail_sums(b: _Blocks, rows: slice) -> tuple[float, float, float]:
    """``(Σ e²/L, Σ e⁴/L², n)`` of the shortest span off the jumps, outliers kept (§F5.5).

    ``L`` is each block's trimmed level (outliers left out, so that it does not follow
    the tails it scales): level changes between blocks are not tails.
    """
    count, s2, s4 = b.total_count[rows], b.total_sum[0, rows], b.total_fourth[rows]
    with np.errstate(invalid="ignore", divide="ignore"):
        level = b.block_sum[0, rows] / b.kept_count[rows]
    ok = (count > 0) & (level > 0) & np.isfinite(level)
    if not ok.any():
        return 0.0, 0.0, 0.0
    lv = level[ok]
    with np.errstate(over="ignore", invalid="ignore"):  # e⁴ of a huge record may be inf
        k2, k4 = float(np.sum(s2[ok] / lv)), float(np.sum(s4[ok] / lv / lv))
    return k2, k4, float(count[ok].sum())


@lru_cache(maxsize=64)
def _efficiencies(spans: tuple[int, ...], order: int) -> NDArray:
    return np.asarray([sequence_efficiency(residual_sequence(s, order)) for s in spans])


def auto_part(
    z: NDArray,
    spans: tuple[int, ...],
    order: int,
    trim: float,
    own: tuple[int, int] | None = None,
    step_limit: float | None = None,
    offset: int = 0,
    after: int = 0,
) -> AutoPart:
    """``auto``'s block sums for the samples ``own`` of the window ``z`` (§F5.2-§F5.5).

    Parameters
    ----------
    z : ndarray, shape (m,)
        The window: the stretch and its overlap (a record's edge where it has one).
    spans, order, trim : see :func:`auto_estimate` (``spans`` from :func:`auto_spans`).
    own : (int, int), optional
        The stretch within the window, on the block grid (default: all of it).
    step_limit : float, optional
        At most this many jump samples are believed (default: a fifth of the window).
    offset : int
        Record index of the window's first sample (for the outliers' positions).
    after : int
        Samples of the record after the window (its levels' second grid is the record's).

    Returns
    -------
    AutoPart
    """
    m = z.size
    lo, hi = own or (0, m)
    sq = np.empty((len(spans), m))
    peak = max(float(np.max(z)), -float(np.min(z)))  # every span's rounding bound's
    _every_span_squares(z, spans, order, sq, peak)
    b = _trimmed_blocks(z, sq, spans, trim, step_limit, after, offset == 0, order)
    rows = slice(lo // b.block, b.nb if hi == m else hi // b.block)
    choice = _choose_spans(b, spans, order)
    sums = _chosen_sums(b, choice)
    chosen_sum, kept_count = core_trimmed(sq, b, choice, sums, trim)
    # outliers stay in the total: a span needs only to stay clear of the jumps (with no
    # outliers, the flagged samples are the jumps: the same spans and sums)
    if b.clean_total is not b.clean_for:
        choice = _choose_spans(b, spans, order, b.clean_total)
        sums = _chosen_sums(b, choice, total=True)
    total_sum, total_count = sums
    # a glitch at the record's edge: at its sample, and counted as inside (_edges)
    ends = (offset == 0 and rows.start == 0, after == 0 and rows.stop == b.nb)
    edge = (spans[choice[0]], spans[choice[-1]])
    peaks, first, last = edge_glitches(z, b.outliers, edge, spans[0], order, ends)
    if first or last:
        total_sum = total_sum.copy()
        total_sum[0] += first
        total_sum[-1] += last
    choice, total_count = choice[rows], total_count[rows]
    out, near = peaks[(peaks >= lo) & (peaks < hi)], b.near_jumps
    return AutoPart(
        n=hi - lo,
        core_sum=float(chosen_sum[rows].sum()),
        core_count=float(kept_count[rows].sum()),
        total_sum=float(total_sum[rows].sum()),
        total_count=float(total_count.sum()),
        # ν = Σ_b n_b / Σρ²_b (Gaussian noise; estimate() widens it for the measured tails)
        dof=float(np.sum(total_count / _efficiencies(spans, order)[choice])),
        short=float(np.sum(total_count[choice < len(spans) - 1])),
        span_weight=float(np.sum(np.asarray(spans)[choice] * total_count)),
        outliers=out + offset,
        jumps=b.jumps,
        found=int(np.count_nonzero((b.found >= lo) & (b.found < hi))),
        tails=_tail_sums(b, rows),
        # every outlying sample, also in a jump's neighbourhood: the diagnostics' glitches
        glitches=np.union1d(out, near[(near >= lo) & (near < hi)]) + offset,
    )


def _auto_notes(parts: list[AutoPart], spans: tuple[int, ...], block: int) -> list[str]:
    n = sum(p.n for p in parts)
    n_kept = int(sum(p.total_count for p in parts))
    notes = []
    trimmed = n - n_kept
    if trimmed > 0.01 * n:
        notes.append(f"{trimmed} residuals ({trimmed / n:.1%}) left out around level jumps")
    short = float(sum(p.short for p in parts) / max(n_kept, 1))
    if len(spans) > 1 and short > 0.05:
        notes.append(
            f"{short:.0%} of the record needed a shorter span (a fast signal, or noise that "
            "is not white)"
        )
    if len(spans) > 1:
        mean_span = float(sum(p.span_weight for p in parts) / max(n_kept, 1))
        notes.append(f"span chosen per block of {block} samples: mean {mean_span:.1f}")
    outliers = [p.outliers for p in parts if p.outliers.size]
    if outliers:
        k = sum(o.size for o in outliers)
        notes.append(outlier_note(k, n, int(outliers[0][0])))
    return notes


def auto_reduce(
    parts: list[AutoPart], spans: tuple[int, ...], params: dict, notes: list[str]
) -> VarianceEstimate:
    """The record's estimate from its parts (§F5.5): sums of the parts' block sums.

    ``params``: the config form (``span`` None when chosen per block; ``order``, ``trim``).
    """
    n = sum(p.n for p in parts)
    trim = float(params["trim"])
    n_kept = int(sum(p.core_count for p in parts))
    n_total = int(sum(p.total_count for p in parts))
    tau = _truncated_second_moment(min(trim, AUTO_CORE_TRIM)) if np.isfinite(trim) else 1.0
    # core = sum e² / (n_kept τ(κ_c)) over the samples off outliers and jumps, each below κ_c
    core = float(sum(p.core_sum for p in parts) / (n_kept * tau))
    # var = sum e² / n over the samples off the jumps: outliers and tails are noise
    var = float(sum(p.total_sum for p in parts) / n_total)
    dof = float(sum(p.dof for p in parts))
    n_out = sum(p.outliers.size for p in parts)
    notes = list(notes) + _auto_notes(parts, spans, auto_block(n))
    jumps = parts[0].jumps if len(parts) == 1 else None
    return VarianceEstimate(
        "auto", var, chi2_interval(var, dof), n_total, n, dof, dict(params), notes,
        core_variance=core, outlier_fraction=n_out / n, jumps=jumps,
        kurtosis=_own_kurtosis(parts, spans[0], int(params["order"])),
        outliers=np.concatenate([p.glitches for p in parts]),
    )  # fmt: skip


def _own_kurtosis(parts: list[AutoPart], span: int, order: int) -> float | None:
    """The noise kurtosis read off ``auto``'s own shortest-span residual (§F5.5; None: no sums).

    The residual that made the estimate does not leak a fast signal the way the
    diagnostics' fixed span does, and a glitch counts in it as in ``.variance``.
    """
    k2, k4, kn = (sum(p.tails[i] for p in parts) for i in range(3))
    if not kn > 0:
        return None
    return kurtosis_from_moments(k2 / kn, k4 / kn, residual_sequence(span, order))


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
    (§F5.5). The record is one :func:`auto_part`; :mod:`~noisevar.estimators.auto.chunked`
    sums many.
    """
    order, trim = int(order), float(trim)
    span = None if span is None else int(span)
    spans = auto_spans(span, order, trim, z.size)
    notes = list(notes or [])
    if span is None and spans[0] < AUTO_SPANS[0]:
        notes.append(SHORT_SPAN_NOTE.format(span=spans[0], order=order))
    part = auto_part(z, spans, order, trim)
    # params are the config form: the requested span, None when it is chosen per block
    params = {"span": span, "order": order, "trim": trim}
    return auto_reduce([part], spans, params, notes)


def auto_method(z: NDArray, notes: list[str], **p: object) -> VarianceEstimate:
    """:func:`auto_estimate` as a :class:`~noisevar.estimators.spec.MethodSpec`'s ``func``."""
    return auto_estimate(z, notes=notes, **p)


def finish_quantised(
    result: VarianceEstimate,
    diag: NoiseDiagnostics,
    record: Callable[[int, int], NDArray] | None,
) -> VarianceEstimate:
    """``auto``'s finishing step: on a quantised record, the rounding error its residual misses.

    Parameters
    ----------
    result : VarianceEstimate
        ``auto``'s estimate of the record.
    diag : NoiseDiagnostics
        The record's diagnostics (``diag.lsb``: its grid step, None when not on a grid).
    record : callable or None
        ``record(a, b)``: samples ``a .. b`` of a record in one uniform segment.

    Returns
    -------
    VarianceEstimate
        Corrected at low noise on a grid (docs/algorithms.md §E3), else ``result``.
    """
    if diag.lsb is None:
        return result
    # here: the correction needs scipy, which an estimate of an ordinary record never loads
    from noisevar.estimators.auto import _quantised

    p = result.params
    spans = auto_spans(p.get("span"), p["order"], p["trim"], result.n_total)
    return _quantised.correct(result, diag.lsb, record, spans[-1], p["order"], spans[0])


def jump_mask(z: NDArray, order: int = AUTO_ORDER, trim: float = AUTO_TRIM) -> NDArray | None:
    """Samples that ``auto`` leaves out around persistent level jumps (None when none).

    Parameters
    ----------
    z : ndarray, shape (n,)
        Finite samples (at least 10).
    order, trim : see :func:`auto_estimate`.

    Returns
    -------
    ndarray of bool or None
        Jump samples widened by the mask half-width (docs/algorithms.md §F5.3, §F5.4).
    """
    spans = auto_spans(None, order, trim, z.size)
    block = auto_block(z.size)
    half = max(s for s in spans if s <= max(AUTO_MASK_SPAN, spans[0])) // 2
    sq0 = detection_squares(z, _residual_squares(z, spans[0], order), spans[0], (True, True))
    _, jumps, _ = _flag(z, sq0, trim, block, half, None, detect=(spans[0], order))
    return None if jumps is None else dilate(jumps, half)
